/*
 * renderer_private.h: the renderer's state, shared by the files of src/render that make it up
 * (renderer.h lists them) and by nothing else: its users hold an opaque handle.
 */
#ifndef VKRT_RENDERER_PRIVATE_H
#define VKRT_RENDERER_PRIVATE_H

#include "../../glsl/shared.h"
#include "../gpu/pipeline.h"
#include "material_kernel.h"
#include "renderer.h"

typedef struct renderer_kernels renderer_kernels;

struct vkrt_renderer {
    gpu_context *ctx;
    vkrt_tuning tuning;       /* the device's settings, with the desc's overrides */
    gpu_storage_set set;
    vkrt_accel_gpu accel;     /* the structure, its statistics and the triangle order */
    gpu_pipeline raygen, trace, light, occlusion, count, prepare, shade;
    gpu_pipeline order;       /* where material_order (order.comp) */
    gpu_pipeline adapt, adapt_dispatch; /* with a target error only (renderer_adaptive.c) */
    gpu_buffer rays, rays_b, hits, materials, lights, image, counters, waves, visibility, slots,
        texture_infos;
    /* The per-triangle arrays and the textures' texels, each split over several buffers where
     * one cannot hold it (gpu/array.h); the addresses of split arrays' chunks, as the kernels
     * read them (glsl/shared.h VKRT_SPLIT_*; a minimal buffer when none is split). */
    gpu_array triangles, normals, texcoords, triangle_material, texels;
    gpu_buffer split_addresses;
    bool split;               /* an array is split: the kernels are compiled to read chunks */
    bool material_order;      /* each bounce's hits grouped by shader (glsl/order.comp) */
    gpu_buffer order_buffer;  /* its bins and the grouped order (minimal without it) */
    gpu_buffer emitters;      /* LightInfo, then the alias table over emissive triangles */
    gpu_buffer environment;   /* the environment map's sampling distribution */
    gpu_buffer plastic_tables; /* @roughplastic's coat tables (minimal without one) */
    /* Adaptive sampling's PixelStats, ActivePixels and per-sample luminance (bindings.glsl);
     * minimal buffers without a target error. */
    gpu_buffer pixel_stats, active_pixels, sample_luminance;
    /* --aov: the AOVs the kernels record (VKRT_AOV_* of glsl/shared.h, vkrt_render_desc.aovs)
     * and their planes (binding VKRT_BINDING_AOVS; a minimal buffer without any). */
    uint32_t aovs;
    gpu_buffer aov_planes;
    float target_error;         /* vkrt_render_desc.target_error; 0: uniform sampling */
    vkrt_integrator integrator; /* never auto */
    char integrator_reason[256];
    uint32_t light_sampling;  /* VKRT_SAMPLING_* */
    bool has_cutouts;         /* a material is cut out by a texture (lib/cutout.glsl) */
    bool two_level;           /* instances under a two-level BVH (accel_instanced.h), decided
                                 before the structure is built */
    uint32_t surface_maps;    /* VKRT_MATERIAL_*_MAP of any material (lib/surface_maps.glsl) */
    bool emitter_light;       /* Whitted on a scene with emissive triangles: a point on them is
                                 one more light (lib/emitters.glsl) */
    float clamp;              /* the largest channel of a contribution to a pixel; 0: no limit */
    uint32_t width, height, samples, max_depth;
    uint32_t batch;           /* samples per pixel a sample pass traces (renderer.c) */
    uint32_t triangle_count, light_count, light_words;
    uint32_t capacity, max_capacity; /* rays per ray buffer: now, and the most the device allows */
    float min_importance;
    bool profile;
    uint32_t profile_repeat;  /* timed frames of a profile */
    uint32_t seed;            /* vkrt_render_desc.seed */
    float shutter;            /* vkrt_render_desc.shutter */
    bool has_next;            /* next_camera holds the next frame's camera */
    vkrt_config_camera next_camera;
    vkrt_config_camera camera; /* the frame's camera, for the passes of a moving one */
    bool texel_loads;         /* traversal reads triangles and nodes through the views below */
    VkBufferView triangle_view, node_view; /* texel views of triangles and accel.nodes */
    uint32_t *light_kinds;    /* VKRT_LIGHT_KIND_* per light, kept for the loop budget check */
    char **material_names;    /* per uploaded material, "name (file:line)", for messages */
    uint32_t material_count;
    vkrt_renderer_startup startup; /* the steps of creation, timed */
    renderer_kernels *kernels;     /* compiling, from creation's start to its end */
    uint32_t *material_cutouts;    /* per material, VKRT_CUTOUT_* (renderer_scan_materials) */
};

