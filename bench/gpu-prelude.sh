# gpu-prelude.sh: sourced by the bench/gpu-run-*.sh scripts on the GPU machine. Sets $out (the
# folder whose files come back, $OUT) and $root, unpacks .bundle/scenes.tar.gz and links it
# where the scene files expect ../shared/scenes.
set -u
out=${OUT:-/tmp/vkrt-out}
mkdir -p "$out"
root=$(pwd)
(cd .bundle && tar xzf scenes.tar.gz)
mkdir -p ../shared && ln -sfn "$root/.bundle/scenes" ../shared/scenes
