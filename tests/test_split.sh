#!/bin/sh
# test_split.sh: scenes whose arrays are split over several buffers (issue 20, src/gpu/array.h)
# render byte for byte what they render whole. VKRT_TEST_MAX_BUFFER_BYTES makes arrays split at a few
# kilobytes, as 100 million triangles split at 4 GiB on an H200; each split render is compared
# with the whole one (the kernels read the same values through device addresses instead of
# bindings, and compute the same). And a scene too big for the device, in chunks or in memory, is
# refused with the sizes. Run by meson test with VKRT_BINARY, VKRT_SOURCE_DIR and VKRT_SCENES_DIR.
set -u
vkrt=${VKRT_BINARY:?}
src=${VKRT_SOURCE_DIR:?}
scenes=${VKRT_SCENES_DIR:-}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
passed=0

check() { # check NAME CONDITION...: counts a pass or prints the failure
    name=$1; shift
    if "$@"; then passed=$((passed + 1)); else echo "FAIL: $name"; failures=$((failures + 1)); fi
}

# same NAME LIMIT SPLIT CFG ARGS...: renders CFG whole and with arrays split past LIMIT bytes;
# the split render must say SPLIT (the arrays and their buffer counts) and match byte for byte.
same() {
    what=$1 limit=$2 split=$3 cfg=$4; shift 4
    "$vkrt" render "$cfg" --quiet -o "$tmp/whole.png" "$@"
    check "$what: whole render exits 0" test $? -eq 0
    VKRT_TEST_MAX_BUFFER_BYTES=$limit "$vkrt" render "$cfg" --verbose -o "$tmp/split.png" "$@" \
        2>"$tmp/err"
    check "$what: split render exits 0" test $? -eq 0
    check "$what: split as asked ($split)" \
        grep -q "^vkrt: arrays split past $limit bytes (VKRT_TEST_MAX_BUFFER_BYTES): $split\$" "$tmp/err"
    check "$what: the same image" cmp -s "$tmp/whole.png" "$tmp/split.png"
    rm -f "$tmp/whole.png" "$tmp/split.png"
}

# The BVH's nodes, the triangles, their normals and materials (Whitted, the materials' own rays);
# the BVH asked for, since lavapipe's auto takes the kd-tree.
demo="$src/scenes/materials-demo/scene.cfg"
same "materials-demo, BVH" 4096 \
    "triangles in 31 buffers, normals in 31 buffers, triangle materials in 2 buffers, nodes in 8 buffers" \
    "$demo" --width 40 --height 40 --spp 1 --accel bvh
# The kd-tree's nodes and references; the grid's cells and references.
spheres="$src/scenes/cornell-spheres/scene.cfg"
same "cornell-spheres, kd-tree" 16384 \
    "triangles in 18 buffers, normals in 18 buffers, triangle materials in 2 buffers, nodes in 18 buffers, references in 3 buffers" \
    "$spheres" --width 32 --height 32 --spp 1 --accel kdtree
same "cornell-spheres, grid" 16384 \
    "triangles in 18 buffers, normals in 18 buffers, triangle materials in 2 buffers, nodes in 3 buffers, references in 3 buffers" \
    "$spheres" --width 32 --height 32 --spp 1 --accel grid
# Texture coordinates and texels (with their mipmaps, a third more): Sponza's (a shared scene;
# skipped where absent), path traced.
if [ -z "${VKRT_SKIP_SHARED_SCENES:-}" ] && [ -n "$scenes" ] &&
    [ -f "$scenes/dabrovic-sponza/sponza.obj" ]; then
    same "Sponza, path" 1500000 \
        "triangles in 5 buffers, texture coordinates in 3 buffers, texels in 26 buffers" \
        "$src/scenes/shared/sponza-path.cfg" --width 32 --height 18 --spp 1 --accel bvh
fi

# Too big: more chunks than an array may have; split arrays without device addresses; and the
# device's memory, split or not.
VKRT_TEST_MAX_BUFFER_BYTES=200 "$vkrt" render "$demo" --width 16 --height 16 --accel bvh -o "$tmp/big.png" \
    2>"$tmp/err"
check "an array past 64 buffers exits 1" test $? -eq 1
check "and says what does not fit, with the sizes" grep -q "^vkrt: the scene does not fit .*: its BVH nodes take 29056 bytes (454 x 64 bytes), more than 64 buffers of 128 bytes hold (VKRT_TEST_MAX_BUFFER_BYTES: 200 bytes)$" "$tmp/err"
check "and writes no image" test ! -e "$tmp/big.png"
VKRT_TEST_NO_DEVICE_ADDRESSES=1 VKRT_TEST_MAX_BUFFER_BYTES=4096 "$vkrt" render "$demo" --width 16 --height 16 \
    --accel bvh -o "$tmp/big.png" 2>"$tmp/err"
check "a split array without device addresses exits 1" test $? -eq 1
check "and says why, with the sizes" grep -q "^vkrt: the scene does not fit .*: its BVH nodes take 29056 bytes (454 x 64 bytes), more than one buffer holds (VKRT_TEST_MAX_BUFFER_BYTES: 4096 bytes), and the device has no buffer device addresses to reach several$" "$tmp/err"
VKRT_TEST_DEVICE_MEMORY_LIMIT=60000 VKRT_TEST_MAX_BUFFER_BYTES=4096 "$vkrt" render "$demo" --width 16 --height 16 \
    --accel bvh -o "$tmp/big.png" 2>"$tmp/err"
check "split arrays beyond the device's memory exit 1" test $? -eq 1
check "and say which part does not fit, with the sizes" grep -q "^vkrt: triangles (part [0-9]* of 31) ([0-9]* bytes): the scene does not fit .*: .* MiB more device memory with .* MiB already in use makes .* MiB, and the device has 0.1 MiB (VKRT_TEST_DEVICE_MEMORY_LIMIT)$" "$tmp/err"

echo "$passed checks passed, $failures failed"
[ "$failures" -eq 0 ]
