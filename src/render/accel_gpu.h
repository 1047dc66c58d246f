/*
 * accel_gpu.h: the chosen acceleration structure, built on the CPU and uploaded for the kernels.
 *
 * Owns the three buffers of bindings 9-11 (grid frame or kd-tree box, BVH or kd-tree nodes or
 * grid cell starts, grid or kd-tree references; the last two split where one buffer cannot hold
 * them, gpu/array.h) and the triangle order: a BVH stores its triangles
 * in leaf order, so every per-triangle array the kernels read is uploaded in that order, and
 * prim_order maps back. With spatial splits a triangle sits in several leaves: it is uploaded
 * once per leaf (its record, material and attributes copied), so the kernels read leaves as
 * ranges as before.
 */
#ifndef VKRT_ACCEL_GPU_H
#define VKRT_ACCEL_GPU_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "../../glsl/shared.h"
#include "../accel/choose.h"
#include "../error.h"
#include "../gpu/array.h"
#include "../gpu/buffer.h"
#include "../gpu/context.h"

typedef struct vkrt_accel_stats {
    vkrt_accel_kind kind;       /* what was built (never auto) */
    char reason[384];           /* why: the auto rule's sentence, or "asked for" */
    uint32_t triangles;         /* the scene's triangles it was built over */
    double build_ms;            /* CPU build time */
    double choose_ms;           /* time to decide (the grid built for auto's statistics) */
    size_t bytes;               /* GPU memory of the structure, triangles not counted */
    uint32_t nodes;             /* BVH or kd-tree nodes, or grid cells */
    uint32_t leaves;            /* BVH or kd-tree leaves, or occupied grid cells */
    double triangles_per_leaf;  /* mean triangles per BVH leaf, non-empty kd-tree leaf or
                                   occupied grid cell */
    uint32_t grid_dims[3];
    uint32_t max_cell_refs;     /* grid: the fullest cell's triangles */
    uint32_t max_depth;         /* BVH, of its GPU layout; kd-tree */
    uint32_t bvh_width;         /* BVH: children per GPU node, 2 or 4 */
    float sah_cost;             /* BVH; kd-tree (in units of a triangle test) */
    float kd_traversal_cost;    /* kd-tree: the build's K_T / K_I */
    uint32_t references;        /* BVH, kd-tree: triangle references in its leaves (a BVH's are the
                                   scene's triangles, or more with spatial splits: the uploaded
                                   triangle count) */
    uint32_t empty_leaves;      /* kd-tree */
    uint32_t bvh_max_leaf;      /* BVH: the build's largest leaf */
    float bvh_traversal_cost;   /* BVH: the build's SAH cost of a node against a triangle */
    bool from_cache;            /* read from the structure cache (accel_cache.h): build_ms is the
                                   time of reading it, choose_ms 0 */
    /* A two-level BVH (accel_instanced.h): triangles, references and triangles_per_leaf are then
     * its unique meshes', sah_cost the top level's, max_depth the deepest top-level path plus
     * the deepest mesh tree. */
    bool two_level;
    uint32_t instances;          /* instances in the top level */
    uint32_t meshes;             /* unique meshes with a tree of their own */
    uint64_t instanced_triangles; /* triangles over all instances: what a flat structure holds */
} vkrt_accel_stats;

/* How a two-level BVH's hits map back to the model (accel_instanced.h builds it): the
 * structure's instances in the top-level tree's leaf order, each with its first triangle in the
 * instanced order (glsl/shared.h Instance: ascending), its mesh's first uploaded triangle, and its
 * first triangle in vkrt_model_world's order (instance after instance of the model). count 0: the
 * structure is one flat tree. */
typedef struct vkrt_instance_map {
    uint32_t count;
    uint32_t *first;
    uint32_t *mesh_base;
    uint64_t *flat_first;
} vkrt_instance_map;

typedef struct vkrt_accel_gpu {
    gpu_buffer info;            /* GridInfo; for other kinds a zeroed one keeps the binding valid */
    gpu_array nodes;            /* BvhPair[] or BvhQuad[], KdNode[], or grid cell starts */
    gpu_array refs;             /* grid or kd-tree references; for other kinds a minimal buffer,
                                   unread */
    uint32_t *prim_order;       /* NULL for identity order; else prim_order[i] = original index */
    uint32_t triangle_count;    /* triangles uploaded: the scene's, or more with spatial splits;
                                   a two-level BVH's: its unique meshes' */
    vkrt_instance_map instances; /* a two-level BVH's instances; count 0 for one flat tree */
    vkrt_accel_stats stats;
} vkrt_accel_gpu;

