#!/bin/sh
# test_order.sh: hits grouped by shader (glsl/order.comp, VKRT_TEST_MATERIAL_ORDER) change which
# invocation shades which ray, never what a ray computes: renders with the grouping forced on and
# off must agree up to the order of the float atomic adds into a pixel (at most one 8-bit step),
# and the profile must show the grouping ran (its column above zero) and did not run when off.
# Scenes of several shaders, Whitted (user shaders beside built-ins) and path traced (glass,
# mirror and diffuse). Run by meson test with VKRT_BINARY, VKRT_SOURCE_DIR and VKRT_PNG_COMPARE.
set -u
vkrt=${VKRT_BINARY:?}
src=${VKRT_SOURCE_DIR:?}
compare=${VKRT_PNG_COMPARE:?}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
. "$src/tests/lib.sh"

# order_total FILE: the profile's total of the order column (the third after "total").
order_total() {
    awk '$1 == "total" { print $4 }' "$1"
}

# same WHAT CFG ARGS...: CFG rendered with the grouping off and on.
same() {
    what=$1 cfg=$2
    shift 2
    for on in 0 1; do
        VKRT_TEST_MATERIAL_ORDER=$on "$vkrt" render "$cfg" -o "$tmp/$on.png" --profile \
            --profile-repeat 1 "$@" >"$tmp/$on.txt" 2>&1
        check "$what, grouping $on: exits 0" test $? -eq 0
    done
    check "$what: no grouping when off" test "$(order_total "$tmp/0.txt")" = 0.000
    check "$what: the grouping ran when on" awk -v t="$(order_total "$tmp/1.txt")" 'BEGIN { exit !(t > 0) }'
    check "$what: the same picture, to an 8-bit step" "$compare" "$tmp/0.png" "$tmp/1.png" 1
}

same "materials-demo (Whitted)" "$src/scenes/materials-demo/scene.cfg" --width 48 --height 48 --spp 2
# One sample per pass, so the profile's timestamps are counted exactly (a miscount hung the H200).
same "cornell-spheres lamp (path)" "$src/scenes/cornell-spheres/lamp.cfg" --width 32 --height 32 --spp 1
summary
