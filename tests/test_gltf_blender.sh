#!/bin/sh
# test_gltf_blender.sh ROUTE: vkrt against Cycles on the Blender-made scenes of tests/gltf/
# (tools/blender_scenes.py wrote them, and rendered each view with Cycles).
#   ROUTE obj:  each scene.cfg (Blender's OBJ export; its lights and cameras converted by the
#               script): an independent check of the camera and light conversions and of this
#               harness, with vkrt's OBJ loader.
#   ROUTE gltf: each scene.glb through the glTF loader, with the file's own cameras, animation
#               and lights. Skipped (77), saying why, while vkrt cannot read .glb.
# Each view is held to Cycles twice (tests/cycles_compare.c):
#   - the silhouette: the soft IoU of vkrt's coverage against Cycles' alpha, at least MIN_IOU,
#     and at most MAX_WRONG pixels covered in one and not the other: every instance where
#     Cycles has it (the instances' scenes have no ground, whose outline would hold them). vkrt's coverage: a Whitted render at max-depth 0 in an
#     environment of 1, where only camera rays that miss see the environment, less the same
#     render in a black one (the OBJ route leaves the lights out instead: these scenes have no
#     emission, so every surface is black and one render is enough);
#   - the image means of R, G and B (the path tracer, 4 bounces as Cycles had, black
#     environment), within the scene's tolerance, where the material models coincide
#     (tools/blender_scenes.py says where they do not: the glass sphere of `materials` is solid
#     in Cycles and thin-walled in glTF, Cycles' spot light has a cosine glTF's has not).
# Run by meson test with VKRT_BINARY, VKRT_SOURCE_DIR and VKRT_CYCLES_COMPARE.
set -u
vkrt=${VKRT_BINARY:?}
src=${VKRT_SOURCE_DIR:?}
compare=${VKRT_CYCLES_COMPARE:?}
route=${1:?usage: test_gltf_blender.sh obj|gltf}
scenes=$src/tests/gltf
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
. "$src/tests/lib.sh"

MIN_IOU=0.97
# Pixels whose coverage may differ from Cycles' by more than half: none did in any view here; a
# field of view 1.3% too wide made 26 (and an IoU of 0.994, still above MIN_IOU).
MAX_WRONG=10
# Samples per pixel: the silhouette's renders are only camera rays; 16 samples put a pixel's
# coverage within about 1/8 on an edge. The means are over 19,200 pixels: 8 paths each put
# their noise well under a percent.
SILHOUETTE_SPP=16
MEAN_SPP=8

# variant CFG ENVIRONMENT INTEGRATOR DEPTH GEOMETRY: the scene file CFG with GEOMETRY (an
# absolute path), the environment, integrator and depth replaced, and no output line.
variant() {
    sed -e "s|^geometry .*|geometry $5|" -e "s|^environment .*|environment $2|" \
        -e "s|^integrator .*|integrator $3|" -e "s|^max-depth .*|max-depth $4|" -e '/^output /d' \
        "$1"
}

# render WHAT CFG OUT SPP ARGS...: renders CFG into OUT (a pattern with the frame number).
render() {
    label=$1 cfg=$2 out=$3 spp=$4
    shift 4
    "$vkrt" render "$cfg" -o "$out" --spp "$spp" --quiet "$@" >"$tmp/log" 2>&1
    status=$?
    [ $status -eq 0 ] || sed 's/^/    /' "$tmp/log"
    check "$label: vkrt exits 0" test $status -eq 0
}

# hold NAME VIEW TOLERANCE BLACK.png WHITE.png MEAN.exr: one view's renders against Cycles' view
# VIEW of scene NAME.
hold() {
    scene=$1 view=$2 tolerance=$3
    ref=$scenes/$scene/cycles-$view
    printf '%s %s %s: ' "$route" "$scene" "$view"
    check "$scene $view: silhouette" "$compare" iou "$ref.png" "$4" "$5" $MIN_IOU $MAX_WRONG
    printf '%s %s %s: ' "$route" "$scene" "$view"
    if [ "$tolerance" = - ]; then
        "$compare" mean "$ref.exr" "$6" 1000 # printed, not held
    else
        check "$scene $view: means" "$compare" mean "$ref.exr" "$6" "$tolerance"
    fi
}

# variants CFG DIR GEOMETRY: the scene files of the renders, DIR/black.cfg, white.cfg and
# mean.cfg, from CFG with GEOMETRY as its geometry.
variants() {
    variant "$1" "0 0 0" whitted 0 "$3" >"$2/black.cfg"
    variant "$1" "1 1 1" whitted 0 "$3" >"$2/white.cfg"
    variant "$1" "0 0 0" path 4 "$3" >"$2/mean.cfg"
}