/* renderer_upload.c: the scene's data in GPU buffers, in the structure's triangle order; mesh
 * (here and below) is the model's triangles in world space (vkrt_model_world). */
bool renderer_upload_geometry(vkrt_renderer *r, const vkrt_mesh *mesh,
                              const vkrt_scene_materials *mats, vkrt_error *err);
bool renderer_upload_materials(vkrt_renderer *r, const vkrt_scene_materials *mats,
                               const vkrt_material_kernel *kernel, vkrt_error *err);
bool renderer_upload_lights(vkrt_renderer *r, const vkrt_config_light *lights, uint32_t count,
                            vkrt_error *err);
/* renderer_plastic.c: the coat tables of the scene's @roughplastic materials (binding
 * VKRT_BINDING_PLASTIC_TABLES; a minimal buffer without one), and where each material's table
 * starts in materials[m].maps.w (-1: none). */
bool renderer_upload_plastic_tables(vkrt_renderer *r, const vkrt_scene_materials *mats,
                                    Material *materials, vkrt_error *err);
/* One coat table: its index, its rows (1: exactly at roughness; more: evenly from 0 to
 * roughness), and where it starts in the floats. */
typedef struct renderer_plastic_table {
    float eta, roughness;
    uint32_t rows, offset;
} renderer_plastic_table;
/* The tables the scene's rough plastics need, before any row is made: the tables, and the rows
 * and floats they take in all. */
typedef struct renderer_plastic_layout {
    renderer_plastic_table *tables;
    uint32_t count, rows, floats;
} renderer_plastic_layout;
/* Lays out the tables (renderer_upload_plastic_tables fills what it lays out) and sets
 * materials[m].maps.w to where material m's starts (-1: none). Pure CPU, for the tests too. */
bool renderer_plastic_layout_make(const vkrt_scene_materials *mats, Material *materials,
                                  renderer_plastic_layout *layout, vkrt_error *err);
void renderer_plastic_layout_free(renderer_plastic_layout *layout);
/* The radiance material m emits as an area light (number 8-10, Ke, for the built-ins that emit it,
 * times the mean of its map_Ke, else 0): what the integrator's choice and the path tracer's light
 * sampling go by. */
void renderer_material_ke(const vkrt_scene_materials *mats, uint32_t m, float ke[3]);
/* The area lights and the sky (binding VKRT_BINDING_EMITTERS and _ENVIRONMENT): the path
 * tracer's, and Whitted's emitter light (r->emitter_light, cleared when every emissive triangle
 * has zero area); otherwise minimal buffers that keep the bindings valid. */
bool renderer_upload_light_sampling(vkrt_renderer *r, const vkrt_scene *scene,
                                    const vkrt_mesh *world, const vkrt_scene_materials *mats,
                                    vkrt_error *err);
/* The texel views of the triangles and the nodes, always made (every trace kernel declares
 * them), and r->texel_loads: the tuning's choice where the views hold the whole arrays (never a
 * split one). */
bool renderer_create_texel_views(vkrt_renderer *r, vkrt_error *err);
/* The split arrays' chunk addresses (binding VKRT_BINDING_SPLIT_ADDRESSES) and r->split. */
bool renderer_upload_split_addresses(vkrt_renderer *r, vkrt_error *err);
/* The shift of array k's chunks (VKRT_SPLIT_*): the kernels' VKRT_SPEC_SPLIT_* constant. */
uint32_t renderer_split_shift(const vkrt_renderer *r, uint32_t k);

/* renderer_buffers.c: the buffers sized by the image and by the rays of a depth. */
uint32_t renderer_max_ray_capacity(const vkrt_renderer *r);
bool renderer_create_frame_buffers(vkrt_renderer *r, vkrt_error *err);
void renderer_destroy_ray_buffers(vkrt_renderer *r);
/* Grows the ray buffers to hold `needed` rays: at least double, never past the device's limit. */
bool renderer_grow_ray_buffers(vkrt_renderer *r, uint64_t needed, vkrt_error *err);
/* Points every binding of the set at its buffer (after creation, and after growth). */
void renderer_bind_all(vkrt_renderer *r);

/* renderer_adaptive.c: the buffers of adaptive sampling (minimal ones without a target error). */
bool renderer_adaptive_create_buffers(vkrt_renderer *r, vkrt_error *err);
void renderer_adaptive_destroy_buffers(vkrt_renderer *r);
/* Records adapt.comp and adapt_dispatch.comp: done is the samples each listed pixel has after the
 * pass just recorded (0: before the first pass of a frame, which lists every pixel), taken the
 * samples that pass gave each (at the start: r->batch, the slots to clear). */
void renderer_adaptive_record_adapt(vkrt_renderer *r, VkCommandBuffer cmd, FrameParams params,
                                    uint32_t done, uint32_t taken);
