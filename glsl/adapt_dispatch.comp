/*
 * adapt_dispatch.comp: one invocation after adapt.comp (--target-error): the pixels it listed
 * become the next pass's list, and raygen's indirect dispatch covers them times counts.z, the
 * most samples a pass gives a pixel (raygen stops invocations past the pass's own count). The
 * host reads counters.active_pixels after a submission: 0 means every pixel is done.
 */
#include "lib/bindings.glsl"

void main()
{
    if (invocation_index() != 0u)
        return;
    uint count = active_list.appended;
    /* At least one workgroup, whose first invocation empties the wave table when no pixel is
     * listed (raygen.comp), so the pass's other kernels find no rays. */
    uint groups = max((count * frame.counts.z + WAVE_WORKGROUP_SIZE - 1u) / WAVE_WORKGROUP_SIZE, 1u);
    uint groups_x = min(groups, 65535u);
    active_list.groups_x = groups_x;
    active_list.groups_y = (groups + groups_x - 1u) / groups_x;
    active_list.groups_z = 1u;
    active_list.count = count;
    active_list.appended = 0u;
    counters.active_pixels = count;
}
