/*
 * sort_count.comp: the ray sort's first pass (lib/ray_sort.glsl): counts this workgroup's chunk
 * of RayBufferB per direction cell, then reserves the chunk's run of slots in each cell.
 */
#include "lib/bindings.glsl"
#include "lib/ray_sort.glsl"

shared uint chunk_rays[SORT_MAX_BINS];

void main()
{
    uint n = frame.counts.z, cells = sort_cells(), chunk = sort_chunk();
    uint lane = gl_LocalInvocationIndex;
    for (uint b = lane; b < cells; b += gl_WorkGroupSize.x)
        chunk_rays[b] = 0u;
    barrier();
    uint first = chunk * SORT_CHUNK, end = min(first + SORT_CHUNK, n);
    for (uint i = first + lane; i < end; i += gl_WorkGroupSize.x)
        atomicAdd(chunk_rays[sort_key(rays_b[i].direction.xyz)], 1u);
    barrier();
    /* The order chunks reserve in is the order their atomics land, not their index: a cell's runs
     * may come in any chunk order, each run in order within. */
    for (uint b = lane; b < cells; b += gl_WorkGroupSize.x) {
        uint count = chunk_rays[b];
        sort_words[SORT_PLACES + chunk * cells + b] =
            count == 0u ? 0u : atomicAdd(sort_words[SORT_TOTALS + b], count);
    }
}
