/*
 * bvh_split.h: one node's split decision in the BVH builder (bvh.c), by the binned surface area
 * heuristic of Wald, "On fast construction of SAH-based bounding volume hierarchies" (IEEE
 * Symposium on Interactive Ray Tracing 2007). Internal to the builder.
 *
 * The centroids of the node's triangle records are binned along the 3 axes over the node's
 * centroid bounds, the bins are swept for the cheapest split, and the records are partitioned in
 * place. The decision depends only on the records and the parameters, never on the thread that
 * makes it, which keeps the build deterministic.
 */
#ifndef VKRT_BVH_SPLIT_H
#define VKRT_BVH_SPLIT_H

#include <stdbool.h>
#include <stdint.h>

#include "bvh_lanes.h"

/* The most bins per axis a build may use: the scratch arrays are this long. */
enum { BVH_SPLIT_MAX_BINS = 256 };

/* The SAH settings of a build: bvh_build_desc's, defaults applied (bvh.h). */
typedef struct bvh_split_params {
    uint32_t max_leaf;    /* a node over this many triangles always splits */
    uint32_t bins;        /* per axis, at most BVH_SPLIT_MAX_BINS */
    float traversal_cost; /* of one node visit, in triangle tests */
} bvh_split_params;

/* One thread's bins, about 30 KiB: one per thread, reused for every node it splits. */
typedef struct bvh_split_scratch {
    aabb bins[3][BVH_SPLIT_MAX_BINS];
    uint32_t counts[3][BVH_SPLIT_MAX_BINS];
    float right_area[BVH_SPLIT_MAX_BINS];
    uint32_t right_count[BVH_SPLIT_MAX_BINS];
} bvh_split_scratch;

/* What one node's split decision says. */
typedef struct bvh_split_result {
    bool split;
    uint32_t mid;          /* left child: [begin, mid), right child: [mid, end) */
    aabb bounds[2];        /* exact bounds of the children */
    aabb cbounds[2];       /* centroid bounds of the children */
} bvh_split_result;

/* Decides whether the node over refs[begin, end), with exact bounds `bounds` and centroid bounds
 * `cbounds`, is a leaf or splits, and on a split reorders refs[begin, end) so that its children
 * are [begin, out->mid) and [out->mid, end), both non-empty, with their bounds in *out. A node of
 * more than p->max_leaf triangles always splits (in the middle of its order when no binned split
 * separates it); a leaf leaves the order of refs as it was. */
void bvh_split_node(const bvh_split_params *p, bvh_split_scratch *s, prim_ref *refs,
                    uint32_t begin, uint32_t end, const aabb *bounds, const aabb *cbounds,
                    bvh_split_result *out);

#endif
