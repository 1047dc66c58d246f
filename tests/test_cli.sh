#!/bin/sh
# test_cli.sh: the vkrt program as a user meets it: help, version, a render to PNG and EXR, and
# bad input (a broken scene.cfg, a missing OBJ, a broken OBJ) giving one line on stderr, a
# non-zero exit and no output file. Run by meson test with VKRT_BINARY and VKRT_SOURCE_DIR set.
set -u
vkrt=${VKRT_BINARY:?}
src=${VKRT_SOURCE_DIR:?}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
. "$src/tests/lib.sh"

"$vkrt" --help >"$tmp/help" 2>&1
check "--help exits 0" test $? -eq 0
check "--help mentions render" grep -q "vkrt render" "$tmp/help"
"$vkrt" --version >"$tmp/version"
check "--version prints the version" grep -q "^vkrt [0-9]" "$tmp/version"
"$vkrt" --list-devices >"$tmp/devices"
check "--list-devices lists device 0" grep -q "^0: " "$tmp/devices"
"$vkrt" frobnicate 2>"$tmp/err"
check "unknown command exits non-zero" test $? -ne 0

# A real render, both formats, through the default scene with overrides.
"$vkrt" render "$src/scenes/cornell/scene.cfg" --width 48 --height 32 --spp 2 -o "$tmp/c.png" 2>"$tmp/err"
check "render to PNG exits 0" test $? -eq 0
check "PNG written" test -s "$tmp/c.png"
check "PNG has the PNG signature" sh -c "head -c 8 '$tmp/c.png' | od -An -c | grep -q 'P   N   G'"
check "summary names rays per second" grep -q "Mrays/s" "$tmp/err"
# Issue 20: --verbose reports memory and the start-up's stages; a scene too big for the device
# (made small here by VKRT_TEST_DEVICE_MEMORY_LIMIT) is refused with the sizes, not a driver error.
"$vkrt" render "$src/scenes/cornell/scene.cfg" --width 48 --height 32 --spp 2 -o "$tmp/v.png" --verbose 2>"$tmp/err"
check "--verbose prints device memory by kind against the device's" \
    grep -q "^vkrt: device memory: triangles .* MiB, nodes .* rays .* MiB of the device's .* MiB$" "$tmp/err"
check "--verbose prints host memory" grep -q "^vkrt: host memory: mesh .* peak resident" "$tmp/err"
check "--verbose prints the start-up's stages" grep -q "^vkrt: start-up: scene .* (scene file .*), Vulkan .* first frame" "$tmp/err"
# The kernels compile while the structure is built, for the layout predicted before it: for the
# Cornell box (brute force, nothing split) the prediction holds, so they are not compiled again.
check "--verbose prints the renderer's steps, the kernels compiled alongside them" \
    grep -q "^vkrt: start-up: .* renderer .* (structure .* triangles' upload .*, waiting for the kernels compiled alongside [0-9]*)" "$tmp/err"
VKRT_TEST_DEVICE_MEMORY_LIMIT=300000 "$vkrt" render "$src/scenes/cornell/scene.cfg" --width 48 --height 32 --spp 2 \
    -o "$tmp/small.png" 2>"$tmp/err"
check "a scene beyond the device's memory exits 1" test $? -eq 1
check "and says it does not fit, with the sizes" \
    grep -q "does not fit .*MiB more device memory with .* MiB already in use makes .* MiB, and the device has 0.3 MiB (VKRT_TEST_DEVICE_MEMORY_LIMIT)" "$tmp/err"
check "and writes no image" test ! -e "$tmp/small.png"
"$vkrt" render "$src/scenes/cornell-spheres/scene.cfg" --width 16 --height 16 --profile -o "$tmp/p.png" 2>"$tmp/err"
check "--profile exits 0" test $? -eq 0
check "--profile prints the share of tracing" grep -q "the frame costs .*x its tracing" "$tmp/err"
check "--profile has a row per depth" grep -q "^ *8 " "$tmp/err"
"$vkrt" render "$src/scenes/cornell-spheres/scene.cfg" --width 16 --height 16 --profile-repeat 3 -o "$tmp/p.png" 2>"$tmp/err"
check "--profile-repeat exits 0" test $? -eq 0
check "--profile-repeat takes the median of its frames after a warm-up" grep -q "median of 3 frames back to back after [1-9][0-9]* warm-up frame" "$tmp/err"
"$vkrt" render "$src/scenes/cornell/scene.cfg" --width 48 --height 32 --quiet -o "$tmp/c.exr" 2>"$tmp/err"
check "render to EXR exits 0" test $? -eq 0
check "EXR written" test -s "$tmp/c.exr"
check "--quiet prints nothing" test ! -s "$tmp/err"
check "no temporary files left" sh -c "! ls '$tmp' | grep -q tmp"

