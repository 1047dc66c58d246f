/*
 * prepare.comp: one invocation that turns the next wave's ray count into its indirect dispatch
 * (folded into y past 65535 workgroups, as gpu_dispatch does) and keeps the frame's statistics.
 */
#include "lib/bindings.glsl"

void main()
{
    if (invocation_index() != 0u)
        return;
    uint next = frame.wave.y + 1u;
    uint requested = waves[next].ray_count;
    uint count = min(requested, frame.wave.w);
    uint groups = (count + WAVE_WORKGROUP_SIZE - 1u) / WAVE_WORKGROUP_SIZE;
    uint groups_x = min(groups, 65535u);
    waves[next].groups_x = groups_x;
    waves[next].groups_y = groups_x == 0u ? 0u : (groups + groups_x - 1u) / groups_x;
    waves[next].groups_z = 1u;
    counters.secondary_rays += count;
    counters.max_wave = max(counters.max_wave, requested);
}