# renders WHAT DIR KINDS ARGS...: the renders KINDS (black white mean, or white mean) of DIR's
# scene files into DIR/black, white and mean, numbered by frame.
renders() {
    label=$1 dir=$2 kinds=$3
    shift 3
    for kind in $kinds; do
        mkdir -p "$dir/$kind"
        case $kind in
        mean) render "$label $kind" "$dir/$kind.cfg" "$dir/$kind/%02d.exr" $MEAN_SPP "$@" ;;
        *) render "$label $kind" "$dir/$kind.cfg" "$dir/$kind/%02d.png" $SILHOUETTE_SPP "$@" ;;
        esac
    done
}

# scene_obj NAME TOLERANCE VIEW...: renders scene.cfg, whose frame i is Cycles' view VIEW i.
# Its silhouette render has no lights (no emission in the scenes it is run on).
scene_obj() {
    scene=$1 tolerance=$2
    shift 2
    dir=$tmp/$scene
    mkdir -p "$dir"
    variants "$scenes/$scene/scene.cfg" "$dir" "$scenes/$scene/scene.obj"
    sed -i '/^light /d' "$dir/white.cfg"
    renders "$scene" "$dir" "white mean"
    frame=0
    for view in "$@"; do
        f=$(printf %02d $frame)
        hold "$scene" "$view" "$tolerance" - "$dir/white/$f.png" "$dir/mean/$f.exr"
        frame=$((frame + 1))
    done
}

# output DIR KIND EXT VIEW: the render of VIEW among DIR/KIND/*.EXT: frame NN for a view
# frameNN of a flythrough, else the one file there.
output() {
    case $4 in
    frame[0-9]*) echo "$1/$2/${4#frame}.$3" ;;
    *) for file in "$1/$2/"*".$3"; do echo "$file"; break; done ;;
    esac
}

# scene_gltf NAME TOLERANCE VIEWS:ARGS...: renders scene.glb with its own lights and cameras;
# ARGS (words joined by commas) pick the views, VIEWS (joined by commas): --camera N for one
# camera, --frames A:B:STEP for frames of the flythrough, its views named frameNN.
scene_gltf() {
    scene=$1 tolerance=$2
    shift 2
    for spec in "$@"; do
        views=${spec%%:*}
        dir=$tmp/$scene-$(echo "$views" | tr , -)
        mkdir -p "$dir"
        # the OBJ route's settings, neither lights nor cameras: the file's own are used
        sed -e '/^light /d' -e '/^camera /d' "$scenes/$scene/scene.cfg" >"$dir/scene.cfg"
        variants "$dir/scene.cfg" "$dir" "$scenes/$scene/scene.glb"
        # shellcheck disable=SC2046 # the views' arguments, split at commas
        renders "$scene $views" "$dir" "black white mean" $(echo "${spec#*:}" | tr , ' ')
        for view in $(echo "$views" | tr , ' '); do
            hold "$scene" "$view" "$tolerance" "$(output "$dir" black png "$view")" \
                "$(output "$dir" white png "$view")" "$(output "$dir" mean exr "$view")"
        done
    done
}

# Tolerances of the means: the noise of 8 paths a pixel, and of Cycles' 1024, is under 1% of a
# mean (the OBJ route's sun-lit scenes agreed within 0.1%); lights: 5%, as Cycles' spot has a
# cosine and a later, smoothstep edge (its half of the picture 5% brighter than vkrt's, the point
# light's half within 0.01%); '-' prints the means without holding them (materials: the glass is
# solid in Cycles and thin-walled in glTF).
if [ "$route" = obj ]; then
    scene_obj instances 0.03 cam0
    scene_obj flythrough 0.03 frame00 frame08 frame24
    scene_obj lights 0.05 cam0
else
    probe_dir=$tmp/probe
    mkdir -p "$probe_dir"
    sed -e '/^light /d' -e '/^camera /d' "$scenes/instances/scene.cfg" >"$probe_dir/scene.cfg"
    variants "$probe_dir/scene.cfg" "$probe_dir" "$scenes/instances/scene.glb"
    probe=$("$vkrt" render "$probe_dir/mean.cfg" --width 8 --height 6 --spp 1 --quiet \
        -o "$probe_dir/probe.png" 2>&1)
    case $probe in
    *"not an OBJ text file"* | *"not a text line"* | *"no 'camera' line"* | *"unknown option"*)
        echo "SKIP: this vkrt cannot render a .glb yet: $probe"
        exit 77 ;;
    esac
    scene_gltf instances 0.03 cam0:
    scene_gltf materials - cam0:
    scene_gltf cameras 0.03 cam0:--camera,0 cam1:--camera,1
    scene_gltf flythrough 0.03 frame00,frame08,frame24:--frames,0:24:8
    scene_gltf lights 0.05 cam0:
fi
summary
