/*
 * sort_scatter.comp: the ray sort's last pass (lib/ray_sort.glsl): copies this workgroup's chunk
 * of RayBufferB into RayBuffer, each ray to the next slot of its cell's run for this chunk. Rays
 * of a cell keep their order within a subgroup and a round.
 */
#include "lib/bindings.glsl"
#include "lib/ray_sort.glsl"

void main()
{
    uint n = frame.counts.z, cells = sort_cells(), chunk = sort_chunk();
    uint lane = gl_LocalInvocationIndex;
    for (uint b = lane; b < cells; b += gl_WorkGroupSize.x)
        sort_cell[b] = sort_words[SORT_STARTS + b] + sort_words[SORT_PLACES + chunk * cells + b];
    barrier();
    uint first = chunk * SORT_CHUNK;
    for (uint k = 0u; k < SORT_CHUNK; k += gl_WorkGroupSize.x) {
        uint i = first + k + lane;
        bool live = i < n;
        Ray ray;
        if (live)
            ray = rays_b[i];
        uint slot = sort_reserve(live ? sort_key(ray.direction.xyz) : 0u, live);
        if (live)
            rays[slot] = ray;
    }
}
