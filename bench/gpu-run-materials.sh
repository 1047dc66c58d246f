#!/bin/sh
# gpu-run-materials.sh: what was run on the GPU machine (an H100 without a display) for the
# wavefront pipeline (issue 3): the GPU tests of materials, textures and the CPU reference, and
# renders of the scenes with .mtl files and textures. It expects the bundle made by
#   tools/bundle .bundle build/tests/test_materials build/tests/test_render \
#       build/tests/test_texture_gpu build/tests/test_layout
# with .bundle/scenes.tar.gz holding ../shared/scenes/{dabrovic-sponza,sibenik-cathedral,
# lost-empire} (OBJ, MTL and textures) under scenes/, and writes everything under $OUT.
. bench/gpu-prelude.sh
export LD_LIBRARY_PATH="$root/.bundle/lib" VKRT_VALIDATION=0 VKRT_SOURCE_DIR="$root" \
    VKRT_SCENES_DIR="$root/.bundle/scenes"
{ .bundle/vkrt --list-devices; nvidia-smi --query-gpu=name,driver_version --format=csv; } \
    >"$out/tests.txt" 2>&1
for t in layout texture_gpu render materials; do
    .bundle/bin/test_$t >/tmp/test_$t.txt 2>&1
    status=$?
    { echo "== test_$t exit $status"; cat /tmp/test_$t.txt; } >>"$out/tests.txt"
    echo "test_$t exit $status"
done
render() {
    name=$1
    shift
    echo "== $name $*" >>"$out/renders.txt"
    .bundle/vkrt render "$@" -o "$out/$name.png" --verbose 2>&1 | grep -v "Both .d." >>"$out/renders.txt"
}
render cornell-spheres scenes/cornell-spheres/scene.cfg --width 1024 --height 1024 --spp 16
render sponza scenes/shared/sponza.cfg --width 1280 --height 720 --spp 4
render sibenik scenes/shared/sibenik.cfg --width 1280 --height 720 --spp 4
render lost-empire scenes/shared/lost-empire.cfg --width 1280 --height 720 --spp 4
cat "$out/renders.txt"
