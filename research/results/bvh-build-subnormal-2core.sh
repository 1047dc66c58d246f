#!/bin/sh
# The runs of research/results/bvh-build-subnormal-2core.txt: the bvh-bench of $OLD (there 0ba6d56: main's builder,
# bvh-bench printing the tree hash) and of $NEW (this branch), interleaved; run from the repository root with the
# tiles made first (the .txt's header says how). Its summary table: bvh-build-subnormal-2core-table.py on the output.
S=../shared/scenes
hdr() { echo "== $1 threads=$2 round $3 load $(cut -d' ' -f1-3 /proc/loadavg)"; }
for r in 1 2 3; do
  for f in $S/stanford-bunny/stanford-bunny.obj $S/dabrovic-sponza/sponza.obj $S/sibenik-cathedral/sibenik.obj $S/lost-empire/lost_empire.obj $S/utah-teapot/teapot.obj $S/cornell-box/CornellBox-Original.obj /tmp/tiled-3x3/tiled.obj; do
    runs=10; [ "$(basename $f)" = tiled.obj ] && runs=2
    for v in old new; do
      hdr "$v $(basename $f)" 1 $r
      b=${OLD:-.bundle-old/bin/bvh-bench}; [ $v = new ] && b=${NEW:-build/bvh-bench}
      $b $f $runs 1 2 0.5 | grep -E "^run|triangles|min"
    done
  done
done
for r in 1 2; do for v in old new; do
  hdr "$v tiled-3x3" 2 $r
  b=${OLD:-.bundle-old/bin/bvh-bench}; [ $v = new ] && b=${NEW:-build/bvh-bench}
  $b /tmp/tiled-3x3/tiled.obj 2 2 2 0.5
done; done
for v in old new; do
  hdr "$v tiled-9x5" 1 1
  b=${OLD:-.bundle-old/bin/bvh-bench}; [ $v = new ] && b=${NEW:-build/bvh-bench}
  $b /tmp/tiled-9x5/tiled.obj 2 1 2 0.5
done
