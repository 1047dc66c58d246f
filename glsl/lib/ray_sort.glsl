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

/* Rays per workgroup of sort_count and sort_scatter (4 per invocation): one place per cell and
 * chunk to store. Chunks of 4096 left too few workgroups to hide the memory's latency: the sort
 * of 2M rays took 0.24 ms on an H200. */
const uint SORT_CHUNK = 1024u;

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

/* Per cell, the workgroup's counter: rays of the chunk so far (sort_count) or the next slot
 * (sort_scatter). */
shared uint sort_cell[SORT_MAX_BINS];

#ifdef VKRT_SUBGROUPS
/* Each invocation's atomic result, for the others of its subgroup that share its key. */
shared uint sort_first[SORT_MAX_BINS + 128u];
#endif

/* Adds one to sort_cell[key] for every live invocation and returns what it found there, as if one
 * at a time in invocation order within a subgroup. Must be called by the whole workgroup
 * (uniform control flow: the subgroup operations below rely on it). With subgroup operations,
 * the invocations of a subgroup that share a key add once, by their first: the rays of a chunk
 * fall in few cells, and colliding atomics on one word serialize. Which invocations share a key
 * is found one key bit at a time with ballots, not with a loop over keys, since a loop that
 * lanes leave at different times need not keep the others together (no maximal reconvergence
 * is assumed). */
uint sort_reserve(uint key, bool live)
{
#ifdef VKRT_SUBGROUPS
    uvec4 same = subgroupBallot(live);
    uint bits = findMSB(sort_cells() - 1u) + 1u;
    for (uint b = 0u; b < bits; ++b) {
        bool bit = ((key >> b) & 1u) != 0u;
        uvec4 ones = subgroupBallot(bit);
        same &= bit ? ones : ~ones;
    }
    uint leader = subgroupBallotFindLSB(same);
    uint slot = gl_SubgroupID * gl_SubgroupSize;
    sort_first[slot + gl_SubgroupInvocationID] =
        live && leader == gl_SubgroupInvocationID
            ? atomicAdd(sort_cell[key], subgroupBallotBitCount(same))
            : 0u;
    subgroupMemoryBarrierShared();
    subgroupBarrier();
    uint first = sort_first[slot + leader] + subgroupBallotExclusiveBitCount(same);
    subgroupBarrier(); /* all have read before the next call writes */
    return first;
#else
    return live ? atomicAdd(sort_cell[key], 1u) : 0u;
#endif
}

#endif
