#!/bin/sh
# test_aov.sh: `vkrt render --aov` end to end: a bad list is refused before any GPU work; the AOVs
# of a PNG come as files beside it and leave the beauty as it is without them (to the order of
# the float atomic adds: at most one 8-bit step); an EXR's AOVs are layers that OpenEXR's own
# exrheader lists under the names Blender and Nuke read (skipped, 77, without exrheader: Debian's
# openexr package). Run by meson test with VKRT_BINARY, VKRT_SOURCE_DIR and VKRT_PNG_COMPARE.
set -u
src=${VKRT_SOURCE_DIR:?}
. "$src/tests/lib.sh"
vkrt=${VKRT_BINARY:?} compare=${VKRT_PNG_COMPARE:?} tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

"$vkrt" render "$src/scenes/cornell/scene.cfg" --aov albedo,colour -o "$tmp/x.png" \
    >"$tmp/bad.txt" 2>&1
check "--aov colour: refused" test $? -ne 0
check "--aov colour: says which names it takes" \
    grep -q "'colour' is not one of albedo, normal, depth, position" "$tmp/bad.txt"

lamp="$src/scenes/cornell-spheres/lamp.cfg"
size="--width 32 --height 32 --spp 1 --quiet"
"$vkrt" render "$lamp" $size -o "$tmp/plain.png"
check "path render without --aov: exits 0" test $? -eq 0
"$vkrt" render "$lamp" $size -o "$tmp/shot.png" --aov albedo,normal,depth,position
check "path render with --aov: exits 0" test $? -eq 0
check "the AOVs beside the PNG" test "$(cd "$tmp" && ls shot.*)" = \
    "$(printf 'shot.albedo.png\nshot.depth.exr\nshot.normal.png\nshot.png\nshot.position.exr')"
check "the beauty as without --aov" "$compare" "$tmp/plain.png" "$tmp/shot.png" 1

"$vkrt" render "$src/scenes/cornell/scene.cfg" $size -o "$tmp/layers.exr" \
    --aov albedo,normal,depth,position
check "Whitted render to EXR with --aov: exits 0" test $? -eq 0
if ! command -v exrheader >/dev/null; then
    summary
    echo "exrheader missing (Debian's openexr package): the layer check skipped"
    exit 77
fi
exrheader "$tmp/layers.exr" >"$tmp/header.txt"
channels=$(awk '/^channels/ { on = 1; next } on && /^    / { sub(/,.*/, ""); sub(/^ +/, ""); print; next } { on = 0 }' "$tmp/header.txt" | tr '\n' ' ')
check "exrheader lists the beauty and the AOV layers ($channels)" test "$channels" = \
    "B G R albedo.B albedo.G albedo.R depth.Z normal.X normal.Y normal.Z position.X position.Y position.Z "
summary
