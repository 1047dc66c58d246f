/*
 * bvh.h: a bounding volume hierarchy over triangles, built on the CPU with the binned surface
 * area heuristic, flattened into 32-byte nodes that the kernels walk as they are.
 */
#ifndef VKRT_BVH_H
#define VKRT_BVH_H

#include <stdbool.h>
#include <stdint.h>

#include "../error.h"

/* One node, 32 bytes, the layout the kernels read (glsl/shared.h BvhNode has the same bytes).
 * count == 0: an inner node whose two children are nodes[left_first] and nodes[left_first + 1]
 * (siblings are adjacent, so one index serves both). Sibling pairs lie in the depth-first order
 * (left before right) of their parents: the children of the k-th inner node in that order are
 * nodes 2k + 1 and 2k + 2 (bvh_pairs.c relies on it). count > 0: a leaf holding triangles
 * left_first .. left_first + count - 1 of the BVH's triangle order (prim_order). With spatial
 * splits a leaf's box bounds the parts of its triangles that lie in it, not whole triangles. */
typedef struct bvh_node {
    float lo[3];
    uint32_t left_first;
    float hi[3];
    uint32_t count;
} bvh_node;

/* What bvh_build_desc's zero fields mean. */
#define BVH_DEFAULT_MAX_LEAF 8u
#define BVH_DEFAULT_TRAVERSAL_COST 1.0f

typedef struct bvh_build_desc {
    uint32_t max_leaf_size;   /* a node with more triangles is always split; 0: 8 */
    uint32_t bins;            /* SAH bins per axis; 0: 16 */
    uint32_t threads;         /* build threads; 0: one per online core, up to 16 */
    float traversal_cost;     /* SAH cost of visiting a node, relative to one triangle test; 0: 1 */
    float spatial_budget;     /* spatial splits (an SBVH, bvh_spatial.h) may add up to this share
                                 of the triangles as duplicate references (0.3: +30%), at most
                                 BVH_MAX_SPATIAL_BUDGET; 0: none, a plain binned-SAH tree */
} bvh_build_desc;

/* The build's stages, in the order they run (bvh.c's header comment describes them). */
typedef enum bvh_stage {
    BVH_STAGE_REFS,     /* allocation and the triangles' reference records */
    BVH_STAGE_TOP,      /* the top levels, split by all threads together */
    BVH_STAGE_SUBTREES, /* the pool of jobs: the rest of the tree */
    BVH_STAGE_STITCH,   /* the jobs stitched into one node array, prim_order */
    BVH_STAGE_FINISH,   /* scratch freed, the tree's SAH cost */
    BVH_STAGE_COUNT
} bvh_stage;

/* One stage's wall-clock time and the processor time of the whole process during it (all
 * threads): their ratio says how many cores the stage kept busy. */
typedef struct bvh_stage_time {
    double wall_ms, cpu_ms;
} bvh_stage_time;

/* The largest spatial_budget a build takes: a budget this large is not used up by the scenes'
 * spatial splits, and the GPU's leaf references address at most 2^27 triangles. */
#define BVH_MAX_SPATIAL_BUDGET 1.0f

typedef struct bvh {
    bvh_node *nodes;          /* nodes[0] is the root */
    uint32_t node_count;
    uint32_t *prim_order;     /* prim_order[i]: the original index of the i-th triangle in BVH order;
                                 with spatial splits a triangle may appear more than once */
    uint32_t prim_count;      /* references in leaves: triangle_count, or more with spatial splits */
    uint32_t triangle_count;  /* the triangles the tree was built over */
    uint32_t leaf_count;
    uint32_t max_depth;       /* of the deepest leaf; the root has depth 0 */
    uint32_t spatial_splits;  /* nodes cut by a plane (spatial splits); with none the tree is the
                                 one a build without a spatial budget makes, byte for byte */
    float sah_cost;           /* SAH cost of the whole tree, relative to the root's area */
    double build_ms;          /* wall-clock build time */
    bvh_stage_time stages[BVH_STAGE_COUNT];
} bvh;

/* A leaf as the GPU layouts (bvh_pairs.h, bvh_quads.h) refer to it in one word: the flag,
 * (count - 1) in bits 27-30, the first triangle (in prim_order) in bits 0-26. A child word
 * without the flag is the index of an inner node. glsl/shared.h VKRT_BVH_LEAF is the same flag. */
#define BVH_LEAF_REF 0x80000000u
#define BVH_LEAF_REF_MAX_COUNT 16u
#define BVH_LEAF_REF_MAX_FIRST 0x07FFFFFFu

/* The leaf reference of node n (a leaf), or false with err set when it does not fit. */
bool bvh_leaf_ref(const bvh_node *n, uint32_t *ref, vkrt_error *err);

/* Builds a BVH over triangle_count triangles (positions: 9 floats each, all finite; degenerate
 * triangles are allowed). Uses desc->threads threads. desc may be NULL for all defaults. On
 * failure returns false with err set and *out zeroed. */
bool bvh_build(bvh *out, const float *positions, uint32_t triangle_count,
               const bvh_build_desc *desc, vkrt_error *err);

/* Frees what bvh_build allocated and zeroes *b. Safe on a zeroed struct. */
void bvh_free(bvh *b);

#endif
