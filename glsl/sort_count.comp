/*
 * sort_count.comp: the ray sort's first pass (lib/ray_sort.glsl): counts this workgroup's chunk
 * of RayBufferB per direction cell, then reserves the chunk's run of slots in each cell.
 */
#include "lib/bindings.glsl"
#include "lib/ray_sort.glsl"

void main()
{
    uint n = frame.counts.z, cells = sort_cells(), chunk = sort_chunk();
    uint lane = gl_LocalInvocationIndex;
    for (uint b = lane; b < cells; b += gl_WorkGroupSize.x)
        sort_cell[b] = 0u;
    barrier();
    /* Every invocation runs every round, live or not: sort_reserve needs them all. */
    uint first = chunk * SORT_CHUNK;
    for (uint k = 0u; k < SORT_CHUNK; k += gl_WorkGroupSize.x) {
        uint i = first + k + lane;
        bool live = i < n;
        sort_reserve(live ? sort_key(rays_b[i].direction.xyz) : 0u, live);
    }
    barrier();
    /* The order chunks reserve in is the order their atomics land, not their index: a cell's runs
     * may come in any chunk order, each run in order within. */
    for (uint b = lane; b < cells; b += gl_WorkGroupSize.x) {
        uint count = sort_cell[b];
        sort_words[SORT_PLACES + chunk * cells + b] =
            count == 0u ? 0u : atomicAdd(sort_words[SORT_TOTALS + b], count);
    }
}
