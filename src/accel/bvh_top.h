/*
 * bvh_top.h: the top of the BVH, where nodes hold most of the triangles, split by all build
 * threads together (bvh.c uses it; internal to the builder).
 *
 * One call splits a level's big nodes at once: the threads bin slices of every node's records,
 * each node's slices are added up and its split chosen as bvh_split_node chooses it, and the
 * records are partitioned in parallel into the order Hoare's partition (bvh_split.c) leaves, so
 * the tree is the one the serial build makes, byte for byte.
 */
#ifndef VKRT_BVH_TOP_H
#define VKRT_BVH_TOP_H

#include <stdbool.h>
#include <stdint.h>

#include "bvh_split.h"

/* One node to split: refs[begin, end), its exact bounds and centroid bounds. */
typedef struct bvh_top_node {
    uint32_t begin, end;
    aabb bounds, cbounds;
} bvh_top_node;

/* Splits each of nodes[0, count) (disjoint ranges of refs) as bvh_split_node would, writing
 * out[i] and reordering refs, with `threads` threads (1 .. BVH_MAX_THREADS). False only when out
 * of memory, with refs and out as they were or as the split left them (the caller then splits
 * the nodes itself). */
bool bvh_top_split(const bvh_split_params *p, prim_ref *refs, const bvh_top_node *nodes,
                   uint32_t count, uint32_t threads, bvh_split_result *out);

#endif