/* What to build, as the tuning resolved it (tuning.h) for the device. */
typedef struct vkrt_accel_desc {
    vkrt_accel_kind kind;     /* auto (0) chooses from the scene */
    float grid_density;       /* cells per triangle; 0: the grid's default */
    uint32_t bvh_width;       /* GPU layout: 2 (bvh_pairs.h) or 4 (bvh_quads.h) */
    uint32_t bvh_max_leaf;    /* bvh_build_desc.max_leaf_size, at most 16 (the GPU's leaf
                                 references); 0: bvh.h's default */
    float bvh_traversal_cost; /* bvh_build_desc.traversal_cost; 0: bvh.h's default */
    float bvh_spatial_budget; /* bvh_build_desc.spatial_budget of a tree with spatial splits;
                                 0: accel_gpu.c's default */
    float kd_traversal_cost;  /* the kd-tree's K_T / K_I; 0: kdtree.h's default */
    bool grid_competes;       /* auto weighs the grid against the BVH (vkrt_tuning) */
    bool kdtree_competes;     /* auto takes the kd-tree for scenes it builds fast (vkrt_tuning) */
    vkrt_bvh_splits bvh_splits; /* auto (0): both trees built (up to a size; the plain one only
                                   where the split one took a spatial split), the spatial
                                   splits' kept when its SAH cost is lower by a margin */
    const char *source;       /* what the positions came from (the OBJ's path), or NULL: the
                                 structure cache keeps one entry per source and settings
                                 (accel_cache.h); the structure never depends on it */
} vkrt_accel_desc;

/* A structure built on the CPU in the form the upload takes (and the structure cache keeps,
 * accel_cache.h): the frame of binding 9 (a grid's, the kd-tree's box, or zeroed), the nodes of
 * binding 10 (node_count records of node_size bytes: BvhPair, BvhQuad, KdNode, or a grid's cell
 * starts), the references of binding 11, the triangle order (NULL for the scene's own) and the
 * statistics. */
typedef struct vkrt_accel_arrays {
    GridInfo info;
    void *nodes;
    size_t node_size, node_count;
    uint32_t *refs;
    size_t ref_count;
    uint32_t *prim_order;
    uint32_t triangle_count; /* triangles uploaded: the scene's, or more with spatial splits */
    vkrt_instance_map instances; /* a two-level BVH's (accel_instanced.h), else zeroed */
    vkrt_accel_stats stats;
} vkrt_accel_arrays;

/* Builds the structure desc asks for over positions (9 floats per triangle) on the CPU, without
 * the cache; a brute-force walk has no arrays. On failure returns false with err set and *a
 * zeroed. */
bool vkrt_accel_build(const vkrt_accel_desc *desc, const float *positions,
                      uint32_t triangle_count, vkrt_accel_arrays *a, vkrt_error *err);

/* Frees the arrays and zeroes *a. Safe on a zeroed struct. */
void vkrt_accel_arrays_free(vkrt_accel_arrays *a);

/* A binary BVH laid out in the GPU's nodes of width 2 (BvhPair) or 4 (BvhQuad): the nodes
 * (malloc'd, count of node_size bytes), the depth of the layout and the deepest stack a walk
 * needs. */
typedef struct vkrt_bvh_layout {
    void *nodes;
    uint32_t count, depth, stack;
    size_t bytes, node_size;
} vkrt_bvh_layout;

struct bvh;
/* Lays b out in width-wide nodes; false with err set (nothing allocated) when memory runs out
 * or a leaf does not fit a reference. */
bool vkrt_bvh_lay_out(const struct bvh *b, uint32_t width, vkrt_bvh_layout *out, vkrt_error *err);

/* Uploads arr into a (zeroed first), taking its triangle order, instance map and statistics;
 * on failure false with err set and a destroyed. */
bool vkrt_accel_gpu_upload(vkrt_accel_gpu *a, gpu_context *ctx, vkrt_accel_arrays *arr,
                           vkrt_error *err);

/* Takes the structure desc asks for over positions (9 floats per triangle) from the structure
 * cache, or builds it (and stores it there), and uploads it. On failure returns false with err
 * set and nothing left allocated. */
bool vkrt_accel_gpu_create(vkrt_accel_gpu *a, gpu_context *ctx, const vkrt_accel_desc *desc,
                           const float *positions, uint32_t triangle_count, vkrt_error *err);

/* The kind vkrt_accel_gpu_create will build for desc over triangle_count triangles, where that
 * is known before building anything (asked for, or auto's rule needs no grid to choose);
 * VKRT_ACCEL_AUTO where only the build can tell. On a GPU a BVH whose SAH cost turns out far too
 * high may still give way to the kd-tree (choose.h): the renderer then compiles again. */
vkrt_accel_kind vkrt_accel_gpu_predict(const vkrt_accel_desc *desc, uint32_t triangle_count);

/* Frees buffers and the order. Safe on a zeroed struct. */
void vkrt_accel_gpu_destroy(vkrt_accel_gpu *a, gpu_context *ctx);

/* The original index of the triangle stored at position i (i < a->triangle_count): for a
 * two-level BVH, its index in the unique meshes' concatenation (accel_instanced.h). */
uint32_t vkrt_accel_original_triangle(const vkrt_accel_gpu *a, uint32_t i);

/* The original index of a hit's triangle as traversal reports it (Hit.triangle): for one tree
 * vkrt_accel_original_triangle's; for a two-level BVH its index in vkrt_model_world's order
 * (which may pass 32 bits). */
uint64_t vkrt_accel_original_hit(const vkrt_accel_gpu *a, uint32_t hit_triangle);

/* Frees the map's arrays and zeroes it. Safe on a zeroed map. */
void vkrt_instance_map_free(vkrt_instance_map *m);

#endif
