# lib.sh: what the shell tests share, sourced after they set src (VKRT_SOURCE_DIR):
#   check NAME CONDITION...   runs CONDITION; counts a pass, or prints "FAIL: NAME"
#   summary                   prints the counts; its status is 0 when nothing failed
#   png_rms A B               prints the rms difference of two PNGs in 8-bit steps
#                             (png_compare, named by $compare)
#   is_below A B              status 0 when the number A is below the number B
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

png_rms() {
    "$compare" "$1" "$2" 255 | sed 's/.*rms //'
}

is_below() {
    awk -v a="$1" -v b="$2" 'BEGIN { exit !(a < b) }'
}
