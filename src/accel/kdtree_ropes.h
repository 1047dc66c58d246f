/*
 * kdtree_ropes.h: ropes for a kd-tree (Popov, Günther, Seidel and Slusallek, "Stackless kd-tree
 * traversal for high performance GPU ray tracing", Eurographics 2007): for each leaf its box and,
 * across each of its six faces, the node on the other side, so that a walk leaves a leaf through
 * its exit face and descends from that node, without a stack.
 */
#ifndef VKRT_KDTREE_ROPES_H
#define VKRT_KDTREE_ROPES_H

#include <stdbool.h>
#include <stdint.h>

#include "../error.h"
#include "kdtree.h"

/* A rope that leads nowhere: the face is on the scene's box. */
#define KD_NO_ROPE 0xFFFFFFFFu

/* The 16-byte texels a leaf's record takes on the GPU, after the nodes (glsl/lib/
 * traverse_kdtree.glsl reads them). */
#define KD_ROPE_TEXELS 3u

/* One leaf's record, 48 bytes: its box, and rope[2 axis + 0] across its low face on that axis,
 * rope[2 axis + 1] across its high face (a node index, or KD_NO_ROPE). */
typedef struct kd_rope_leaf {
    float lo[3], hi[3];
    uint32_t rope[6];
} kd_rope_leaf;

/* The records of t's leaves, in depth-first order (malloc'd, t->leaf_count of them). Each rope is
 * pushed down to the smallest node that still covers the whole face (Popov's optimisation).
 * Each leaf node's `split` is overwritten by the bits of t->node_count + KD_ROPE_TEXELS i, i its
 * record: where the GPU finds it when the records follow the nodes (the stack walk never reads a
 * leaf's split). On failure returns NULL with err set. */
kd_rope_leaf *kdtree_ropes_build(kdtree *t, vkrt_error *err);

#endif
