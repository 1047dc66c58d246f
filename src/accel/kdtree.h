/*
 * kdtree.h: a kd-tree over triangles by the surface area heuristic, built on the CPU in
 * O(N log N) from sorted event lists (Wald and Havran, "On building fast kd-trees for ray tracing,
 * and on doing that in O(N log N)", IEEE Symposium on Interactive Ray Tracing 2006), with every
 * triangle clipped to the node's box so that its split candidates are exact ("perfect splits").
 */
#ifndef VKRT_KDTREE_H
#define VKRT_KDTREE_H

#include <stdbool.h>
#include <stdint.h>

#include "../error.h"

/* One node, 16 bytes, the layout the kernels read (glsl/shared.h KdNode has the same bytes).
 * axis 0-2: an inner node split at `split` on that axis, children nodes[a] (below the plane) and
 * nodes[b] (above). axis == KD_LEAF: a leaf whose triangles are refs[a .. a + b - 1]. A triangle
 * that crosses a plane is referenced by the leaves on both sides. Nodes are in depth-first order,
 * the left subtree before the right. */
typedef struct kd_node {
    float split;
    uint32_t axis;
    uint32_t a; /* inner: left child; leaf: first reference */
    uint32_t b; /* inner: right child; leaf: reference count */
} kd_node;

#define KD_LEAF 3u

/* The deepest tree the builder makes: the GPU walk's stack holds one entry per level
 * (glsl/shared.h VKRT_KD_STACK_SIZE is the same number). */
#define KDTREE_MAX_DEPTH 48u

/* What kdtree_build_desc's zero fields mean: the costs of the SAH, C = K_T + K_I (P_L N_L +
 * P_R N_R), multiplied by the empty-space bonus when one side holds nothing. Only K_T / K_I
 * matters to the tree; docs/kdtree.md ("The termination rule") has what other ratios did. */
#define KDTREE_DEFAULT_TRAVERSAL_COST 15.0f
#define KDTREE_DEFAULT_INTERSECTION_COST 20.0f
#define KDTREE_DEFAULT_EMPTY_BONUS 0.8f

typedef struct kdtree_build_desc {
    float traversal_cost;    /* K_T; 0: 15 */
    float intersection_cost; /* K_I; 0: 20 */
    float empty_bonus;       /* lambda, the factor for a split with an empty side; 0: 0.8 */
    uint32_t max_depth;      /* 0: 8 + 1.3 log2 N (Havran), at most KDTREE_MAX_DEPTH */
    uint32_t threads;        /* 0: one per online core, up to 16 */
} kdtree_build_desc;

typedef struct kdtree {
    kd_node *nodes; /* nodes[0] is the root */
    uint32_t node_count;
    uint32_t *refs; /* triangle indices (original order), by leaf */
    uint32_t ref_count;
    float lo[3], hi[3]; /* the root's box: the triangles' bounds */
    uint32_t leaf_count;
    uint32_t empty_leaves;
    uint32_t max_depth; /* of the deepest leaf; the root has depth 0 */
    float sah_cost;     /* the tree's SAH cost relative to the root's area, in units of K_I */
    double build_ms;    /* wall-clock build time */
} kdtree;

/* Builds the tree over triangle_count triangles (positions: 9 floats each, all finite; degenerate
 * triangles are allowed). desc may be NULL for all defaults. On failure returns false with err
 * set and *out zeroed. */
bool kdtree_build(kdtree *out, const float *positions, uint32_t triangle_count,
                  const kdtree_build_desc *desc, vkrt_error *err);

/* Frees what kdtree_build allocated and zeroes *t. Safe on a zeroed struct. */
void kdtree_free(kdtree *t);

#endif
