/*
 * bvh_pairs.h: the binary BVH re-laid for GPU traversal, one record per inner node holding both
 * children's float boxes (Aila and Laine, "Understanding the Efficiency of Ray Traversal on
 * GPUs", HPG 2009): a traversal step is one 64-byte fetch, where the 32-byte nodes of bvh.h need
 * the parent and then its two children. It is the GPUs' default layout; the 4-wide layout
 * (bvh_quads.h) is the CPU devices'.
 */
#ifndef VKRT_BVH_PAIRS_H
#define VKRT_BVH_PAIRS_H

#include <stdint.h>

#include "../error.h"
#include "bvh.h"

/* One inner node, 64 bytes (glsl/shared.h BvhPair has the same bytes). Child a's box is
 * [x[0], x[1]] x [y[0], y[1]] x [z[0], z[1]], child b's the same with indices 2 and 3, so the
 * kernel computes both slab tests four lanes at a time. ref[k]: child k's record index, or its
 * leaf reference (bvh.h). */
typedef struct bvh_pair {
    float x[4], y[4], z[4];
    uint32_t ref[2];
    uint32_t unused[2];
} bvh_pair;

/* What bvh_pairs_build made. */
typedef struct bvh_pairs {
    bvh_pair *nodes;          /* nodes[0] holds the root's children; depth-first order */
    uint32_t node_count;
} bvh_pairs;

/* Lays b out as pairs, depth first (child a's subtree right after its parent, so the near child
 * of a coherent ray is often the next record). A tree that is one leaf becomes one record with
 * that leaf in both slots (the second test finds no nearer hit). Fails (err set, nothing
 * allocated) on allocation failure or a leaf that does not fit a reference (bvh_leaf_ref). */
bool bvh_pairs_build(const bvh *b, bvh_pairs *out, vkrt_error *err);

/* Frees what bvh_pairs_build allocated and zeroes *p. Safe on a zeroed struct. */
void bvh_pairs_free(bvh_pairs *p);

#endif
