/*
 * sort_scan.comp: the ray sort's second pass (lib/ray_sort.glsl), one workgroup of SORT_MAX_BINS
 * invocations: each cell's first slot is the sum of the cells before it. Zeroes the totals for
 * the next sort.
 */
#include "lib/bindings.glsl"
#include "lib/ray_sort.glsl"

shared uint cell_start[SORT_MAX_BINS];

void main()
{
    uint cells = sort_cells(), lane = gl_LocalInvocationIndex;
    cell_start[lane] = lane < cells ? sort_words[SORT_TOTALS + lane] : 0u;
    barrier();
    /* 256 words, once per sort: a serial sum costs less than the barriers of a parallel scan. */
    if (lane == 0u) {
        uint sum = 0u;
        for (uint b = 0u; b < cells; ++b) {
            uint count = cell_start[b];
            cell_start[b] = sum;
            sum += count;
        }
    }
    barrier();
    if (lane < cells) {
        sort_words[SORT_STARTS + lane] = cell_start[lane];
        sort_words[SORT_TOTALS + lane] = 0u;
    }
}
