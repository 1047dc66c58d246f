# lib.sh: what the shell tests share, sourced after they set src (VKRT_SOURCE_DIR):
#   check NAME CONDITION...   runs CONDITION; counts a pass, or prints "FAIL: NAME"
#   summary                   prints the counts; its status is 0 when nothing failed
failures=0
passed=0

check() {
    name=$1
    shift
    if "$@"; then passed=$((passed + 1)); else echo "FAIL: $name"; failures=$((failures + 1)); fi
}

summary() {
    echo "$passed passed, $failures failed"
    [ $failures -eq 0 ]
}
