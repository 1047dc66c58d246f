/*
 * ray_sort.glsl: what the ray sort's three kernels share (sort_count.comp, sort_scan.comp,
 * sort_scatter.comp). The sort orders the rays of RayBufferB into RayBuffer by the cell of their
 * direction on a SORT_CELLS x SORT_CELLS octahedral map of the sphere, a counting sort:
 *   1. sort_count: each workgroup counts its chunk of SORT_CHUNK rays per cell and takes its
 *      place in every cell with one atomic add to the cell's total;
 *   2. sort_scan: one workgroup turns the totals into the cells' first slots (and zeroes the
 *      totals for the next sort);
 *   3. sort_scatter: each workgroup writes its chunk's rays to its places.
 * A chunk's rays stay together within a cell, in nearly their old order, so rays that shared
 * origins (tiles of pixels) and now share a direction trace as one subgroup (docs/performance.md
 * has what it gains and costs).
 *
 * The scratch is the ray slot buffer (binding 15): free while rays are traced, and with two
 * words per ray it holds the SORT_MAX_BINS totals and starts and a cell count per chunk. The host
 * zeroes the totals before the first sort. Needs bindings.glsl included first.
 */
#ifndef VKRT_RAY_SORT_GLSL
#define VKRT_RAY_SORT_GLSL

/* Cells per side of the direction map (2 to 16); the host sets it. */
layout(constant_id = 8) const uint SORT_CELLS = 8u;

/* Rays per workgroup of sort_count and sort_scatter: one place per cell and chunk to store, and
 * chunks long enough that a cell's share of one fills subgroups. Chunks of 1024 with one atomic
 * per subgroup and cell (keys matched by ballots) measured 8-12% slower on an H200
 * (bench/results/issue8-h200-sort/sort2), so the atomics stay plain. */
const uint SORT_CHUNK = 4096u;

/* The most cells (16 x 16); sort_scan's workgroup has one invocation per cell. */
const uint SORT_MAX_BINS = 256u;

/* Where things live in the scratch words. */
const uint SORT_TOTALS = 0u;                  /* rays per cell */
const uint SORT_STARTS = SORT_MAX_BINS;       /* each cell's first slot */
const uint SORT_PLACES = 2u * SORT_MAX_BINS;  /* chunk c's place in cell b at c * cells + b */

layout(std430, set = 0, binding = 15) buffer SortScratch { uint sort_words[]; };

uint sort_cells()
{
    return SORT_CELLS * SORT_CELLS;
}

/* The workgroup's chunk: gl_WorkGroupID folded as invocation_index() folds invocations. */
uint sort_chunk()
{
    return gl_WorkGroupID.x + gl_WorkGroupID.y * gl_NumWorkGroups.x;
}

/* The cell of direction d: the octahedron |x| + |y| + |z| = 1, its lower half folded out over
 * the corners of the upper half's square (Engelhardt and Dachsbacher 2008), cut into
 * SORT_CELLS x SORT_CELLS cells of about equal solid angle. */
uint sort_key(vec3 d)
{
    vec2 p = d.xy / (abs(d.x) + abs(d.y) + abs(d.z));
    if (d.z < 0.0)
        p = (1.0 - abs(p.yx)) * vec2(p.x < 0.0 ? -1.0 : 1.0, p.y < 0.0 ? -1.0 : 1.0);
    uvec2 c = uvec2(clamp((p * 0.5 + 0.5) * float(SORT_CELLS), vec2(0.0), vec2(SORT_CELLS - 1u)));
    return c.y * SORT_CELLS + c.x;
}

#endif