# A flythrough: two cameras need a frame pattern, and get two numbered files.
cat >"$tmp/fly.cfg" <<CFG
geometry $src/scenes/cornell/cornell.obj
resolution 16 16
light point 278 500 279 250000 250000 250000
camera eye 278 273 -800 look 278 273 0 up 0 1 0 fov 40
camera eye 300 273 -800 look 278 273 0 up 0 1 0 fov 40
camera eye 320 273 -800 look 278 273 0 up 0 1 0 fov 40
output fly%02d.png
CFG
"$vkrt" render "$tmp/fly.cfg" --quiet
check "flythrough exits 0" test $? -eq 0
check "frame 0 written" test -s "$tmp/fly00.png"
check "frame 1 written" test -s "$tmp/fly01.png"
"$vkrt" render "$tmp/fly.cfg" -o "$tmp/single.png" 2>"$tmp/err"
check "two cameras without a frame number is refused" test $? -ne 0
check "and says why" grep -q "frame number" "$tmp/err"

# --camera N|NAME: one camera of a flythrough, by its number or its name, as a single frame (a
# plain file name will do); Whitted at one sample has no random numbers, so it is the flythrough's
# frame to the byte. The last camera is orthographic (`ortho W`).
cat >"$tmp/named.cfg" <<CFG
geometry $src/scenes/cornell/cornell.obj
resolution 16 16
light point 278 500 279 250000 250000 250000
camera eye 278 273 -800 look 278 273 0 up 0 1 0 fov 40
camera eye 300 273 -800 look 278 273 0 up 0 1 0 fov 40 name side
camera eye 278 273 -800 look 278 273 0 up 0 1 0 ortho 700 name front
output named%d.png
CFG
"$vkrt" render "$tmp/named.cfg" --quiet
"$vkrt" render "$tmp/named.cfg" --camera 1 --quiet -o "$tmp/cam1.png"
check "--camera 1 renders one frame into a plain file name" test $? -eq 0
check "and it is the flythrough's frame 1" cmp -s "$tmp/cam1.png" "$tmp/named1.png"
"$vkrt" render "$tmp/named.cfg" --camera front --quiet -o "$tmp/front.png"
check "--camera NAME renders the camera of that name" cmp -s "$tmp/front.png" "$tmp/named2.png"
check "the orthographic camera sees another picture than the perspective one at its place" \
    sh -c "! cmp -s '$tmp/named0.png' '$tmp/named2.png'"
"$vkrt" render "$tmp/named.cfg" --camera 3 -o "$tmp/nocam.png" 2>"$tmp/err"
check "--camera 3 of 3 cameras exits 1" test $? -eq 1
check "and lists the cameras" grep -q "^vkrt: --camera 3: no camera 3: the scene has 3 cameras, numbered from 0: 0 (no name), 1 'side', 2 'front'$" "$tmp/err"
"$vkrt" render "$tmp/named.cfg" --camera top -o "$tmp/nocam.png" 2>"$tmp/err"
check "--camera top (no such name) exits 1" test $? -eq 1
check "and says so with the names" grep -q "^vkrt: --camera top: no camera named 'top': the scene has 3 cameras" "$tmp/err"
"$vkrt" render "$tmp/named.cfg" --camera -o "$tmp/nocam.png" 2>"$tmp/err"
check "--camera without a camera is refused" test $? -eq 2
check "and says what it needs" grep -q -- "--camera needs a camera's number (from 0) or name, not '-o'" "$tmp/err"
check "and nothing was written" test ! -e "$tmp/nocam.png"
# --fps: the rate a file's camera animation is sampled at (a scene.cfg has none: the same frame).
"$vkrt" render "$tmp/named.cfg" --camera 1 --fps 30 --quiet -o "$tmp/fps.png"
check "--fps 30 exits 0" cmp -s "$tmp/fps.png" "$tmp/named1.png"
for bad in 0 -24 x inf; do
    "$vkrt" render "$tmp/named.cfg" --fps $bad -o "$tmp/fpsbad%d.png" 2>"$tmp/err"
    check "--fps $bad is refused" test $? -eq 2
    check "and the message names --fps" grep -q -- "--fps: '$bad' is not a" "$tmp/err"
done
"$vkrt" view "$tmp/named.cfg" --fps 0 2>"$tmp/err"
check "view --fps 0 is refused" grep -q -- "--fps: '0' is not a positive number" "$tmp/err"
"$vkrt" render "$tmp/named.cfg" -o '' 2>"$tmp/err"
check "-o '' is refused" test $? -ne 0
check "and says the name is empty" grep -q "^vkrt: the output file name is empty" "$tmp/err"
"$vkrt" render "$tmp/named.cfg" --accel octree -o "$tmp/x.png" 2>"$tmp/err"
check "--accel octree is refused, listing kdtree" grep -q -- "--accel: 'octree' is not one of auto, brute, grid, bvh or kdtree" "$tmp/err"
"$vkrt" bench "$tmp/named.cfg" --camera 0 >/dev/null 2>"$tmp/err"
check "bench --camera is refused" grep -q "vkrt bench does not take --camera (an option of vkrt render and view)" "$tmp/err"

