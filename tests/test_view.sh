#!/bin/sh
# test_view.sh: `vkrt view` under Xvfb, driven by a --script: it flies (keys held, a mouse drag,
# a scroll), resizes the window, waits for the image to converge and then some more, takes a
# screenshot, prints and records the camera, and quits with Escape. Checked:
#   - a clean exit, with validation on (tests/meson.build) and not one message, swapchain and
#     presentation included;
#   - the screenshot (the window's pixels) against `vkrt render` of the printed camera at the
#     same size and spp;
#   - from the per-frame log: no frame traced anything while its camera and the spp target were
#     unchanged, an image was started again only when the camera (or size) changed, and its
#     passes add up to exactly the target;
#   - `vkrt view` without a display fails with a message instead of crashing;
#   - a .glb alone through its orthographic camera matches `vkrt render` of it;
#   - in path mode (a scene lit by an emissive lamp): a still picture converges (after 8 passes
#     it is nearer a 64-spp render than after 1), a move starts it again, and the converged
#     window matches `vkrt render` of its camera.
# Exit 77 (skipped) without xvfb-run or in a vkrt built without the viewer. VKRT_KEEP_VIEW=DIR
# copies the path-mode screenshots and renders into DIR, to look at.
set -u
vkrt=${VKRT_BINARY:?}
src=${VKRT_SOURCE_DIR:?}
compare=${VKRT_PNG_COMPARE:?}
if ! command -v xvfb-run >/dev/null 2>&1; then
    echo "SKIP: xvfb-run is missing (Debian: apt-get install xvfb xauth)"
    exit 77
fi
tmp=$(mktemp -d)
trap '[ -n "${VKRT_KEEP_VIEW:-}" ] && cp "$tmp"/lamp* "$VKRT_KEEP_VIEW"; rm -rf "$tmp"' EXIT
. "$src/tests/lib.sh"

if DISPLAY= WAYLAND_DISPLAY= "$vkrt" view "$src/scenes/cornell/scene.cfg" 2>"$tmp/err"; then
    status=0
else
    status=$?
fi
if grep -q "built without the viewer" "$tmp/err"; then
    echo "SKIP: this vkrt was built without the viewer (GLFW)"
    exit 77
fi
check "view without a display exits 1" test $status -eq 1
check "and says it needs a display" grep -q "needs a display" "$tmp/err"
"$vkrt" --help >"$tmp/help"
check "--help shows view and its controls" grep -q "vkrt view SCENE.cfg" "$tmp/help"
check "--help lists --script" grep -q -- "--script FILE" "$tmp/help"

# The Cornell box with a mirror and a glass sphere: secondary rays, small, quick on lavapipe.
sed -e "s|^geometry .*|geometry $src/scenes/cornell-spheres/cornell-spheres.obj|" \
    -e '/^output/d' "$src/scenes/cornell-spheres/scene.cfg" >"$tmp/spheres.cfg"
cat >"$tmp/events.txt" <<'EVENTS'
# fly forward, look right and up, go faster, strafe left and up; let the image converge; then
# resize and frame the scene in one frame (the wait after them must see the new image), and
# hold still
hold w 4
drag 40 -15 3
scroll 4
hold a 2
key shift down
hold e 2
key shift up
wait converged
resize 176 132
key f
wait converged
wait 12
key p
key k
key escape
EVENTS
spp=4
xvfb-run -a -s "-screen 0 1280x1024x24" "$vkrt" view "$tmp/spheres.cfg" --width 160 \
    --height 120 --spp $spp --script "$tmp/events.txt" --record "$tmp/flight.cfg" \
    >"$tmp/out" 2>"$tmp/log"
status=$?
check "scripted view exits 0" test $status -eq 0
[ $status -eq 0 ] || cat "$tmp/log"
check "no validation message" sh -c "! grep -q validation '$tmp/log'"
check "K printed one camera line" test "$(grep -c '^camera eye' "$tmp/out")" -eq 1
check "--record appended it" cmp -s "$tmp/out" "$tmp/flight.cfg"
check "the camera moved" sh -c "! grep -q '^camera eye 278 273 -800 ' '$tmp/out'"
check "P wrote the window's PNG" test -s "$tmp/spheres-view-000.png"
check "and the linear EXR" test -s "$tmp/spheres-view-000.exr"
check "the screenshot was taken converged" grep -q "($spp of $spp samples)" "$tmp/log"
check "the screenshot has the resized window's size" grep -q "(176x132, as shown)" "$tmp/log"