/* Records raygen over the listed pixels, `taken` samples each (indirect: adapt_dispatch.comp
 * wrote the workgroup counts). */
void renderer_adaptive_record_raygen(vkrt_renderer *r, VkCommandBuffer cmd, FrameParams *params,
                                     uint32_t taken);

/* Renders a frame to the target error, or to the cap: vkrt_renderer_render's work before it
 * reads the image. */
bool renderer_adaptive_render(vkrt_renderer *r, const vkrt_config_camera *camera,
                              uint32_t frame_index, vkrt_frame_stats *stats, vkrt_error *err);

/* renderer_aov.c: the AOV planes, sized for r->aovs (a minimal buffer without any). */
bool renderer_aov_create_buffer(vkrt_renderer *r, vkrt_error *err);

/* What the structure and the uploads decide of the kernels: known after them, predicted before
 * (renderer_data_layout_predict). */
typedef struct renderer_data_layout {
    vkrt_accel_kind kind;
    bool two_level;           /* a two-level BVH over instances (accel_instanced.h) */
    uint32_t bvh_width;       /* the BVH's, else 0 */
    bool texel_loads;         /* r->texel_loads */
    bool emitter_light;       /* r->emitter_light */
    uint32_t split_shift[VKRT_SPLIT_ARRAY_COUNT]; /* per VKRT_SPLIT_* array, 0: one buffer */
} renderer_data_layout;

/* renderer_upload.c: the layout the structure and the uploads made (after them), and the one
 * predicted before them from the structure asked for (accel) and the counts: false where the
 * kind cannot be told before the build (auto weighing the grid). */
void renderer_data_layout_of(const vkrt_renderer *r, renderer_data_layout *layout);
bool renderer_data_layout_predict(const vkrt_renderer *r, const vkrt_accel_desc *accel,
                                  const vkrt_mesh *mesh, const vkrt_scene_materials *mats,
                                  renderer_data_layout *layout);
/* Each material's cut-out (VKRT_CUTOUT_*, into r->material_cutouts), r->has_cutouts and
 * r->surface_maps: what the kernels are compiled for, before anything is uploaded. */
bool renderer_scan_materials(vkrt_renderer *r, const vkrt_scene_materials *mats,
                             vkrt_error *err);

/* renderer_kernels.c: the wave kernels, the material ones from the scene's materials, each
 * compiled on a thread of its own. What they are compiled for besides their sources: */
enum { RENDERER_KERNEL_CONSTANTS = 24 };
typedef struct renderer_kernel_plan {
    bool split;               /* the preamble reads split arrays through device addresses */
    bool adaptive;            /* adapt.comp and adapt_dispatch.comp too (a target error) */
    bool material_order;      /* order.comp too (hits grouped by shader) */
    uint32_t workgroup_size;
    gpu_spec_constant constants[RENDERER_KERNEL_CONSTANTS];
} renderer_kernel_plan;

/* The plan from r's integrator, tuning and materials and the data's layout. */
void renderer_kernel_plan_make(const vkrt_renderer *r, const renderer_data_layout *layout,
                               bool has_normals, bool has_texcoords, bool traversal_stats,
                               renderer_kernel_plan *plan);
/* Starts compiling the kernels of plan on threads (r->kernels); kernel and mats must stay until
 * renderer_kernels_finish or _abandon. False (out of memory) with err set. */
bool renderer_kernels_start(vkrt_renderer *r, const renderer_kernel_plan *plan,
                            const vkrt_material_kernel *kernel, const vkrt_scene_materials *mats,
                            vkrt_error *err);
/* Joins the compiles; where they were for plan, their pipelines become r's, else they are
 * compiled again for plan (*predicted says which). On a compile error, err holds the first
 * kernel's in compile order, and nothing is left. */
bool renderer_kernels_finish(vkrt_renderer *r, const renderer_kernel_plan *plan, bool *predicted,
                             vkrt_error *err);
/* Joins the compiles, if any, and frees what they made (the error paths; destroy). */
void renderer_kernels_abandon(vkrt_renderer *r);
/* Compiles r->occlusion (any-hit trace, only the trace API's) like r->trace, once. */
bool renderer_kernels_compile_occlusion(vkrt_renderer *r, vkrt_error *err);

/* renderer_frame.c: records the closest-hit or any-hit trace of the rays params covers: `count`
 * of them, or with indirect set, the wave of params->wave.y; brute force in triangle blocks. */
void renderer_record_trace(vkrt_renderer *r, VkCommandBuffer cmd, FrameParams *params,
                           bool any_hit, uint32_t count, bool indirect);

#endif