# --environment R G B over the scene's `environment` line: a camera that sees no geometry shows
# the radiance given in every pixel, scaled by 2^exposure and through the sRGB curve (closed form).
cat >"$tmp/away.cfg" <<CFG
geometry $src/scenes/cornell/cornell.obj
resolution 8 6
environment 1 0 0
light point 278 500 279 250000 250000 250000
camera eye 278 273 -800 look 278 273 -1600 up 0 1 0 fov 40
CFG
srgb8() { # srgb8 LINEAR...: the 8-bit sRGB codes (IEC 61966-2-1, rounded to nearest)
    awk 'BEGIN { for (i = 1; i < ARGC; ++i) { v = ARGV[i]; s = v <= 0.0031308 ? 12.92 * v : 1.055 * exp(log(v) / 2.4) - 0.055
                 printf("%s%d", (i > 1 ? " " : ""), int(s * 255 + 0.5)) } print "" }' "$@"
}
pixel=${VKRT_PNG_PIXEL:?}
"$vkrt" render "$tmp/away.cfg" --environment 0.025 0.15 0.35 --exposure 1 --quiet -o "$tmp/env.png"
check "--environment R G B exits 0" test $? -eq 0
check "a pixel that sees nothing is the radiance given x 2^exposure, sRGB-encoded ($(srgb8 0.05 0.3 0.7))" \
    test "$("$pixel" "$tmp/env.png" 3 2)" = "$(srgb8 0.05 0.3 0.7)"
check "and so is the opposite corner" test "$("$pixel" "$tmp/env.png" 7 5)" = "$(srgb8 0.05 0.3 0.7)"
"$vkrt" render "$tmp/away.cfg" --quiet -o "$tmp/noenv.png"
check "without it, the scene's environment line" test "$("$pixel" "$tmp/noenv.png" 3 2)" = "255 0 0"
# The tone curve: scene.cfg's `tonemap agx` after exposure. 97 154 192 is Wrensch's minimal AgX
# of (0.05, 0.3, 0.7) in double precision, sRGB-encoded (tests/test_tonemap.c holds the curve to
# that code; test_view.sh runs --tonemap through render and the window).
{ cat "$tmp/away.cfg"; echo "tonemap agx"; } >"$tmp/agx.cfg"
"$vkrt" render "$tmp/agx.cfg" --environment 0.025 0.15 0.35 --exposure 1 --quiet -o "$tmp/agx.png"
check "scene.cfg tonemap agx: the pixel is AgX's (97 154 192)" \
    test "$("$pixel" "$tmp/agx.png" 3 2)" = "97 154 192"
"$vkrt" render "$tmp/away.cfg" --tonemap filmic -o "$tmp/filmic.png" 2>"$tmp/err"
check "--tonemap filmic is refused" test $? -eq 2
check "and the message lists the curves" grep -q -- "--tonemap: 'filmic' is not one of none, aces, agx" "$tmp/err"
for bad in "1 2" "1 -2 3" "1 x 3"; do
    # shellcheck disable=SC2086
    "$vkrt" render "$tmp/away.cfg" --environment $bad -o "$tmp/envbad.png" 2>"$tmp/err"
    check "--environment $bad is refused" test $? -eq 2
    check "and the message names --environment" grep -q -- "^vkrt: --environment" "$tmp/err"
done
# --environment-map FILE, relative to the working folder: a 2 x 1 Radiance map of one colour,
# (40, 100, 205) / 256 (RGBE with exponent 128), replaces the scene's environment (path traced:
# a map lights the scene).
printf '#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 2\n\050\144\315\200\050\144\315\200' >"$tmp/plain.hdr"
(cd "$tmp" && "$vkrt" render away.cfg --environment-map plain.hdr --quiet -o envmap.png)
check "--environment-map FILE exits 0" test $? -eq 0
check "a pixel that sees nothing is the map's radiance, sRGB-encoded ($(srgb8 0.15625 0.390625 0.80078125))" \
    test "$("$pixel" "$tmp/envmap.png" 3 2)" = "$(srgb8 0.15625 0.390625 0.80078125)"
"$vkrt" render "$tmp/away.cfg" --environment-map "$tmp/nowhere.hdr" -o "$tmp/envbad.png" 2>"$tmp/err"
check "a missing --environment-map exits 1" test $? -eq 1
check "and names the option and the file" grep -q "^vkrt: --environment-map $tmp/nowhere.hdr: cannot open: No such file or directory$" "$tmp/err"
"$vkrt" render "$tmp/away.cfg" --environment 1 1 1 --environment-map "$tmp/plain.hdr" -o "$tmp/envbad.png" 2>"$tmp/err"
check "--environment with --environment-map is refused" test $? -eq 2
check "and nothing was written" test ! -e "$tmp/envbad.png"
"$vkrt" view "$tmp/away.cfg" --environment 1 1 2>"$tmp/err"
check "view --environment with two numbers is refused" grep -q -- "--environment needs 3 numbers (R G B), got 2" "$tmp/err"

# --frames A:B[:STEP]: only those frames, numbered as the output pattern numbers them.
"$vkrt" render "$tmp/fly.cfg" --frames 1:2 -o "$tmp/fr%d.png" 2>"$tmp/err"
check "--frames 1:2 exits 0" test $? -eq 0
check "a flythrough prints its progress, a line a frame when not on a terminal" \
    sh -c "grep -q '^vkrt: 1 of 2 frames done (.*fr1.png), [0-9.]* frames/s, about [0-9]* s left$' '$tmp/err' && grep -q '^vkrt: 2 of 2 frames done (.*fr2.png), [0-9.]* frames/s$' '$tmp/err'"
