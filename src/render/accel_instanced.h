/*
 * accel_instanced.h: the two-level BVH of an instanced scene: each mesh that instances use is
 * uploaded once, in its own space, under a bottom-level tree of its own; a top-level tree over
 * the instances' world boxes leads to them (glsl/shared.h Instance says what the kernels read,
 * glsl/lib/traverse_instanced.glsl how they walk it). The per-triangle arrays are then the unique
 * meshes', and a hit is reported in the instanced order that glsl/shared.h describes.
 *
 * Used where instancing pays (vkrt_instancing_pays) or where the flattened scene would not fit;
 * the kd-tree, the grid and brute force take the flattened scene (vkrt_model_world). The
 * structure cache (accel_cache.h) keeps two-level structures as it keeps flat ones.
 */
#ifndef VKRT_ACCEL_INSTANCED_H
#define VKRT_ACCEL_INSTANCED_H

#include <stdbool.h>
#include <stdint.h>

#include "../error.h"
#include "../scene/model.h"
#include "accel_gpu.h"

/* The scene's triangle counts: over all instances (what a flat structure holds), and of the
 * meshes that instances use, each once. */
typedef struct vkrt_instancing_counts {
    uint64_t instanced;
    uint64_t unique;
} vkrt_instancing_counts;

vkrt_instancing_counts vkrt_instancing_count(const vkrt_model *model);

/* Whether the two-level BVH pays for the model: its instances hold at least
 * VKRT_INSTANCING_MIN_RATIO times the triangles of the meshes they use (a scene of one instance,
 * or of meshes each placed once, stays flat). */
#define VKRT_INSTANCING_MIN_RATIO 2u
bool vkrt_instancing_pays(const vkrt_model *model);

/* The meshes that instances use, each once, as one mesh in their own spaces (the upload's
 * source), mesh after mesh in the model's order: positions, normals where any mesh has some (a
 * mesh without gets its geometric normal), texture coordinates where any has some (zeros where
 * one has none), and per triangle the scene material (mesh m's triangle k's at
 * triangle_material[material_first[m] + k]: vkrt_scene_materials' triangle_material and
 * mesh_first). mesh_base[m]: mesh m's first triangle in it, or UINT32_MAX for a mesh no instance
 * uses. */
typedef struct vkrt_unique_meshes {
    vkrt_mesh mesh;
    uint32_t *scene_material;
    uint32_t *mesh_base;
} vkrt_unique_meshes;

/* Makes u for model; false with err set (and u zeroed) when memory runs out or the unique
 * triangles do not fit the GPU's leaf references (2^27). */
bool vkrt_unique_meshes_make(const vkrt_model *model, const uint32_t *triangle_material,
                             const uint32_t *material_first, vkrt_unique_meshes *u,
                             vkrt_error *err);

void vkrt_unique_meshes_free(vkrt_unique_meshes *u);

/* Builds the two-level BVH of model over u, with desc's width, leaf size and node cost (no
 * spatial splits in the bottom-level trees): a's nodes (top level from node 0, then each mesh's
 * tree), its references (the Instance records), its frame (dims.x: the instance count), its
 * triangle order (over u.mesh), its instance map and statistics (kind BVH). Instances whose
 * transform is singular, or whose mesh is empty, are left out: they have no area. False with err
 * set and a zeroed when memory runs out, when the walk's stack could overflow, or when the
 * instanced triangles do not fit 32-bit hit indices. */
bool vkrt_accel_build_instanced(const vkrt_accel_desc *desc, const vkrt_model *model,
                                const vkrt_unique_meshes *u, vkrt_accel_arrays *a,
                                vkrt_error *err);

/* vkrt_accel_build_instanced, then the upload into a (vkrt_accel_gpu_upload); on failure false
 * with err set and nothing left allocated. */
bool vkrt_accel_gpu_create_instanced(vkrt_accel_gpu *a, gpu_context *ctx,
                                     const vkrt_accel_desc *desc, const vkrt_model *model,
                                     const vkrt_unique_meshes *u, vkrt_error *err);

#endif
