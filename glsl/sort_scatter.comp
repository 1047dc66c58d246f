/*
 * sort_scatter.comp: the ray sort's last pass (lib/ray_sort.glsl): copies this workgroup's chunk
 * of RayBufferB into RayBuffer, each ray to the next slot of its cell's run for this chunk. Rays
 * of a cell keep their order up to the invocations in flight at once.
 */
#include "lib/bindings.glsl"
#include "lib/ray_sort.glsl"

shared uint next_slot[SORT_MAX_BINS];

void main()
{
    uint n = frame.counts.z, cells = sort_cells(), chunk = sort_chunk();
    uint lane = gl_LocalInvocationIndex;
    for (uint b = lane; b < cells; b += gl_WorkGroupSize.x)
        next_slot[b] = sort_words[SORT_STARTS + b] + sort_words[SORT_PLACES + chunk * cells + b];
    barrier();
    uint first = chunk * SORT_CHUNK, end = min(first + SORT_CHUNK, n);
    for (uint i = first + lane; i < end; i += gl_WorkGroupSize.x) {
        Ray ray = rays_b[i];
        rays[atomicAdd(next_slot[sort_key(ray.direction.xyz)], 1u)] = ray;
    }
}
