#!/bin/sh
# test_denoise.sh: `--denoise` end to end (src/output/denoise.h).
#   - Without its library (VKRT_OIDN_LIBRARY naming a file that is not there) render and view
#     stop before any work (not even the scene is read), exit 1, write nothing, and say how to
#     get the library; bench refuses the option.
#   - With the library (tools/setup-python's .venv; else the rest is skipped, exit 77): the
#     Cornell box with spheres under its lamp at 64x64, 4 spp denoised, is nearer a 64-spp render
#     of other random numbers than the raw 16-spp render is. The reference's own noise adds the
#     same amount to both distances (it is independent of both), so the order is the order of
#     their distances to the converged picture.
#   - Under Xvfb, `vkrt view --denoise` shows its image denoised: its window at 16 passes is
#     nearer the reference than the raw 16-spp render (a window that showed the raw passes would
#     be as far).
set -u
vkrt=${VKRT_BINARY:?}
src=${VKRT_SOURCE_DIR:?}
compare=${VKRT_PNG_COMPARE:?}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
. "$src/tests/lib.sh"

# The scene with its files named from anywhere.
sed -e "s|^geometry .*|geometry $src/scenes/cornell-spheres/cornell-spheres.obj|" \
    -e "s|^materials .*|materials $src/scenes/cornell-spheres/lamp.mat|" \
    -e '/^output/d' "$src/scenes/cornell-spheres/lamp.cfg" >"$tmp/lamp.cfg"

says_how() {
    grep -q -- "--denoise" "$1" && grep -q "tools/setup-python" "$1" &&
        grep -q "VKRT_OIDN_LIBRARY=/nonexistent" "$1" && ! grep -q "missing.cfg" "$1"
}
VKRT_OIDN_LIBRARY=/nonexistent "$vkrt" render "$tmp/missing.cfg" --denoise -o "$tmp/x.png" \
    2>"$tmp/render-err"
check "render --denoise without the library exits 1" test $? -eq 1
check "and says how to get it, before reading the scene" says_how "$tmp/render-err"
check "and writes no file" test ! -e "$tmp/x.png"
cat "$tmp/render-err"
VKRT_OIDN_LIBRARY=/nonexistent "$vkrt" view "$tmp/missing.cfg" --denoise 2>"$tmp/view-err"
check "view --denoise without the library exits 1" test $? -eq 1
if ! grep -q "built without the viewer" "$tmp/view-err"; then
    check "and says how to get it" says_how "$tmp/view-err"
fi
"$vkrt" bench "$tmp/lamp.cfg" --denoise 2>"$tmp/bench-err"
check "bench refuses --denoise" grep -q "an option of vkrt render and view" "$tmp/bench-err"

"$vkrt" render "$tmp/lamp.cfg" --width 64 --height 64 --spp 4 --denoise --verbose \
    -o "$tmp/denoised4.png" 2>"$tmp/denoised-log"
status=$?
if [ $status -ne 0 ] && grep -q "needs Intel Open Image Denoise" "$tmp/denoised-log"; then
    sed -n 's/^vkrt: //p' "$tmp/denoised-log"
    summary || exit 1
    echo "SKIP: the rest needs Open Image Denoise (tools/setup-python)"
    exit 77
fi
check "render --denoise exits 0" test $status -eq 0
check "--verbose names the library and its device" \
    grep -q "vkrt: denoise: Open Image Denoise 2\.[0-9.]*, [A-Za-z]* device" "$tmp/denoised-log"
grep "denoise:" "$tmp/denoised-log"
"$vkrt" render "$tmp/lamp.cfg" --width 64 --height 64 --spp 16 -o "$tmp/raw16.png" --quiet
"$vkrt" render "$tmp/lamp.cfg" --width 64 --height 64 --spp 64 --seed 7 -o "$tmp/ref.png" \
    --quiet
denoised=$(png_rms "$tmp/denoised4.png" "$tmp/ref.png")
raw=$(png_rms "$tmp/raw16.png" "$tmp/ref.png")
echo "rms difference from 64 spp (seed 7): $denoised denoised at 4 spp, $raw raw at 16 spp"
check "4 spp denoised is nearer the reference than 16 spp raw" is_below "$denoised" "$raw"

if command -v xvfb-run >/dev/null 2>&1 && ! grep -q "built without the viewer" "$tmp/view-err"
then
    printf 'wait converged\nkey p\nkey escape\n' >"$tmp/events.txt"
    xvfb-run -a -s "-screen 0 1280x1024x24" "$vkrt" view "$tmp/lamp.cfg" --width 64 \
        --height 64 --spp 16 --denoise --script "$tmp/events.txt" >/dev/null 2>"$tmp/view-log"
    status=$?
    check "view --denoise exits 0" test $status -eq 0
    [ $status -eq 0 ] || cat "$tmp/view-log"
    check "view: no validation message" sh -c "! grep -q validation '$tmp/view-log'"
    shown=$(png_rms "$tmp/lamp-view-000.png" "$tmp/ref.png")
    echo "view: the window after 16 passes, denoised: rms $shown from 64 spp"
    check "view: 16 passes denoised are nearer the reference than 16 spp raw" \
        is_below "$shown" "$raw"
fi
summary
