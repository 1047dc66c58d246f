/*
 * order.comp: groups the hits of this depth by the shader of their material, so that the light,
 * count and shade kernels that follow (each reading its ray through ray_of_invocation) run one
 * shader's code per subgroup instead of every shader its lanes' hits need, one after the other: a
 * subgroup whose lanes hit several shaders pays for each of them in turn, one of a single shader
 * pays once (docs/performance.md has the measurements).
 *
 * Two dispatches over the wave (frame_order_step): VKRT_ORDER_COUNT adds each workgroup's
 * count of hits per bin to the depth's totals; VKRT_ORDER_PLACE gives each workgroup a run of
 * places in every bin it has hits of (the bin's start, from the totals, plus an atomic cursor)
 * and writes each hit's ray index at its place. Within a bin the rays keep their workgroups'
 * order loosely (workgroups take their runs as they come), which keeps much of the
 * coherence of neighbouring pixels' rays. raygen.comp zeroes the totals and cursors of every
 * depth at the start of each sample pass.
 */
#include "lib/bindings.glsl"
#include "lib/instances.glsl"

shared uint bin_hits[VKRT_ORDER_BINS];
shared uint bin_place[VKRT_ORDER_BINS];

/* The bin of ray index's hit: its material's shader, or the last bin for misses and dead rays. */
uint bin_of(uint index)
{
    Hit hit = hits[index];
    if (ray_is_dead(load_ray(index)) || hit.triangle == VKRT_NO_HIT)
        return VKRT_ORDER_BINS - 1u;
    return min(materials[material_of(hit_uploaded_triangle(hit.triangle))].info.x, VKRT_ORDER_BINS - 2u);
}

void main()
{
    uint local = gl_LocalInvocationIndex, size = gl_WorkGroupSize.x;
    for (uint b = local; b < VKRT_ORDER_BINS; b += size)
        bin_hits[b] = 0u;
    barrier();
    uint index = invocation_index();
    bool in_wave = index < dispatch_ray_count();
    uint bin = 0u, rank = 0u;
    if (in_wave) {
        bin = bin_of(index);
        rank = atomicAdd(bin_hits[bin], 1u);
    }
    barrier();
    uint totals = order_bins_start(frame.wave.y), cursors = totals + VKRT_ORDER_BINS;
    if (frame_order_step(frame) == VKRT_ORDER_COUNT) {
        for (uint b = local; b < VKRT_ORDER_BINS; b += size)
            if (bin_hits[b] > 0u)
                atomicAdd(material_order[totals + b], bin_hits[b]);
        return;
    }
    /* Where each bin starts: the totals of the bins before it. */
    for (uint b = local; b < VKRT_ORDER_BINS; b += size)
        bin_place[b] = material_order[totals + b];
    barrier();
    if (local == 0u) {
        uint start = 0u;
        for (uint b = 0u; b < VKRT_ORDER_BINS; ++b) {
            uint total = bin_place[b];
            bin_place[b] = start;
            start += total;
        }
    }
    barrier();
    for (uint b = local; b < VKRT_ORDER_BINS; b += size)
        if (bin_hits[b] > 0u)
            bin_place[b] += atomicAdd(material_order[cursors + b], bin_hits[b]);
    barrier();
    if (in_wave)
        material_order[order_places_start() + bin_place[bin] + rank] = index;
}
