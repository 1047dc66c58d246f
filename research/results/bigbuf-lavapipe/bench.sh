#!/bin/sh
export VKRT_CACHE_DIR=/tmp/bb/cache
unset VKRT_VALIDATION
for i in 1 2 3 4 5 6; do
  for b in base new; do
    bin=/work/wt-bigbuf/build/vkrt; [ $b = base ] && bin=/tmp/bb/base/build/vkrt
    echo "$b $(cat /proc/loadavg | cut -d' ' -f1) $(nice $bin bench /work/wt-bigbuf/scenes/shared/sponza.cfg --accel bvh --width 160 --height 90 2>&1 | tail -1)"
    echo "$b-render $(nice $bin render /work/wt-bigbuf/scenes/shared/sponza.cfg --width 160 --height 90 --spp 4 -o /tmp/bb/r_$b.png 2>&1 | grep -o '[0-9.]* ms/frame')"
  done
done