# The window against `vkrt render` of the printed camera, same size and spp. Both average the
# same stratified passes from the same random streams; the sums differ only in float atomic
# order (a few ULPs), and the window's sRGB curve runs in float on the GPU where the PNG
# writer's runs in double: each moves a value by far less than one 8-bit step, so a channel can
# land at most one step away (when it sits on a rounding boundary), never two.
{ grep -v '^camera' "$tmp/spheres.cfg"; cat "$tmp/out"; } >"$tmp/again.cfg"
"$vkrt" render "$tmp/again.cfg" --width 176 --height 132 --spp $spp -o "$tmp/render.png" --quiet
check "render of the printed camera exits 0" test $? -eq 0
"$compare" "$tmp/spheres-view-000.png" "$tmp/render.png" 1 >"$tmp/compared"
check "the window matches the render to one 8-bit step" test $? -eq 0
cat "$tmp/compared"

# A glTF file alone (no scene.cfg), through its orthographic camera (--camera 1), with a tone
# curve after an exposure: the converged window against `vkrt render` of the same file, camera
# and finish, to one 8-bit step as above (the window's curve is glsl/display.comp's, the PNG's
# src/output/tonemap.c's).
cp "$src/tests/gltf/cameras/scene.glb" "$tmp/cams.glb"
printf 'wait converged\nkey p\nkey escape\n' >"$tmp/glb-events.txt"
xvfb-run -a -s "-screen 0 1280x1024x24" "$vkrt" view "$tmp/cams.glb" --camera 1 --width 96 \
    --height 72 --spp 4 --tonemap aces --exposure 1 --script "$tmp/glb-events.txt" \
    >"$tmp/glb-out" 2>"$tmp/glb-log"
status=$?
check "glTF: view of a .glb alone exits 0" test $status -eq 0
[ $status -eq 0 ] || cat "$tmp/glb-log"
check "glTF: no validation message" sh -c "! grep -q validation '$tmp/glb-log'"
"$vkrt" render "$tmp/cams.glb" --camera 1 --width 96 --height 72 --spp 4 --tonemap aces \
    --exposure 1 -o "$tmp/glb-render.png" --quiet
check "glTF: render of the same camera exits 0" test $? -eq 0
"$compare" "$tmp/cams-view-000.png" "$tmp/glb-render.png" 1 >"$tmp/glb-compared"
check "glTF: the window matches the render to one 8-bit step" test $? -eq 0
cat "$tmp/glb-compared"

# The log has a line per frame: "vkrt: view: frame F view V passes P/T traced K". audit LOG
# STILL: no frame traced while its camera and target were unchanged and complete, a new image
# starts from 0, passes add up, and at least STILL frames were still and complete.
audit() {
awk -v min_still="$2" '/^vkrt: view: frame / {
        v = $6; split($8, pt, "/"); p = pt[1]; t = pt[2]; k = $10
        if (v == last_v) {
            if (k > 0 && last_p >= t) { print "frame " $4 ": traced while still and complete"; bad++ }
            if (p != last_p + k) { print "frame " $4 ": passes do not add up"; bad++ }
        } else if (p != k) { print "frame " $4 ": a new image does not start from 0"; bad++ }
        if (p > t) { print "frame " $4 ": more passes than the target"; bad++ }
        if (k == 0 && p == t) still++
        last_v = v; last_p = p; frames++
     }
     END { printf "%d frames, %d still, %d bad\n", frames, still, bad; exit bad > 0 || still < min_still }' \
    "$1"
}
audit "$tmp/log" 12 >"$tmp/audit"
check "nothing traced while the camera and target were unchanged" test $? -eq 0
cat "$tmp/audit"