check "--frames 1:2 writes frames 1 and 2" sh -c "test -s '$tmp/fr1.png' && test -s '$tmp/fr2.png'"
check "--frames 1:2 leaves frame 0 out" test ! -e "$tmp/fr0.png"
"$vkrt" render "$tmp/fly.cfg" --quiet --frames 0:2:2 -o "$tmp/fs%d.png"
check "--frames 0:2:2 writes frames 0 and 2 only" \
    sh -c "test -s '$tmp/fs0.png' && test ! -e '$tmp/fs1.png' && test -s '$tmp/fs2.png'"
rm "$tmp/fs0.png"
"$vkrt" render "$tmp/fly.cfg" --frames 0:2:2 --resume -o "$tmp/fs%d.png" 2>"$tmp/err"
check "--frames with --resume renders only the range's missing frame" \
    sh -c "grep -q 'resumed: 1 of 2 frames were already complete' '$tmp/err' && test -s '$tmp/fs0.png' && test ! -e '$tmp/fs1.png'"
"$vkrt" render "$tmp/fly.cfg" --frames 1:3 -o "$tmp/fx%d.png" 2>"$tmp/err"
check "--frames past the last camera is refused" test $? -eq 1
check "and says how many frames there are" grep -q "has 3 cameras (frames 0 to 2)" "$tmp/err"
for bad in 2:1 1 1:2:0 a:b 1:2:3:4; do
    "$vkrt" render "$tmp/fly.cfg" --frames "$bad" -o "$tmp/fx%d.png" 2>"$tmp/err"
    check "--frames $bad is refused" test $? -eq 2
done
check "and nothing was written" test ! -e "$tmp/fx0.png"

# --resume: frame 0 complete, frame 1 missing, frame 2 cut short, a stale temporary beside it.
"$vkrt" render "$tmp/fly.cfg" --quiet -o "$tmp/r%d.png"
cp "$tmp/r0.png" "$tmp/r0.saved"
rm "$tmp/r1.png"
head -c 300 "$tmp/r2.png" >"$tmp/cut" && mv "$tmp/cut" "$tmp/r2.png"
# Temporaries of a process that is gone, beside a cut frame and beside a complete one, and
# one of a live process (this shell) that must stay.
gone=$(sh -c 'echo $$')
: >"$tmp/r2.png.tmp-$gone"
: >"$tmp/r0.png.tmp-$(uname -n | tr -c 'A-Za-z0-9._\n' _)-$gone"
: >"$tmp/r0.png.tmp-$$"
"$vkrt" render "$tmp/fly.cfg" --resume -o "$tmp/r%d.png" 2>"$tmp/err"
check "resume exits 0" test $? -eq 0
check "resume skips exactly the complete frame" grep -q "resumed: 1 of 3 frames were already complete" "$tmp/err"
check "resume re-renders the cut frame" test "$(wc -c <"$tmp/r2.png")" -gt 300
check "resume renders the missing frame" test -s "$tmp/r1.png"
check "resume removes stale temporaries" test ! -e "$tmp/r2.png.tmp-$gone"
check "also beside a complete frame" sh -c "! ls '$tmp' | grep -q 'r0.png.tmp-.*-$gone'"
check "but not a live process's" test -e "$tmp/r0.png.tmp-$$"
rm "$tmp/r0.png.tmp-$$"
check "resume leaves the complete frame alone" cmp -s "$tmp/r0.png" "$tmp/r0.saved"

# Frames are written by threads while the next ones render (src/output/write_pool.h): the same
# bytes as written one at a time on the render thread (VKRT_WRITE_THREADS=0).
VKRT_WRITE_THREADS=0 "$vkrt" render "$tmp/fly.cfg" --quiet -o "$tmp/w0-%d.png"
VKRT_WRITE_THREADS=3 "$vkrt" render "$tmp/fly.cfg" --quiet -o "$tmp/w3-%d.png"
check "frames written by 3 threads have the bytes of frames written one at a time" \
    sh -c "cmp '$tmp/w0-0.png' '$tmp/w3-0.png' && cmp '$tmp/w0-1.png' '$tmp/w3-1.png' && cmp '$tmp/w0-2.png' '$tmp/w3-2.png'"
check "and the frames differ from each other (the cameras move)" sh -c "! cmp -s '$tmp/w3-0.png' '$tmp/w3-1.png'"
VKRT_WRITE_THREADS=many "$vkrt" render "$tmp/fly.cfg" --quiet -o "$tmp/wx%d.png" 2>"$tmp/err"
check "a VKRT_WRITE_THREADS that is not a number is refused" test $? -eq 1
check "and says what it takes" grep -q "VKRT_WRITE_THREADS=many: give the number of writer threads, 0 to 16" "$tmp/err"
# A write that fails mid-run (frame 1's folder is a file): the file named, exit 1, no temporary.
mkdir "$tmp/d0" "$tmp/d2" && : >"$tmp/d1"
VKRT_WRITE_THREADS=2 "$vkrt" render "$tmp/fly.cfg" -o "$tmp/d%d/f.png" 2>"$tmp/err"
check "a frame that cannot be written stops the run with exit 1" test $? -eq 1
check "and names its file" grep -q "^vkrt: $tmp/d1/f.png: cannot write: Not a directory$" "$tmp/err"
check "the frame before it was written" test -s "$tmp/d0/f.png"
check "and no temporary is left" sh -c "! find '$tmp' -name '*.tmp-*' | grep -q ."

