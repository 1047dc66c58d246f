/*
 * bvh_pairs.h: the BVH re-laid for GPU traversal, one record per inner node holding both
 * children's boxes (Aila and Laine, "Understanding the Efficiency of Ray Traversal on GPUs",
 * HPG 2009). A traversal step then needs one 64-byte fetch, where the 32-byte nodes of bvh.h
 * need the parent and then its two children: two dependent loads per step instead of one.
 */
#ifndef VKRT_BVH_PAIRS_H
#define VKRT_BVH_PAIRS_H

#include <stdint.h>

#include "../error.h"
#include "bvh.h"

/* One inner node, 64 bytes (glsl/shared.h BvhPair has the same bytes). Child a's box is
 * [x[0], x[1]] x [y[0], y[1]] x [z[0], z[1]], child b's the same with indices 2 and 3: the
 * kernel computes both slab tests four lanes at a time. ref[k] is the index of child k's record
 * when count[k] == 0, else the first of its count[k] triangles (in the BVH's triangle order). */
typedef struct bvh_pair {
    float x[4], y[4], z[4];
    uint32_t ref[2];
    uint32_t count[2];
} bvh_pair;

/* Lays b out as pairs, in depth-first order (child a's subtree right after its parent, so the
 * near child of a coherent ray is often the next record). A tree that is a single leaf becomes
 * one record whose children split that leaf in two (both the same triangle when it has one). Returns false with err set on allocation failure; *pairs is
 * malloc'd, *count records. */
bool bvh_pairs_build(const bvh *b, bvh_pair **pairs, uint32_t *count, vkrt_error *err);

#endif