# Path tracing: the Cornell box lit by its emissive lamp alone (lamp.cfg: `integrator auto`
# chooses path). A still camera gathers samples, so the picture after all 16 passes is nearer a
# converged one (a 64-spp render) than the first pass's: by the root mean square of the 8-bit
# differences, 0.23 times as far when written, 1/4 in theory. With --clamp 1 in the window and
# the renders: unclamped, the fireflies of the small bright lamp stay white in 8 bits at any spp
# and hold the ratio near 0.6. A move starts the image again, and the picture converged there is
# the render of the printed camera.
sed -e "s|^geometry .*|geometry $src/scenes/cornell-spheres/cornell-spheres.obj|" \
    -e "s|^materials .*|materials $src/scenes/cornell-spheres/lamp.mat|" \
    -e '/^output/d' "$src/scenes/cornell-spheres/lamp.cfg" >"$tmp/lamp.cfg"
cat >"$tmp/path-events.txt" <<'EVENTS'
wait 1
key p
wait converged
key p
hold d 3
key p
wait converged
key p
key k
key escape
EVENTS
xvfb-run -a -s "-screen 0 1280x1024x24" "$vkrt" view "$tmp/lamp.cfg" --width 48 --height 48 \
    --spp 16 --clamp 1 --script "$tmp/path-events.txt" >"$tmp/path-out" 2>"$tmp/path-log"
status=$?
check "path: scripted view exits 0" test $status -eq 0
[ $status -eq 0 ] || cat "$tmp/path-log"
check "path: no validation message" sh -c "! grep -q validation '$tmp/path-log'"
check "path: auto chose the path tracer" grep -q "| integrator path |" "$tmp/path-log"
check "path: the first screenshot holds one pass" grep -q "lamp-view-000.exr (1 of 16 samples)" "$tmp/path-log"
check "path: the second all sixteen" grep -q "lamp-view-001.exr (16 of 16 samples)" "$tmp/path-log"
check "path: after the move the image started again" \
    grep -q "lamp-view-002.exr ([1-3] of 16 samples)" "$tmp/path-log"
audit "$tmp/path-log" 0 >"$tmp/path-audit"
check "path: images start again only on a move, passes add up" test $? -eq 0
cat "$tmp/path-audit"
"$vkrt" render "$tmp/lamp.cfg" --width 48 --height 48 --spp 64 --clamp 1 -o "$tmp/lamp64.png" \
    --quiet
first=$(png_rms "$tmp/lamp-view-000.png" "$tmp/lamp64.png")
all16=$(png_rms "$tmp/lamp-view-001.png" "$tmp/lamp64.png")
echo "path: rms difference from 64 spp: $first after 1 pass, $all16 after 16"
check "path: 16 passes are nearer convergence than 1" awk -v a="$first" -v b="$all16" 'BEGIN { exit !(b < 0.5 * a) }'
{ grep -v '^camera' "$tmp/lamp.cfg"; cat "$tmp/path-out"; } >"$tmp/lamp-moved.cfg"
"$vkrt" render "$tmp/lamp-moved.cfg" --width 48 --height 48 --spp 16 --clamp 1 \
    -o "$tmp/lamp-moved.png" --quiet
"$compare" "$tmp/lamp-view-003.png" "$tmp/lamp-moved.png" 1 >"$tmp/compared"
check "path: the converged window after the move matches the render of its camera" test $? -eq 0
cat "$tmp/compared"

# Sampling to a target error: a still picture is done when every pixel's estimate is within it
# (the same as vkrt render's), before the --spp cap: the screenshot after `wait converged` holds
# fewer samples than the cap.
cat >"$tmp/target-events.txt" <<'EVENTS'
wait converged
key p
key escape
EVENTS
(cd "$tmp" && xvfb-run -a -s "-screen 0 1280x1024x24" "$vkrt" view "$tmp/lamp.cfg" --width 32 \
    --height 32 --spp 1024 --target-error 0.3 --clamp 1 --script "$tmp/target-events.txt" \
    >/dev/null 2>"$tmp/target-log")
status=$?
check "target: scripted view exits 0" test $status -eq 0
[ $status -eq 0 ] || cat "$tmp/target-log"
check "target: no validation message" sh -c "! grep -q validation '$tmp/target-log'"
grep "screenshot" "$tmp/target-log"
check "target: done within the target before the 1024-sample cap" \
    grep -Eq "lamp-view-[0-9]+.exr \(([0-9]|[0-9][0-9]|[0-9][0-9][0-9]|10[01][0-9]|102[0-3]) of 1024 samples\)" "$tmp/target-log"

summary