# Ctrl-C in the middle of a flythrough: exit 130 after a whole frame, then --resume finishes.
{
    echo "geometry $src/scenes/cornell/cornell.obj"
    echo "resolution 160 160"
    echo "samples 4"
    echo "light point 278 500 279 250000 250000 250000"
    i=0
    while [ $i -lt 120 ]; do
        echo "camera eye $((200 + i)) 273 -800 look 278 273 0 up 0 1 0 fov 40"
        i=$((i + 1))
    done
    echo "output long%02d.png"
} >"$tmp/long.cfg"
"$vkrt" render "$tmp/long.cfg" --quiet 2>"$tmp/err" &
pid=$!
waited=0
while [ ! -e "$tmp/long01.png" ] && [ $waited -lt 600 ]; do sleep 0.05; waited=$((waited + 1)); done
kill -INT $pid
wait $pid
status=$?
check "interrupted render exits 130" test $status -eq 130
check "and says how to continue" grep -q "resume" "$tmp/err"
done_frames=$(ls "$tmp" | grep -c '^long.*png$')
check "some but not all frames were written" test "$done_frames" -gt 0 -a "$done_frames" -lt 120
"$vkrt" render "$tmp/long.cfg" --resume 2>"$tmp/err"
check "resume after the interrupt exits 0" test $? -eq 0
check "all 120 frames exist" test "$(ls "$tmp" | grep -c '^long.*png$')" -eq 120
check "no temporaries remain" sh -c "! ls '$tmp' | grep -q 'tmp-'"

# Bad input: one line on stderr, non-zero exit, nothing written.
expect_error() { # expect_error NAME CFG PATTERN
    rm -f "$tmp/out.png"
    "$vkrt" render "$2" -o "$tmp/out.png" 2>"$tmp/err"
    status=$?
    check "$1: non-zero exit" test $status -ne 0
    check "$1: one line on stderr" test "$(wc -l <"$tmp/err")" -eq 1
    check "$1: message matches '$3'" grep -q "$3" "$tmp/err"
    check "$1: no output file" test ! -e "$tmp/out.png"
    [ $status -ne 0 ] && grep -q "$3" "$tmp/err" || cat "$tmp/err"
}
printf 'geometry x.obj\nresolution 640 abc\ncamera eye 0 0 1 look 0 0 0 up 0 1 0 fov 40\n' >"$tmp/broken.cfg"
expect_error "broken scene.cfg" "$tmp/broken.cfg" "broken.cfg:2:"
printf 'geometry missing.obj\ncamera eye 0 0 1 look 0 0 0 up 0 1 0 fov 40\n' >"$tmp/missing.cfg"
expect_error "missing OBJ" "$tmp/missing.cfg" "missing.obj"
printf 'v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n' >"$tmp/broken.obj"
printf 'geometry broken.obj\ncamera eye 0 0 1 look 0 0 0 up 0 1 0 fov 40\n' >"$tmp/brokenobj.cfg"
expect_error "broken OBJ" "$tmp/brokenobj.cfg" "broken.obj:3:"
expect_error "missing scene.cfg" "$tmp/nonexistent.cfg" "nonexistent.cfg"
printf '\211PNG\r\n\032\n\0\0\0\rIHDR\0\0\0\1\0\0\0\1\10\6\0\0\0' >"$tmp/picture.png"
printf 'geometry picture.png\ncamera eye 0 0 1 look 0 0 0 up 0 1 0 fov 40\n' >"$tmp/picture.cfg"
expect_error "an image named as geometry" "$tmp/picture.cfg" "picture.png: not an OBJ text file: it starts like a PNG image"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 0 2\n' >"$tmp/broken.obj"
expect_error "a zero face index in our words" "$tmp/brokenobj.cfg" "broken.obj:4: face index 0 is not valid (OBJ indices start at 1)"

# Materials and textures: a quad whose material comes from a material file or its .mtl.
printf 'mtllib q.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl m\nf 1/1 2/2 3/3 4/4\n' >"$tmp/q.obj"
quad_cfg() { # quad_cfg FILE [materials FILE]: a scene of the quad
    { echo "geometry q.obj"; [ $# -gt 1 ] && echo "materials $2"; echo "resolution 32 32"
      echo "camera eye 0 0 3 look 0 0 0 up 0 1 0 fov 40"; } >"$1"
}
printf 'newmtl m\nKd 1 1 1\n\nmap_Kd nowhere.png\n' >"$tmp/q.mtl"
quad_cfg "$tmp/tex.cfg"
expect_error "missing texture names the .mtl line" "$tmp/tex.cfg" "q.mtl:4: texture '.*nowhere.png'"
printf 'not an image' >"$tmp/garbage.png"
printf 'newmtl m\nmap_Kd garbage.png\n' >"$tmp/q.mtl"
expect_error "a texture that is no image" "$tmp/tex.cfg" "garbage.png.*not an image"
head -c 2000 "$src/docs/images/materials-demo.png" >"$tmp/cut.png"
printf 'newmtl m\nmap_Kd cut.png\n' >"$tmp/q.mtl"
expect_error "a PNG cut short says so" "$tmp/tex.cfg" "cut.png': cannot decode the image: the PNG file is cut short: it has 2000 bytes"
# Loader warnings in our words, folded; --verbose lists each; "newmtl  m" (two blanks) is usemtl m.
{ printf 'newmtl  m\nKd 1 1 1\nd 1\nTr 0\n'; for n in a b c d; do printf 'newmtl %s\nd 1\nTr 0\n' $n; done; } >"$tmp/q.mtl"
"$vkrt" render "$tmp/tex.cfg" -o "$tmp/w.png" 2>"$tmp/err"
check "warnings: render exits 0" test $? -eq 0
check "warnings: repeated ones fold into one line" grep -q "^vkrt: .*q.mtl: warning: 5 materials define both d and Tr; d is used (m, a, b, ...)$" "$tmp/err"
check "warnings: a name written after two blanks is found" sh -c "! grep -q usemtl '$tmp/err'"
"$vkrt" render "$tmp/tex.cfg" --verbose -o "$tmp/w.png" 2>"$tmp/err"
check "warnings: --verbose lists each" test "$(grep -c "q.mtl:[0-9]*: warning: material '.*' defines both d and Tr" "$tmp/err")" -eq 5
printf 'newmtl m\nKd 1 1 1\n' >"$tmp/q.mtl"
printf 'm 0 bad.glsl\n' >"$tmp/bad.mat"
printf 'uint count_rays(Surface s) { return 0u; }\nvoid shade(Surface s)\n{\n    add_radiance(s.colour);\n}\n' >"$tmp/bad.glsl"
quad_cfg "$tmp/bad.cfg" bad.mat
expect_error "shader compile error names material file, shader and line" "$tmp/bad.cfg" "bad.mat:1: material 'm'.*bad.glsl:4:"
printf 'uint count_ray(Surface s) { return 0u; }\nvoid shade(Surface s) { }\n' >"$tmp/bad.glsl"
expect_error "a shader without count_rays is named with what it lacks" "$tmp/bad.cfg" "bad.mat:1: material 'm'.*bad.glsl does not define uint count_rays"
printf 'uint count_rays(Surface s) { return 65u; }\nvoid shade(Surface s) { }\n' >"$tmp/bad.glsl"
expect_error "count_rays above 64 is the material's error" "$tmp/bad.cfg" "material 'm'.*more than 64 rays"
printf 'm 0 missing.glsl\n' >"$tmp/nofile.mat"
quad_cfg "$tmp/nofile.cfg" nofile.mat
expect_error "missing shader file" "$tmp/nofile.cfg" "nofile.mat:1: material 'm'.*missing.glsl"
printf 'm two bad.glsl\n' >"$tmp/syntax.mat"
quad_cfg "$tmp/syntax.cfg" syntax.mat
expect_error "malformed material file line" "$tmp/syntax.cfg" "syntax.mat:1:"
printf 'm 0 @nonesuch\n' >"$tmp/builtin.mat"
quad_cfg "$tmp/builtin.cfg" builtin.mat
expect_error "unknown built-in shader" "$tmp/builtin.cfg" "@nonesuch"
# A shader that never ends: the watchdog stops the frame and names the scene's materials.
printf 'm 0 spin.glsl\n' >"$tmp/spin.mat"
printf 'uint count_rays(Surface s) { return 0u; }\nvoid shade(Surface s)\n{\n    vec3 x = s.position;\n    for (uint i = 0u; i < 4000000000u; ++i)\n        x = sin(x * 1.0001 + cos(x.yzx));\n    add_radiance(x);\n}\n' >"$tmp/spin.glsl"
quad_cfg "$tmp/spin.cfg" spin.mat
# Enough pixels that llvmpipe, which ends loops after 65535 iterations, still runs for minutes.
sed -i 's/^resolution .*/resolution 256 256/' "$tmp/spin.cfg"
export VKRT_TEST_GPU_TIMEOUT=1
expect_error "a shader looping forever meets the watchdog" "$tmp/spin.cfg" "did not finish within 1 s.*'m' (.*spin.mat:1)"
unset VKRT_TEST_GPU_TIMEOUT

# vkrt bench: the JSON, the traversal statistics, and the 4-wide layout finding what the pairs
# find (the same hits and blocked counts on the same rays).
bench_run() { # bench_run NAME ARGS...: a small bench of the Cornell box into $tmp/NAME.json
    name=$1; shift
    "$vkrt" bench "$src/scenes/cornell/scene.cfg" --accel bvh --width 40 --height 30 \
        --json "$tmp/$name.json" "$@" >"$tmp/$name.txt" 2>&1
}
counts() { grep -o '"\(hits\|blocked\|diffuse_hits\)": [0-9]*' "$1" | tr '\n' ' '; }
bench_run pairs --bvh-width 2
check "bench exits 0" test $? -eq 0
check "bench JSON has the rates" grep -q '"primary_mrays_per_s": [0-9]' "$tmp/pairs.json"
check "bench JSON has hits" grep -q '"hits": [1-9]' "$tmp/pairs.json"
bench_run quads --bvh-width 4
check "bench --bvh-width 4 exits 0" test $? -eq 0
check "the 4-wide layout hits what the pairs hit" test "$(counts "$tmp/quads.json")" = "$(counts "$tmp/pairs.json")"
# The traversal's two ways of reading triangles and nodes (storage buffers, texel buffers; the
# default is texel on CPU devices such as lavapipe): the same hits either way, for each structure.
bench_run storage --loads storage
check "bench --loads storage exits 0" test $? -eq 0
check "the JSON names storage loads" grep -q '"loads": "storage"' "$tmp/storage.json"
bench_run texel --loads texel
check "bench --loads texel exits 0" test $? -eq 0
check "the JSON names texel loads" grep -q '"loads": "texel"' "$tmp/texel.json"
check "storage and texel loads hit the same" test "$(counts "$tmp/storage.json")" = "$(counts "$tmp/texel.json")"
check "and what the default loads hit" test "$(counts "$tmp/texel.json")" = "$(counts "$tmp/pairs.json")"
# The BVH's two walks (one loop; nested loops, the default on CPU devices) on both layouts.
for width in 2 4; do
    for walk in one-loop nested; do
        bench_run walk-$width-$walk --bvh-width $width --walk $walk
        check "bench --bvh-width $width --walk $walk exits 0" test $? -eq 0
        check "the JSON names the $walk walk" grep -q "\"walk\": \"$walk\"" "$tmp/walk-$width-$walk.json"
        check "width $width, $walk walk: the same hits as the pairs" test \
            "$(counts "$tmp/walk-$width-$walk.json")" = "$(counts "$tmp/pairs.json")"
    done
done
"$vkrt" bench "$src/scenes/cornell/scene.cfg" --walk sideways >/dev/null 2>"$tmp/err"
check "--walk sideways is refused" test $? -ne 0
bench_run quads-storage --bvh-width 4 --loads storage
check "the 4-wide layout with storage loads hits what the pairs hit" test "$(counts "$tmp/quads-storage.json")" = "$(counts "$tmp/pairs.json")"
for accel in grid brute; do
    for loads in storage texel; do
        "$vkrt" bench "$src/scenes/cornell/scene.cfg" --accel $accel --width 40 --height 30 \
            --loads $loads --json "$tmp/$accel-$loads.json" >/dev/null 2>&1
    done
    check "$accel: storage and texel loads hit the same as the BVH" test \
        "$(counts "$tmp/$accel-storage.json")" = "$(counts "$tmp/pairs.json")" -a \
        "$(counts "$tmp/$accel-texel.json")" = "$(counts "$tmp/pairs.json")"
done
"$vkrt" bench "$src/scenes/cornell/scene.cfg" --loads fast >/dev/null 2>"$tmp/err"
check "--loads fast is refused" test $? -ne 0
bench_run stats --stats
check "bench --stats exits 0" test $? -eq 0
check "bench --stats counts nodes per ray" grep -q '"primary_nodes_per_ray": [1-9]' "$tmp/stats.json"
check "bench --stats measures SIMD utilisation" grep -q '"primary_simd_utilisation": 0\.[0-9]*[1-9]' "$tmp/stats.json"
bench_run tuned --bvh-leaf 4 --bvh-cost 2
check "bench --bvh-leaf 4 --bvh-cost 2 exits 0" test $? -eq 0
check "another BVH over the same triangles hits what the default one hits" test "$(counts "$tmp/tuned.json")" = "$(counts "$tmp/pairs.json")"
check "and is another tree" test "$(grep -o '"nodes_or_cells": [0-9]*' "$tmp/tuned.json")" != "$(grep -o '"nodes_or_cells": [0-9]*' "$tmp/pairs.json")"
"$vkrt" bench "$src/scenes/cornell/scene.cfg" --bvh-leaf 17 >/dev/null 2>"$tmp/err"
check "--bvh-leaf 17 is refused" test $? -ne 0
# The driver's kernel statistics: printed where the device reports them, else a refusal that
# names the extension (lavapipe has none).
bench_run kernel --kernel-stats
if [ $? -eq 0 ]; then
    check "bench --kernel-stats prints the trace kernel's statistics" grep -q "trace.comp: ." "$tmp/kernel.txt"
else
    check "bench --kernel-stats names what the device lacks" grep -q "VK_KHR_pipeline_executable_properties" "$tmp/kernel.txt"
fi
"$vkrt" bench "$src/scenes/cornell/scene.cfg" --bvh-width 3 >/dev/null 2>"$tmp/err"
check "--bvh-width 3 is refused" test $? -ne 0
check "and says which widths there are" grep -q "not one of 2, 4" "$tmp/err"
# Each command owns its options: one given to a command that does not take it is refused, with
# the command named (before any work: no output file appears).
"$vkrt" render "$src/scenes/cornell/scene.cfg" --walk nested -o "$tmp/walk.png" 2>"$tmp/err"
check "render --walk is refused" test $? -eq 2
check "and the message names the command and the one that takes it" \
    grep -q "vkrt render does not take --walk (an option of vkrt bench)" "$tmp/err"
check "and nothing was written" test ! -e "$tmp/walk.png"
"$vkrt" bench "$src/scenes/cornell/scene.cfg" --spp 4 >/dev/null 2>"$tmp/err"
check "bench --spp is refused" grep -q "vkrt bench does not take --spp (an option of vkrt render and view)" "$tmp/err"
"$vkrt" view "$src/scenes/cornell/scene.cfg" --resume 2>"$tmp/err"
check "view --resume is refused" grep -q "vkrt view does not take --resume" "$tmp/err"
# --clamp takes a positive number; anything else is refused before any work, naming the flag.
for bad in -1 x 0 inf; do
    "$vkrt" render "$src/scenes/cornell/scene.cfg" --clamp $bad -o "$tmp/clamp.png" 2>"$tmp/err"
    check "render --clamp $bad is refused" test $? -eq 2
    check "and the message names --clamp" grep -q -- "--clamp: '$bad' is not a" "$tmp/err"
done
check "and nothing was written" test ! -e "$tmp/clamp.png"
"$vkrt" view "$src/scenes/cornell/scene.cfg" --clamp x 2>"$tmp/err"
check "view --clamp x is refused" grep -q -- "--clamp: 'x' is not a number" "$tmp/err"
"$vkrt" bench "$src/scenes/cornell/scene.cfg" --clamp 1 >/dev/null 2>"$tmp/err"
check "bench --clamp is refused" grep -q "vkrt bench does not take --clamp" "$tmp/err"
"$vkrt" render "$src/scenes/cornell/scene.cfg" --width 8 --height 8 --clamp 0.5 -o "$tmp/clamp.exr" 2>"$tmp/err"
check "render --clamp 0.5 exits 0" test $? -eq 0
"$vkrt" bench "$src/scenes/cornell/scene.cfg" --ray-fetch dynamic >/dev/null 2>"$tmp/err"
check "--ray-fetch (an experiment that left the product) is an unknown option" \
    grep -q "unknown option '--ray-fetch'" "$tmp/err"

# The kernel cache (src/gpu/spirv_cache.h): four renders started together on an empty cache all
# succeed with the same picture, and leave whole entries (the next render compiles nothing);
# --no-cache neither reads nor writes it.
cache=$tmp/kernel-cache
for i in 1 2 3 4; do
    VKRT_CACHE_DIR=$cache "$vkrt" render "$src/scenes/cornell/scene.cfg" --width 24 --height 16 \
        --quiet -o "$tmp/k$i.png" 2>"$tmp/k$i.err" &
done
wait
for i in 1 2 3 4; do
    check "concurrent render $i on one cache exits 0 and writes its picture" test -s "$tmp/k$i.png"
    check "and the same picture as the first" cmp -s "$tmp/k1.png" "$tmp/k$i.png"
done
VKRT_CACHE_DIR=$cache "$vkrt" render "$src/scenes/cornell/scene.cfg" --width 24 --height 16 \
    --verbose -o "$tmp/k5.png" 2>"$tmp/err"
check "after them, every kernel comes from the cache" grep -q "kernels: 0 compiled, [1-9][0-9]* from the cache" "$tmp/err"
check "no temporary file is left in the cache" sh -c "! ls '$cache' | grep -q tmp"
check "the driver's pipeline data comes from the cache too" grep -q "pipelines: [1-9][0-9]* from the driver's data there, 0 stored" "$tmp/err"
VKRT_CACHE_DIR=$tmp/k1.png "$vkrt" render "$src/scenes/cornell/scene.cfg" --width 24 --height 16 \
    --verbose -o "$tmp/k6.png" 2>"$tmp/err"
check "a cache directory that is a file stores nothing, and --verbose says so" grep -q "kernels: [1-9][0-9]* compiled, 0 from the cache in $tmp/k1.png, 0 stored there; pipelines: 0 from the driver's data there, 0 stored (the cache could not be written" "$tmp/err"
# A damaged pipeline entry is not handed to the driver: it is made and written again, whole.
first=$(ls "$cache"/*.vkpc | head -n 1)
size=$(wc -c <"$first")
printf 'not a pipeline cache' >"$first"
VKRT_CACHE_DIR=$cache "$vkrt" render "$src/scenes/cornell/scene.cfg" --width 24 --height 16 \
    --verbose -o "$tmp/k7.png" 2>"$tmp/err"
check "a damaged pipeline entry still renders the same picture" cmp -s "$tmp/k1.png" "$tmp/k7.png"
check "and is stored again" grep -q "pipelines: [1-9][0-9]* from the driver's data there, 1 stored" "$tmp/err"
check "whole" test "$(wc -c <"$first")" -eq "$size"
VKRT_CACHE_DIR=$tmp/unused "$vkrt" render "$src/scenes/cornell/scene.cfg" --width 24 --height 16 \
    --no-cache --verbose -o "$tmp/k6.png" 2>"$tmp/err"
check "--no-cache compiles every kernel" grep -q "kernels: [1-9][0-9]* compiled (no kernel cache" "$tmp/err"
check "and writes no cache" test ! -e "$tmp/unused"

# --seed (what it does is tests/test_path.c's seeds_give_independent_noise): taken by render.
"$vkrt" render "$src/scenes/cornell-spheres/lamp.cfg" --width 8 --height 8 --spp 1 --quiet \
    --seed 7 -o "$tmp/seed.png"
check "render --seed exits 0" test $? -eq 0
"$vkrt" render "$src/scenes/cornell-spheres/lamp.cfg" --seed x -o "$tmp/seedx.png" 2>"$tmp/err"
check "--seed x is refused" test $? -eq 2

summary
