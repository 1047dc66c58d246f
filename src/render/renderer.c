/*
 * renderer.c: scene upload, kernel compilation and frame recording (see renderer.h).
 */
#define _POSIX_C_SOURCE 200809L
#include "renderer.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "../../glsl/shared.h"
#include "../gpu/shader.h"
#include "../gpu/timer.h"
#include "kernel_sources.h"
#include "material_kernel.h"

/* Binding numbers of glsl/lib/bindings.glsl; keep both in the same order. */
enum {
    BINDING_RAYS,
    BINDING_HITS,
    BINDING_TRIANGLES,
    BINDING_NORMALS,
    BINDING_TRIANGLE_MATERIAL,
    BINDING_MATERIALS,
    BINDING_LIGHTS,
    BINDING_IMAGE,
    BINDING_COUNTERS,
    BINDING_GRID_INFO,
    BINDING_ACCEL_NODES,
    BINDING_GRID_REFS,
    BINDING_RAYS_B,
    BINDING_WAVES,
    BINDING_VISIBILITY,
    BINDING_SLOTS,
    BINDING_TEXCOORDS,
    BINDING_TEXTURE_INFOS,
    BINDING_TEXELS,
    BINDING_TRACE_CURSOR,
    BINDING_COUNT,
};

/* The uniform texel buffers after the storage buffers (glsl/lib/bindings.glsl): views of the
 * triangles and of the acceleration structure's nodes. */
enum {
    BINDING_TRIANGLE_TEXELS = BINDING_COUNT,
    BINDING_NODE_TEXELS,
    TEXEL_BINDING_END,
};

/* 64 invocations fill two NVIDIA warps or one AMD wave64 and suit lavapipe's 8-wide SIMD; to be
 * tuned by measurement with the faster traversals. */
static const uint32_t default_workgroup_size = 64;

/* Triangles per brute-force dispatch. Mesa's llvmpipe ends an invocation's loops after 65535
 * iterations in all (glsl/lib/traverse_brute.glsl), so brute force goes in blocks below that. */
static const uint32_t brute_force_block = 32768;

/* A cast ray whose importance (largest channel) falls under this is not traced: it could change
 * its pixel by less than a thousandth of the light that reaches it. */
static const float default_min_importance = 1e-3f;

/* A profile renders its frame back to back after this much GPU time (as src/bench.c does; the
 * H100 needs this long at full load to reach its clocks), at most max_warmup_frames frames, then
 * times default_profile_repeat frames unless the description asks for another number. */
static const double warmup_ms = 300.0;
static const uint32_t max_warmup_frames = 4000;
static const uint32_t default_profile_repeat = 11;

/* VKRT_MAX_CAST of glsl/lib/material_api.glsl: the most rays one hit may cast. */
static const uint32_t max_cast = 64;

/* How the trace kernels take their rays unless asked otherwise (docs/performance.md has the
 * measurements behind it). */
static const vkrt_ray_fetch default_ray_fetch = VKRT_RAY_FETCH_STATIC;

/* The ray buffers may take at most this share of the device's largest memory heap. */
static const uint32_t ray_memory_share = 4;

/* Specialization constant ids shared with glsl/lib/bindings.glsl (0 is the workgroup size). */
enum {
    SPEC_HAS_NORMALS = 1,
    SPEC_ACCEL_KIND = 2,
    SPEC_HAS_TEXCOORDS = 3,
    SPEC_WAVE_WORKGROUP = 4,
    SPEC_TRAVERSAL_STATS = 5,
    SPEC_BVH_WIDTH = 6,
    SPEC_DYNAMIC_FETCH = 7,
    SPEC_SORT_CELLS = 8,
    SPEC_TEXEL_LOADS = 9,
    SPEC_NESTED_WALK = 10,
};

/* The ray sort's constants (glsl/lib/ray_sort.glsl): rays per workgroup of its count and scatter
 * kernels, its most cells (and workgroup size), and the words its totals take in the slot
 * buffer. */
enum { sort_chunk = 4096, sort_max_bins = 256, sort_min_cells = 2, sort_max_cells = 16 };

static bool upload(vkrt_renderer *r, gpu_buffer *buf, const void *data, size_t size,
                   const char *what, vkrt_error *err)
{
    return gpu_buffer_create(r->ctx, buf, size, what, err) &&
           gpu_buffer_upload(r->ctx, buf, data, size, err);
}

static bool upload_geometry(vkrt_renderer *r, const vkrt_mesh *mesh,
                            const vkrt_scene_materials *mats, vkrt_error *err)
{
    uint32_t n = mesh->triangle_count;
    bool want_texcoords = mats->reads_texcoords && mesh->texcoords;
    Triangle *tris = calloc(n, sizeof *tris);
    uint32_t *material = calloc(n, sizeof *material);
    TriangleNormals *normals = mesh->normals ? calloc(n, sizeof *normals) : NULL;
    TriangleTexcoords *texcoords = want_texcoords ? calloc(n, sizeof *texcoords) : NULL;
    bool ok = tris && material && (normals || !mesh->normals) && (texcoords || !want_texcoords);
    if (!ok) {
        vkrt_error_set(err, "out of memory for %u triangles", n);
        goto done;
    }
    for (uint32_t i = 0; i < n; ++i) {
        /* Triangles go up in the structure's order (a BVH's leaf order), attributes with them. */
        uint32_t from = vkrt_accel_original_triangle(&r->accel, i);
        const float *p = mesh->positions + 9 * (size_t)from;
        tris[i].v0 = (vec4){p[0], p[1], p[2], 0};
        tris[i].v1 = (vec4){p[3], p[4], p[5], 0};
        tris[i].v2 = (vec4){p[6], p[7], p[8], 0};
        material[i] = mats->triangle_material[from];
        if (normals) {
            const float *q = mesh->normals + 9 * (size_t)from;
            normals[i].n0 = (vec4){q[0], q[1], q[2], 0};
            normals[i].n1 = (vec4){q[3], q[4], q[5], 0};
            normals[i].n2 = (vec4){q[6], q[7], q[8], 0};
        }
        if (texcoords) {
            const float *t = mesh->texcoords + 6 * (size_t)from;
            texcoords[i].uv01 = (vec4){t[0], t[1], t[2], t[3]};
            texcoords[i].uv2 = (vec4){t[4], t[5], 0, 0};
        }
    }
    ok = upload(r, &r->triangles, tris, n * sizeof *tris, "triangles", err) &&
         upload(r, &r->triangle_material, material, n * sizeof *material, "triangle materials",
                err);
    /* Attributes no kernel will read get a minimal buffer that keeps their binding valid. */
    if (ok)
        ok = normals ? upload(r, &r->normals, normals, n * sizeof *normals, "normals", err)
                     : gpu_buffer_create(r->ctx, &r->normals, 0, "normals", err);
    if (ok)
        ok = texcoords ? upload(r, &r->texcoords, texcoords, n * sizeof *texcoords,
                                "texture coordinates", err)
                       : gpu_buffer_create(r->ctx, &r->texcoords, 0, "texture coordinates", err);
done:
    free(tris);
    free(material);
    free(normals);
    free(texcoords);
    return ok;
}

static bool upload_materials(vkrt_renderer *r, const vkrt_scene_materials *mats,
                             const vkrt_material_kernel *kernel, vkrt_error *err)
{
    Material *materials = calloc(mats->count, sizeof *materials);
    r->material_names = calloc(mats->count, sizeof *r->material_names);
    if (!materials || !r->material_names) {
        free(materials);
        return vkrt_error_set(err, "out of memory");
    }
    r->material_count = mats->count;
    for (uint32_t i = 0; i < mats->count; ++i) {
        const vkrt_scene_material *m = &mats->list[i];
        Material *g = &materials[i];
        for (uint32_t k = 0; k < VKRT_MATERIAL_PARAM_COUNT; ++k)
            (&g->params[k / 4].x)[k % 4] = m->params[k];
        for (uint32_t k = 0; k < VKRT_MATERIAL_TEXTURE_SLOTS; ++k)
            (&g->textures[k / 4].x)[k % 4] = m->textures[k];
        g->info = (uvec4){m->shader,
                          kernel->shader_uses_lights[m->shader] ? VKRT_MATERIAL_USES_LIGHTS : 0,
                          m->texture_count, 0};
        size_t len = strlen(m->name) + strlen(m->referrer) + 8;
        r->material_names[i] = malloc(len);
        if (!r->material_names[i]) {
            free(materials);
            return vkrt_error_set(err, "out of memory");
        }
        snprintf(r->material_names[i], len, "'%s' (%s)", m->name, m->referrer);
    }
    bool ok = upload(r, &r->materials, materials, mats->count * sizeof *materials, "materials",
                     err);
    free(materials);
    const vkrt_texture_set *tex = &mats->textures;
    if (ok && tex->count) {
        ok = upload(r, &r->texture_infos, tex->info, tex->count * sizeof *tex->info,
                    "texture table", err) &&
             upload(r, &r->texels, tex->texels, tex->texel_words * sizeof *tex->texels,
                    "texels (all textures together)", err);
    } else if (ok) {
        ok = gpu_buffer_create(r->ctx, &r->texture_infos, 0, "texture table", err) &&
             gpu_buffer_create(r->ctx, &r->texels, 0, "texels", err);
    }
    return ok;
}

static float radians(float degrees)
{
    return degrees * 3.14159265358979f / 180.0f;
}

static bool upload_lights(vkrt_renderer *r, const vkrt_config *cfg, vkrt_error *err)
{
    r->light_count = cfg->light_count;
    r->light_kinds = calloc(cfg->light_count ? cfg->light_count : 1, sizeof *r->light_kinds);
    if (!r->light_kinds)
        return vkrt_error_set(err, "out of memory");
    Light *lights = calloc(cfg->light_count ? cfg->light_count : 1, sizeof *lights);
    if (!lights)
        return vkrt_error_set(err, "out of memory");
    for (uint32_t i = 0; i < cfg->light_count; ++i) {
        const vkrt_config_light *l = &cfg->lights[i];
        Light *g = &lights[i];
        g->position = (vec4){l->position[0], l->position[1], l->position[2], 0};
        g->direction = (vec4){l->direction[0], l->direction[1], l->direction[2], 0};
        g->colour = (vec4){l->colour[0], l->colour[1], l->colour[2], 0};
        if (l->kind == VKRT_LIGHT_SPOT) {
            /* Mitsuba's spot light: full intensity within beam = 3/4 of the cutoff angle, then a
             * linear fall in angle to zero at the cutoff. */
            float cutoff = radians(l->half_angle_deg);
            g->position.w = cutoff;
            g->direction.w = cosf(cutoff);
            g->colour.w = 0.75f * cutoff;
        }
        static const uint32_t kinds[] = {
            [VKRT_LIGHT_AMBIENT] = VKRT_LIGHT_KIND_AMBIENT,
            [VKRT_LIGHT_DIRECTIONAL] = VKRT_LIGHT_KIND_DIRECTIONAL,
            [VKRT_LIGHT_POINT] = VKRT_LIGHT_KIND_POINT,
            [VKRT_LIGHT_SPOT] = VKRT_LIGHT_KIND_SPOT,
        };
        g->info = (uvec4){kinds[l->kind], 0, 0, 0};
        r->light_kinds[i] = kinds[l->kind];
    }
    bool ok = upload(r, &r->lights, lights, cfg->light_count * sizeof *lights, "lights", err);
    free(lights);
    return ok;
}

/* The most rays a ray buffer may hold: each buffer within maxStorageBufferRange, all the
 * per-ray buffers together within a share of the largest device-local heap. */
static uint32_t max_ray_capacity(const vkrt_renderer *r)
{
    const VkPhysicalDeviceLimits *limits = &r->ctx->properties.limits;
    uint64_t by_range = limits->maxStorageBufferRange / sizeof(Ray);
    uint64_t words = r->light_words ? r->light_words : 1;
    uint64_t by_visibility = limits->maxStorageBufferRange / (4 * words);
    VkDeviceSize heap = 0;
    for (uint32_t i = 0; i < r->ctx->memory.memoryHeapCount; ++i)
        if ((r->ctx->memory.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT) &&
            r->ctx->memory.memoryHeaps[i].size > heap)
            heap = r->ctx->memory.memoryHeaps[i].size;
    uint64_t per_ray = 2 * sizeof(Ray) + sizeof(Hit) + 4 * words + 2 * sizeof(uint32_t);
    uint64_t by_memory = heap / ray_memory_share / per_ray;
    uint64_t cap = by_range < by_visibility ? by_range : by_visibility;
    cap = by_memory < cap ? by_memory : cap;
    return cap > UINT32_MAX / 2 ? UINT32_MAX / 2 : (uint32_t)cap;
}

static void destroy_ray_buffers(vkrt_renderer *r)
{
    gpu_buffer *buffers[] = {&r->rays, &r->rays_b, &r->hits, &r->visibility, &r->slots};
    for (size_t i = 0; i < sizeof buffers / sizeof *buffers; ++i)
        gpu_buffer_destroy(r->ctx, buffers[i]);
}

/* The buffers with one entry per ray of a depth, for r->capacity rays. */
static bool create_ray_buffers(vkrt_renderer *r, vkrt_error *err)
{
    size_t n = r->capacity;
    size_t words = r->light_words ? r->light_words : 1;
    /* Two words per ray, or the ray sort's scratch (glsl/lib/ray_sort.glsl) where it is more:
     * its totals and starts, and a place per cell and chunk. */
    size_t slot_words = n * 2;
    if (r->sort_cells) {
        size_t chunks = (n + sort_chunk - 1) / sort_chunk;
        size_t sort_words = 2 * (size_t)sort_max_bins + chunks * r->sort_cells * r->sort_cells;
        slot_words = slot_words > sort_words ? slot_words : sort_words;
    }
    char what[64];
    snprintf(what, sizeof what, "ray buffer (%zu rays)", n);
    return gpu_buffer_create(r->ctx, &r->rays, n * sizeof(Ray), what, err) &&
           gpu_buffer_create(r->ctx, &r->rays_b, n * sizeof(Ray), what, err) &&
           gpu_buffer_create(r->ctx, &r->hits, n * sizeof(Hit), "hit buffer", err) &&
           gpu_buffer_create(r->ctx, &r->visibility, n * words * sizeof(uint32_t),
                             "light visibility buffer", err) &&
           gpu_buffer_create(r->ctx, &r->slots, slot_words * sizeof(uint32_t), "ray slot buffer",
                             err);
}

static bool create_frame_buffers(vkrt_renderer *r, vkrt_error *err)
{
    size_t pixels = (size_t)r->width * r->height;
    return create_ray_buffers(r, err) &&
           gpu_buffer_create(r->ctx, &r->image, pixels * sizeof(vec4), "image", err) &&
           gpu_buffer_create(r->ctx, &r->counters, sizeof(Counters), "counters", err) &&
           gpu_buffer_create(r->ctx, &r->waves, (r->max_depth + 2) * sizeof(WaveState),
                             "wave buffer", err) &&
           gpu_buffer_create(r->ctx, &r->trace_cursor, (r->max_depth + 2) * sizeof(uint32_t),
                             "trace cursors", err);
}

static void bind_all(vkrt_renderer *r)
{
    const gpu_buffer *bound[BINDING_COUNT] = {
        [BINDING_RAYS] = &r->rays,
        [BINDING_HITS] = &r->hits,
        [BINDING_TRIANGLES] = &r->triangles,
        [BINDING_NORMALS] = &r->normals,
        [BINDING_TRIANGLE_MATERIAL] = &r->triangle_material,
        [BINDING_MATERIALS] = &r->materials,
        [BINDING_LIGHTS] = &r->lights,
        [BINDING_IMAGE] = &r->image,
        [BINDING_COUNTERS] = &r->counters,
        [BINDING_GRID_INFO] = &r->accel.info,
        [BINDING_ACCEL_NODES] = &r->accel.nodes,
        [BINDING_GRID_REFS] = &r->accel.refs,
        [BINDING_RAYS_B] = &r->rays_b,
        [BINDING_WAVES] = &r->waves,
        [BINDING_VISIBILITY] = &r->visibility,
        [BINDING_SLOTS] = &r->slots,
        [BINDING_TEXCOORDS] = &r->texcoords,
        [BINDING_TEXTURE_INFOS] = &r->texture_infos,
        [BINDING_TEXELS] = &r->texels,
        [BINDING_TRACE_CURSOR] = &r->trace_cursor,
    };
    for (uint32_t i = 0; i < BINDING_COUNT; ++i)
        gpu_storage_set_bind(r->ctx, &r->set, i, bound[i]);
    gpu_storage_set_bind_view(r->ctx, &r->set, BINDING_TRIANGLE_TEXELS, r->triangle_view);
    gpu_storage_set_bind_view(r->ctx, &r->set, BINDING_NODE_TEXELS, r->node_view);
}

/* The texel views of the triangles and the nodes, always made (every trace kernel declares them),
 * and whether traversal reads through them (vkrt_loads): asked for, or by default on CPU devices,
 * and only where the views hold the whole buffers. */
static bool create_texel_views(vkrt_renderer *r, vkrt_loads loads, vkrt_error *err)
{
    bool whole_triangles, whole_nodes;
    if (!gpu_buffer_view_create(r->ctx, &r->triangles, &r->triangle_view, &whole_triangles, err) ||
        !gpu_buffer_view_create(r->ctx, &r->accel.nodes, &r->node_view, &whole_nodes, err))
        return false;
    /* Only the BVH's walk reads nodes through a view (the grid's cells stay storage buffers). */
    if (r->accel.stats.kind != VKRT_ACCEL_BVH)
        whole_nodes = true;
    bool cpu = r->ctx->properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
    bool wanted = loads == VKRT_LOADS_TEXEL || (loads == VKRT_LOADS_DEFAULT && cpu);
    if (loads == VKRT_LOADS_TEXEL && !(whole_triangles && whole_nodes))
        return vkrt_error_set(err, "texel loads: the triangles (%zu bytes) or the structure's "
                                   "nodes (%zu) exceed %s's %u texels of a texel buffer",
                              (size_t)r->triangles.size, (size_t)r->accel.nodes.size,
                              r->ctx->properties.deviceName,
                              r->ctx->properties.limits.maxTexelBufferElements);
    r->texel_loads = wanted && whole_triangles && whole_nodes;
    return true;
}

static bool make_pipeline(vkrt_renderer *r, gpu_pipeline *pipe, const char *path,
                          const uint32_t *spirv, size_t words, uint32_t workgroup_size,
                          const gpu_spec_constant *spec, uint32_t spec_count, vkrt_error *err)
{
    return gpu_pipeline_create(r->ctx, pipe, &r->set, spirv, words, workgroup_size, spec,
                               spec_count, path, err);
}

/* What every wave kernel may use beyond core GLSL on this device: subgroup operations (count.comp
 * reserves ray slots with one atomic per subgroup with them, one per ray without; the trace
 * kernels' statistics and dynamic ray fetch need them, and are not built without). */
static const char *kernel_preamble(const gpu_context *ctx)
{
    return ctx->subgroup_arithmetic ? "#extension GL_KHR_shader_subgroup_arithmetic : require\n"
                                      "#extension GL_KHR_shader_subgroup_ballot : require\n"
                                      "#extension GL_KHR_shader_subgroup_vote : require\n"
                                      "#define VKRT_SUBGROUPS 1\n"
                                    : "";
}

static bool create_kernel(vkrt_renderer *r, gpu_pipeline *pipe, const char *path,
                          uint32_t workgroup_size, const gpu_spec_constant *spec,
                          uint32_t spec_count, vkrt_error *err)
{
    gpu_shader_sources sources = {
        .lookup = vkrt_kernel_source_lookup,
        .display_prefix = "glsl/",
        .preamble = kernel_preamble(r->ctx),
    };
    uint32_t *spirv;
    size_t words;
    if (!gpu_shader_compile(&sources, path, &spirv, &words, err))
        return false;
    bool ok = make_pipeline(r, pipe, path, spirv, words, workgroup_size, spec, spec_count, err);
    free(spirv);
    return ok;
}

static bool create_material_kernel(vkrt_renderer *r, gpu_pipeline *pipe, const char *path,
                                   const vkrt_material_kernel *kernel,
                                   const vkrt_scene_materials *mats, uint32_t workgroup_size,
                                   const gpu_spec_constant *spec, uint32_t spec_count,
                                   vkrt_error *err)
{
    uint32_t *spirv;
    size_t words;
    if (!vkrt_material_kernel_compile(kernel, mats, path, kernel_preamble(r->ctx), &spirv, &words,
                                      err))
        return false;
    bool ok = make_pipeline(r, pipe, path, spirv, words, workgroup_size, spec, spec_count, err);
    free(spirv);
    return ok;
}

static uint32_t gpu_accel_kind(vkrt_accel_kind kind)
{
    return kind == VKRT_ACCEL_BVH    ? VKRT_TRAVERSE_BVH
           : kind == VKRT_ACCEL_GRID ? VKRT_TRAVERSE_GRID
                                     : VKRT_TRAVERSE_BRUTE;
}

static bool create_kernels(vkrt_renderer *r, bool has_normals, bool has_texcoords,
                           uint32_t workgroup_size, bool traversal_stats,
                           const vkrt_material_kernel *kernel, const vkrt_scene_materials *mats,
                           vkrt_error *err)
{
    /* Dynamic fetch is written for the 2-wide BVH's walk (glsl/lib/trace_wave.glsl), and for
     * GPUs: one invocation of it walks many rays in one loop, and Mesa's llvmpipe silently ends
     * an invocation's loops after 65,535 iterations in all (see brute_force_block), which left
     * rays untraced there (hits changed from run to run, and one run crashed). */
    vkrt_ray_fetch fetch = r->ray_fetch ? r->ray_fetch : default_ray_fetch;
    r->dynamic_fetch = fetch == VKRT_RAY_FETCH_DYNAMIC && r->accel.stats.kind == VKRT_ACCEL_BVH &&
                       r->accel.stats.bvh_width == 2 && r->ctx->subgroup_arithmetic &&
                       r->ctx->properties.deviceType != VK_PHYSICAL_DEVICE_TYPE_CPU;
    gpu_spec_constant spec[] = {
        {SPEC_HAS_NORMALS, has_normals},
        {SPEC_ACCEL_KIND, gpu_accel_kind(r->accel.stats.kind)},
        {SPEC_HAS_TEXCOORDS, has_texcoords},
        {SPEC_WAVE_WORKGROUP, workgroup_size},
        {SPEC_TRAVERSAL_STATS, traversal_stats},
        {SPEC_BVH_WIDTH, r->accel.stats.bvh_width},
        {SPEC_DYNAMIC_FETCH, r->dynamic_fetch},
        {SPEC_TEXEL_LOADS, r->texel_loads},
        {SPEC_NESTED_WALK, r->nested_walk},
    };
    const uint32_t count = sizeof spec / sizeof *spec;
    gpu_spec_constant sort_spec[] = {{SPEC_SORT_CELLS, r->sort_cells}};
    bool sort_ok = r->sort_cells == 0 ||
                   (create_kernel(r, &r->sort_count, "sort_count.comp", sort_max_bins, sort_spec, 1,
                                  err) &&
                    create_kernel(r, &r->sort_scan, "sort_scan.comp", sort_max_bins, sort_spec, 1,
                                  err) &&
                    create_kernel(r, &r->sort_scatter, "sort_scatter.comp", sort_max_bins,
                                  sort_spec, 1, err));
    return sort_ok &&
           create_kernel(r, &r->raygen, "raygen.comp", workgroup_size, spec, count, err) &&
           create_kernel(r, &r->trace, "trace.comp", workgroup_size, spec, count, err) &&
           create_kernel(r, &r->light, "light.comp", workgroup_size, spec, count, err) &&
           create_kernel(r, &r->occlusion, "occlusion.comp", workgroup_size, spec, count, err) &&
           create_kernel(r, &r->prepare, "prepare.comp", 1, spec, count, err) &&
           create_material_kernel(r, &r->count, "count.comp", kernel, mats, workgroup_size, spec,
                                  count, err) &&
           create_material_kernel(r, &r->shade, "shade.comp", kernel, mats, workgroup_size, spec,
                                  count, err);
}

bool vkrt_renderer_create(vkrt_renderer *r, gpu_context *ctx, const vkrt_scene *scene,
                          const vkrt_render_desc *desc, vkrt_error *err)
{
    memset(r, 0, sizeof *r);
    r->ctx = ctx;
    r->width = desc->width;
    r->height = desc->height;
    r->samples = desc->samples ? desc->samples : 1;
    r->max_depth = desc->max_depth ? desc->max_depth : scene->config.max_depth;
    r->min_importance = desc->min_importance > 0 ? desc->min_importance : default_min_importance;
    r->profile = desc->profile;
    r->ray_fetch = desc->ray_fetch;
    r->nested_walk = desc->walk == VKRT_WALK_NESTED ||
                     (desc->walk == VKRT_WALK_DEFAULT &&
                      ctx->properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU);
    r->sort_cells = desc->sort_cells;
    if (r->sort_cells != 0 && (r->sort_cells < sort_min_cells || r->sort_cells > sort_max_cells))
        return vkrt_error_set(err, "ray sort: %u cells per side, not %d to %d", r->sort_cells,
                              sort_min_cells, sort_max_cells);
    r->profile_repeat = desc->profile_repeat ? desc->profile_repeat : default_profile_repeat;
    r->triangle_count = scene->mesh.triangle_count;
    r->light_words = (scene->config.light_count + 31) / 32;
    uint32_t workgroup_size = desc->workgroup_size ? desc->workgroup_size : default_workgroup_size;

    /* A scene assembled in memory (tests, bench) may come without resolved materials: then every
     * triangle is the default diffuse. */
    const vkrt_scene_materials *mats = &scene->materials;
    vkrt_scene_materials own = {0};
    vkrt_material_kernel kernel = {0};
    bool ok = true;
    if (!mats->list) {
        vkrt_mesh plain = scene->mesh;
        plain.material_count = 0;
        int32_t *none = malloc((plain.triangle_count ? plain.triangle_count : 1) * sizeof *none);
        ok = none != NULL;
        for (uint32_t i = 0; ok && i < plain.triangle_count; ++i)
            none[i] = -1;
        plain.material = none;
        ok = ok && vkrt_scene_materials_resolve(&scene->config, &plain, NULL, &own, err);
        free(none);
        if (!ok && err && !err->msg[0])
            vkrt_error_set(err, "out of memory");
        mats = &own;
    }
    uint64_t pixels = (uint64_t)r->width * r->height;
    r->max_capacity = max_ray_capacity(r);
    if (ok && pixels > r->max_capacity)
        ok = vkrt_error_set(err,
                            "%ux%u needs %llu rays per buffer (%.0f MiB each); %s allows at most "
                            "%u: render a smaller image",
                            r->width, r->height, (unsigned long long)pixels,
                            pixels * sizeof(Ray) / 1048576.0, ctx->properties.deviceName,
                            r->max_capacity);
    r->capacity = desc->ray_capacity > pixels ? desc->ray_capacity : (uint32_t)pixels;
    if (r->capacity > r->max_capacity)
        r->capacity = r->max_capacity;
    bool has_texcoords = mats->reads_texcoords && scene->mesh.texcoords;
    ok = ok &&
         gpu_storage_set_create_texels(ctx, &r->set, BINDING_COUNT,
                                       TEXEL_BINDING_END - BINDING_COUNT, sizeof(FrameParams),
                                       err) &&
         vkrt_accel_gpu_create(&r->accel, ctx,
                               &(vkrt_accel_desc){.kind = desc->accel,
                                                  .grid_density = desc->grid_density,
                                                  .bvh_width = desc->bvh_width,
                                                  .bvh_max_leaf = desc->bvh_max_leaf,
                                                  .bvh_traversal_cost = desc->bvh_traversal_cost,
                                                  .storage_loads =
                                                      desc->loads == VKRT_LOADS_STORAGE},
                               scene->mesh.positions, scene->mesh.triangle_count, err) &&
         vkrt_material_kernel_create(&kernel, mats, ctx->float_atomics, err) &&
         upload_geometry(r, &scene->mesh, mats, err) && create_texel_views(r, desc->loads, err) &&
         upload_materials(r, mats, &kernel, err) && upload_lights(r, &scene->config, err) &&
         create_frame_buffers(r, err) &&
         create_kernels(r, scene->mesh.normals != NULL, has_texcoords, workgroup_size,
                        desc->traversal_stats, &kernel, mats, err);
    vkrt_material_kernel_destroy(&kernel);
    vkrt_scene_materials_free(&own);
    if (!ok) {
        vkrt_renderer_destroy(r);
        return false;
    }
    bind_all(r);
    return true;
}

static void normalize3(float v[3])
{
    float len = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int i = 0; i < 3; ++i)
        v[i] /= len;
}

static void cross3(const float a[3], const float b[3], float out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

/* Camera basis of a right-handed camera looking down -z in its own space: right = forward x up. */
void vkrt_camera_params(const vkrt_config_camera *camera, uint32_t width, uint32_t height,
                        FrameParams *params)
{
    float forward[3] = {camera->look[0] - camera->eye[0], camera->look[1] - camera->eye[1],
                        camera->look[2] - camera->eye[2]};
    normalize3(forward);
    float right[3], up[3];
    cross3(forward, camera->up, right);
    normalize3(right);
    cross3(right, forward, up);
    float tan_half = tanf(radians(camera->fov_deg) * 0.5f);
    float aspect = (float)width / (float)height;
    params->eye = (vec4){camera->eye[0], camera->eye[1], camera->eye[2], 0};
    params->forward = (vec4){forward[0], forward[1], forward[2], 0};
    params->right = (vec4){right[0] * tan_half * aspect, right[1] * tan_half * aspect,
                           right[2] * tan_half * aspect, 0};
    params->up = (vec4){up[0] * tan_half, up[1] * tan_half, up[2] * tan_half, 0};
}

/* llvmpipe's 65535 loop iterations per invocation (see brute_force_block) also bound the light
 * kernel, whose brute-force shadow rays each loop over every triangle: refuse rather than render
 * shadows that silently miss triangles. */
static bool check_loop_budget(const vkrt_renderer *r, vkrt_error *err)
{
    const uint32_t llvmpipe_loop_budget = 65535;
    if (r->accel.stats.kind != VKRT_ACCEL_BRUTE ||
        strncmp(r->ctx->properties.deviceName, "llvmpipe", 8) != 0)
        return true;
    uint64_t shadow_lights = 0;
    for (uint32_t i = 0; i < r->light_count; ++i)
        shadow_lights += r->light_kinds[i] != VKRT_LIGHT_KIND_AMBIENT;
    uint64_t iterations = (uint64_t)r->triangle_count * shadow_lights;
    if (iterations > llvmpipe_loop_budget - r->light_count)
        return vkrt_error_set(err,
                              "brute force with %u triangles and %u shadowing lights needs %llu "
                              "loop iterations per pixel; lavapipe (llvmpipe) stops shaders after "
                              "%u: use accel grid or bvh",
                              r->triangle_count, (unsigned)shadow_lights,
                              (unsigned long long)iterations, llvmpipe_loop_budget);
    return true;
}

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* Records the closest-hit or any-hit trace of the rays params covers: `count` of them, or with
 * indirect set, the wave of params->wave.y; brute force in triangle blocks. */
static void record_trace(vkrt_renderer *r, VkCommandBuffer cmd, FrameParams *params, bool any_hit,
                         uint32_t count, bool indirect)
{
    const gpu_pipeline *pipe = any_hit ? &r->occlusion : &r->trace;
    VkDeviceSize wave_offset = (VkDeviceSize)params->wave.y * sizeof(WaveState);
    uint32_t n = r->triangle_count;
    for (uint32_t first = 0;; first += brute_force_block) {
        bool brute = r->accel.stats.kind == VKRT_ACCEL_BRUTE;
        uint32_t end = !brute || n - first < brute_force_block ? n : first + brute_force_block;
        params->range.x = brute ? first : 0;
        params->range.y = end;
        params->range.z = first > 0;
        if (indirect)
            gpu_dispatch_indirect(cmd, pipe, &r->set, params, &r->waves, wave_offset);
        else
            gpu_dispatch(cmd, pipe, &r->set, params, count);
        if (end >= n)
            break;
    }
    params->range.x = 0;
    params->range.y = n;
    params->range.z = 0;
}

/* Zeroes size bytes of buf from the start, between the compute work before (which may have read
 * or written them) and after it. */
static void record_zero(VkCommandBuffer cmd, const gpu_buffer *buf, VkDeviceSize size)
{
    VkMemoryBarrier before = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
        .srcAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT,
        .dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT,
    };
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                         0, 1, &before, 0, NULL, 0, NULL);
    vkCmdFillBuffer(cmd, buf->buffer, 0, size, 0);
    VkMemoryBarrier after = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
        .srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT,
        .dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT,
    };
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                         0, 1, &after, 0, NULL, 0, NULL);
}

/* Zeroes the trace cursors between traces of vkrt_renderer_trace (a frame's are zeroed with its
 * waves): the previous trace read and wrote them. */
static void record_cursor_reset(vkrt_renderer *r, VkCommandBuffer cmd)
{
    record_zero(cmd, &r->trace_cursor, VK_WHOLE_SIZE);
}

/* With a profile, a timestamp follows every kernel: which frame (of the timed ones), kernel and
 * depth each one closes. */
typedef struct profile_mark {
    uint32_t frame;
    uint8_t depth, kernel;
} profile_mark;

typedef struct frame_profile {
    gpu_timer timer;
    profile_mark *marks;
    uint32_t count;           /* marks so far; timestamp 0 opens the first timed frame */
    uint32_t frame;           /* the timed frame being recorded */
    uint32_t *frame_end;      /* per timed frame, its last timestamp */
} frame_profile;

static void mark(VkCommandBuffer cmd, frame_profile *p, uint32_t depth, uint32_t kernel)
{
    if (!p)
        return;
    p->marks[p->count] = (profile_mark){
        p->frame, (uint8_t)(depth < VKRT_PROFILE_DEPTHS ? depth : VKRT_PROFILE_DEPTHS - 1),
        (uint8_t)kernel};
    gpu_timer_write(cmd, &p->timer, ++p->count);
}

/* Records sample passes [first, end) of one frame. There are no transfer commands: raygen clears
 * the image (pass 0) and resets the wave table, so the passes are dispatches and
 * compute-to-compute barriers only. */
static void record_passes(vkrt_renderer *r, VkCommandBuffer cmd, FrameParams params,
                          uint32_t first, uint32_t end, frame_profile *p)
{
    uint32_t pixels = r->width * r->height;
    for (uint32_t s = first; s < end; ++s) {
        params.image.z = s;
        params.counts.z = pixels;
        params.wave = (uvec4){0, 0, r->max_depth, r->capacity};
        gpu_dispatch(cmd, &r->raygen, &r->set, &params, pixels);
        mark(cmd, p, 0, VKRT_KERNEL_RAYGEN);
        params.counts.z = VKRT_RAYS_OF_WAVE;
        for (uint32_t depth = 0; depth <= r->max_depth; ++depth) {
            params.wave.x = depth & 1;
            params.wave.y = depth;
            VkDeviceSize wave = (VkDeviceSize)depth * sizeof(WaveState);
            record_trace(r, cmd, &params, false, 0, true);
            mark(cmd, p, depth, VKRT_KERNEL_TRACE);
            gpu_dispatch_indirect(cmd, &r->light, &r->set, &params, &r->waves, wave);
            mark(cmd, p, depth, VKRT_KERNEL_LIGHT);
            if (depth < r->max_depth) {
                gpu_dispatch_indirect(cmd, &r->count, &r->set, &params, &r->waves, wave);
                mark(cmd, p, depth, VKRT_KERNEL_COUNT);
                gpu_dispatch(cmd, &r->prepare, &r->set, &params, 1);
                mark(cmd, p, depth, VKRT_KERNEL_PREPARE);
            }
            gpu_dispatch_indirect(cmd, &r->shade, &r->set, &params, &r->waves, wave);
            mark(cmd, p, depth, VKRT_KERNEL_SHADE);
        }
    }
}

static int compare_ms(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The median of n values (sorted in place): the middle one, or the mean of the middle two. */
static double median_ms(double *values, uint32_t n)
{
    qsort(values, n, sizeof *values, compare_ms);
    return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

/* Reads the timestamps of p into stats: per kernel and depth, and for the frame, the median over
 * p's timed frames. */
static bool read_profile(vkrt_renderer *r, frame_profile *p, uint32_t frames,
                         vkrt_frame_stats *stats, vkrt_error *err)
{
    size_t cells = (size_t)VKRT_PROFILE_DEPTHS * VKRT_KERNEL_KINDS;
    double *per_frame = calloc(cells * frames, sizeof *per_frame);
    double *values = calloc(frames, sizeof *values);
    bool ok = per_frame && values;
    if (!ok)
        vkrt_error_set(err, "out of memory for a profile");
    for (uint32_t i = 0; ok && i < p->count; ++i) {
        double ms;
        if (!(ok = gpu_timer_ms(r->ctx, &p->timer, i, i + 1, &ms, err)))
            break;
        const profile_mark *m = &p->marks[i];
        per_frame[m->frame * cells + (size_t)m->depth * VKRT_KERNEL_KINDS + m->kernel] += ms;
    }
    for (size_t c = 0; ok && c < cells; ++c) {
        for (uint32_t f = 0; f < frames; ++f)
            values[f] = per_frame[f * cells + c];
        stats->kernel_ms[c / VKRT_KERNEL_KINDS][c % VKRT_KERNEL_KINDS] = median_ms(values, frames);
    }
    for (uint32_t f = 0; ok && f < frames; ++f)
        ok = gpu_timer_ms(r->ctx, &p->timer, f ? p->frame_end[f - 1] : 0, p->frame_end[f],
                          &values[f], err);
    if (ok)
        stats->frame_ms = median_ms(values, frames);
    free(per_frame);
    free(values);
    return ok;
}

/* Records and runs sample passes [first, end) into the image (cleared first when first is 0);
 * counters hold their statistics afterwards. With a profile (r->profile and stats), the frame is
 * recorded warmups + timed times back to back in one submission (only when first is 0: each
 * repetition then starts from a cleared image, so the picture is the same), with timestamps
 * around every dispatch of the timed ones; stats gets the medians. */
static bool run_passes(vkrt_renderer *r, FrameParams params, uint32_t first, uint32_t end,
                       uint32_t warmups, uint32_t timed, double *seconds, vkrt_frame_stats *stats,
                       vkrt_error *err)
{
    if (!r->profile || !stats || first != 0 || timed == 0) {
        warmups = 0;
        timed = 1;
    }
    frame_profile profile = {0}, *p = NULL;
    if (r->profile && stats) {
        uint32_t marks = timed * (end - first) * (1 + 5 * (r->max_depth + 1));
        profile.marks = calloc(marks, sizeof *profile.marks);
        profile.frame_end = calloc(timed, sizeof *profile.frame_end);
        if (!profile.marks || !profile.frame_end) {
            free(profile.marks);
            free(profile.frame_end);
            return vkrt_error_set(err, "out of memory for a profile");
        }
        if (!gpu_timer_create(r->ctx, &profile.timer, marks + 1, err)) {
            free(profile.marks);
            free(profile.frame_end);
            return false;
        }
        p = &profile;
    }
    VkCommandBuffer cmd;
    if (!gpu_commands_begin(r->ctx, &cmd, err))
        goto fail;
    /* Once per submission, before any timestamp: repetitions add to the counters, but the host
     * reads them only after a single frame. */
    record_zero(cmd, &r->counters, VK_WHOLE_SIZE);
    for (uint32_t i = 0; i < warmups; ++i)
        record_passes(r, cmd, params, first, end, NULL);
    if (p) {
        gpu_timer_reset(cmd, &p->timer);
        gpu_timer_write(cmd, &p->timer, 0);
    }
    for (uint32_t i = 0; i < timed; ++i) {
        record_passes(r, cmd, params, first, end, p);
        if (p) {
            p->frame_end[i] = p->count;
            ++p->frame;
        }
    }
    double start = now_seconds();
    if (!gpu_commands_submit(r->ctx, err))
        goto fail;
    *seconds = now_seconds() - start;
    if (p) {
        memset(stats->kernel_ms, 0, sizeof stats->kernel_ms);
        stats->profiled = true;
        stats->profile_frames = timed;
        stats->profile_warmups = warmups;
        if (!read_profile(r, p, timed, stats, err))
            goto fail;
        gpu_timer_destroy(r->ctx, &p->timer);
        free(p->marks);
        free(p->frame_end);
    }
    return true;
fail:
    if (p) {
        gpu_timer_destroy(r->ctx, &p->timer);
        free(p->marks);
        free(p->frame_end);
    }
    return false;
}

void vkrt_frame_stats_print_profile(FILE *out, const vkrt_frame_stats *stats)
{
    static const char *const names[VKRT_KERNEL_KINDS] = {"raygen", "trace", "light", "count",
                                                          "prepare", "shade"};
    fprintf(out, "vkrt: profile (GPU ms, summed over sample passes; median of %u frame%s back to "
                 "back after %u warm-up frame%s)\n  depth",
            stats->profile_frames, stats->profile_frames == 1 ? "" : "s", stats->profile_warmups,
            stats->profile_warmups == 1 ? "" : "s");
    for (int k = 0; k < VKRT_KERNEL_KINDS; ++k)
        fprintf(out, " %9s", names[k]);
    fprintf(out, "\n");
    double total[VKRT_KERNEL_KINDS] = {0};
    for (int d = 0; d < VKRT_PROFILE_DEPTHS; ++d) {
        double row = 0;
        for (int k = 0; k < VKRT_KERNEL_KINDS; ++k)
            row += stats->kernel_ms[d][k];
        if (row == 0)
            continue;
        fprintf(out, "  %5d", d);
        for (int k = 0; k < VKRT_KERNEL_KINDS; ++k) {
            fprintf(out, " %9.3f", stats->kernel_ms[d][k]);
            total[k] += stats->kernel_ms[d][k];
        }
        fprintf(out, "\n");
    }
    double sum = 0;
    fprintf(out, "  total");
    for (int k = 0; k < VKRT_KERNEL_KINDS; ++k) {
        fprintf(out, " %9.3f", total[k]);
        sum += total[k];
    }
    /* The light kernel is mostly its shadow rays' traversal. */
    double tracing = total[VKRT_KERNEL_TRACE] + total[VKRT_KERNEL_LIGHT];
    fprintf(out, "\n  frame %.3f ms (kernels %.3f); trace + light %.3f ms: the frame costs %.2fx "
                 "its tracing (frame / (trace + light))\n",
            stats->frame_ms, sum, tracing, tracing > 0 ? stats->frame_ms / tracing : 0.0);
}

/* Grows the ray buffers to hold `needed` rays: at least double, never past the device's limit. */
static bool grow_ray_buffers(vkrt_renderer *r, uint64_t needed, vkrt_error *err)
{
    uint64_t capacity = r->capacity;
    while (capacity < needed)
        capacity *= 2;
    if (capacity > r->max_capacity)
        capacity = r->max_capacity;
    destroy_ray_buffers(r);
    r->capacity = (uint32_t)capacity;
    if (!create_ray_buffers(r, err))
        return vkrt_error_prefix(err, "growing the ray buffers to %u rays", r->capacity);
    bind_all(r);
    return true;
}

/* After a timeout or a lost device, the likeliest culprit is a material shader that never ends:
 * the message lists the scene's materials (the GPU cannot say which invocation hung). */
static void name_suspects(const vkrt_renderer *r, vkrt_error *err)
{
    char list[600] = "";
    size_t used = 0;
    for (uint32_t i = 0; i < r->material_count && used + 2 < sizeof list; ++i) {
        int n = snprintf(list + used, sizeof list - used, "%s%s", i ? ", " : "",
                         r->material_names[i]);
        if (n < 0 || (size_t)n >= sizeof list - used)
            break;
        used += (size_t)n;
    }
    size_t len = strlen(err->msg);
    snprintf(err->msg + len, sizeof err->msg - len, "; the scene's materials: %s", list);
}

bool vkrt_renderer_add_samples(vkrt_renderer *r, const vkrt_config_camera *camera,
                               uint32_t frame_index, uint32_t first, uint32_t count,
                               vkrt_frame_stats *stats, vkrt_error *err)
{
    uint32_t pixels = r->width * r->height;
    if (first >= r->samples || count > r->samples - first)
        return vkrt_error_set(err, "sample passes %u..%u are outside the %u of the renderer", first,
                              first + count, r->samples);
    if (!check_loop_budget(r, err))
        return false;
    FrameParams params = {0};
    vkrt_camera_params(camera, r->width, r->height, &params);
    params.eye.w = r->min_importance;
    params.image = (uvec4){r->width, r->height, 0, r->samples};
    params.counts = (uvec4){r->triangle_count, r->light_count, pixels, frame_index};
    params.range = (uvec4){0, r->triangle_count, 0, r->light_words};

    Counters counters;
    double seconds = 0;
    uint32_t attempts = 0, start = first;
    for (;;) {
        ++attempts;
        if (!run_passes(r, params, start, first + count, 0, 1, &seconds, stats, err) ||
            !gpu_buffer_download(r->ctx, &r->counters, &counters, sizeof counters, err)) {
            if (r->ctx->lost)
                name_suspects(r, err);
            return vkrt_error_prefix(err, "rendering frame %u", frame_index);
        }
        uint32_t m = counters.overcast_material - 1;
        const char *culprit = m < r->material_count ? r->material_names[m] : "?";
        if (counters.overcount)
            return vkrt_error_set(err,
                                  "material %s: count_rays asked for more than %u rays at %u hits; "
                                  "one hit may cast at most %u",
                                  culprit, max_cast, counters.overcount, max_cast);
        if (counters.overcast)
            return vkrt_error_set(err,
                                  "material %s cast more rays than its count_rays returned (%u "
                                  "rays not traced): shade may cast at most as many rays as "
                                  "count_rays returned for the same hit",
                                  culprit, counters.overcast);
        /* A wave asked for more rays than the buffers hold: those passes are incomplete. Grow
         * and render every pass of the image again from the first (earlier calls' passes are in
         * the image too, and cannot be taken out); the random streams make the new picture the
         * one large buffers would have given. */
        if (counters.max_wave <= r->capacity || r->capacity >= r->max_capacity)
            break;
        if (!grow_ray_buffers(r, counters.max_wave, err))
            return false;
        start = 0;
    }
    /* The profile of a cold GPU measures its clocks' climb (on the H100 the same frame took 7
     * ms right after another and 30 ms after the host wrote a PNG): render the frame again, after
     * warmup_ms of GPU work back to back with it, and take the median of several. The first
     * render sizes the warm-up. */
    if (r->profile && stats && first == 0) {
        double probe = stats->frame_ms;
        uint32_t warmups = probe > 0 ? (uint32_t)fmin(max_warmup_frames, ceil(warmup_ms / probe))
                                     : 1;
        double ignored;
        if (!run_passes(r, params, 0, count, warmups, r->profile_repeat, &ignored, stats, err)) {
            if (r->ctx->lost)
                name_suspects(r, err);
            return vkrt_error_prefix(err, "profiling frame %u", frame_index);
        }
    }
    if (stats) {
        stats->seconds = seconds;
        stats->primary_rays = (uint64_t)pixels * (first + count - start);
        stats->shadow_rays = counters.shadow_rays;
        stats->secondary_rays = counters.secondary_rays;
        stats->attempts = attempts;
        stats->ray_capacity = r->capacity;
        stats->dropped_rays = counters.max_wave > r->capacity ? counters.max_wave - r->capacity : 0;
        stats->nonfinite = counters.nonfinite;
        stats->profiled = r->profile;
    }
    return true;
}

bool vkrt_renderer_read_image(vkrt_renderer *r, uint32_t passes, float *rgb, vkrt_error *err)
{
    uint32_t pixels = r->width * r->height;
    vec4 *image = malloc((size_t)pixels * sizeof *image);
    if (!image)
        return vkrt_error_set(err, "out of memory reading back %u pixels", pixels);
    bool ok = gpu_buffer_download(r->ctx, &r->image, image, (size_t)pixels * sizeof *image, err);
    if (ok) {
        float scale = 1.0f / (float)(passes ? passes : 1);
        for (uint32_t i = 0; i < pixels; ++i) {
            rgb[3 * (size_t)i + 0] = image[i].x * scale;
            rgb[3 * (size_t)i + 1] = image[i].y * scale;
            rgb[3 * (size_t)i + 2] = image[i].z * scale;
        }
    }
    free(image);
    return ok;
}

bool vkrt_renderer_render(vkrt_renderer *r, const vkrt_config_camera *camera, uint32_t frame_index,
                          float *rgb, vkrt_frame_stats *stats, vkrt_error *err)
{
    return vkrt_renderer_add_samples(r, camera, frame_index, 0, r->samples, stats, err) &&
           vkrt_renderer_read_image(r, r->samples, rgb, err);
}

/* The ray sort's three passes over count rays: RayBufferB into RayBuffer (glsl/lib/ray_sort.glsl). */
static void record_sort(vkrt_renderer *r, VkCommandBuffer cmd, FrameParams *params, uint32_t count)
{
    uint32_t chunks = (count + sort_chunk - 1) / sort_chunk;
    gpu_dispatch(cmd, &r->sort_count, &r->set, params, chunks * sort_max_bins);
    gpu_dispatch(cmd, &r->sort_scan, &r->set, params, sort_max_bins);
    gpu_dispatch(cmd, &r->sort_scatter, &r->set, params, chunks * sort_max_bins);
}

/* Zeroes the sort's cell totals (its scan zeroes them after each sort). */
static void record_sort_reset(vkrt_renderer *r, VkCommandBuffer cmd)
{
    record_zero(cmd, &r->slots, sort_max_bins * sizeof(uint32_t));
}

/* vkrt_renderer_trace and vkrt_renderer_trace_sorted: with sort, the rays go to RayBufferB and
 * each run sorts them into RayBuffer first; with trace false nothing is traced. */
static bool trace_rays(vkrt_renderer *r, const Ray *rays, uint32_t count, bool any_hit, bool sort,
                       bool trace, Hit *hits, Ray *sorted, uint32_t repeats, double *gpu_ms,
                       vkrt_error *err)
{
    size_t capacity = r->capacity;
    if (count > capacity)
        return vkrt_error_set(err, "%u rays exceed the renderer's %zu", count, capacity);
    if (sort && r->sort_cells == 0)
        return vkrt_error_set(err, "ray sort: the renderer was made without it (sort_cells 0)");
    if (repeats == 0)
        repeats = 1;
    FrameParams params = {0};
    params.counts = (uvec4){r->triangle_count, r->light_count, count, 0};
    params.wave = (uvec4){0, 0, 0, r->capacity};
    gpu_timer timer = {0};
    if (!gpu_buffer_upload(r->ctx, sort ? &r->rays_b : &r->rays, rays, count * sizeof *rays, err) ||
        (gpu_ms && !gpu_timer_create(r->ctx, &timer, repeats + 1, err)))
        return false;
    VkCommandBuffer cmd;
    bool ok = gpu_commands_begin(r->ctx, &cmd, err);
    if (ok) {
        if (sort)
            record_sort_reset(r, cmd);
        /* Back to back in one submission, so the GPU never idles between repeats (its clocks
         * would fall, and each timing would measure the climb back). */
        if (gpu_ms) {
            gpu_timer_reset(cmd, &timer);
            gpu_timer_write(cmd, &timer, 0);
        }
        for (uint32_t i = 0; i < repeats; ++i) {
            if (sort)
                record_sort(r, cmd, &params, count);
            if (r->dynamic_fetch && trace)
                record_cursor_reset(r, cmd);
            if (trace)
                record_trace(r, cmd, &params, any_hit, count, false);
            if (gpu_ms)
                gpu_timer_write(cmd, &timer, i + 1);
        }
        ok = gpu_commands_submit(r->ctx, err);
        for (uint32_t i = 0; ok && gpu_ms && i < repeats; ++i)
            ok = gpu_timer_ms(r->ctx, &timer, i, i + 1, &gpu_ms[i], err);
        ok = ok && (!trace || gpu_buffer_download(r->ctx, &r->hits, hits, count * sizeof *hits, err)) &&
             (!sorted || gpu_buffer_download(r->ctx, &r->rays, sorted, count * sizeof *sorted, err));
    }
    gpu_timer_destroy(r->ctx, &timer);
    if (!ok)
        return false;
    if (trace && !any_hit)
        for (uint32_t i = 0; i < count; ++i)
            if (hits[i].triangle != VKRT_NO_HIT)
                hits[i].triangle = vkrt_accel_original_triangle(&r->accel, hits[i].triangle);
    return true;
}

bool vkrt_renderer_trace(vkrt_renderer *r, const Ray *rays, uint32_t count, bool any_hit,
                         Hit *hits, uint32_t repeats, double *gpu_ms, vkrt_error *err)
{
    return trace_rays(r, rays, count, any_hit, false, true, hits, NULL, repeats, gpu_ms, err);
}

bool vkrt_renderer_trace_sorted(vkrt_renderer *r, const Ray *rays, uint32_t count, bool trace,
                                Hit *hits, Ray *sorted, uint32_t repeats, double *gpu_ms,
                                vkrt_error *err)
{
    return trace_rays(r, rays, count, false, true, trace, hits, sorted, repeats, gpu_ms, err);
}

bool vkrt_renderer_trace_stats(vkrt_renderer *r, const Ray *rays, uint32_t count, bool any_hit,
                               Hit *hits, vkrt_traversal_stats *stats, vkrt_error *err)
{
    Counters c;
    if (!gpu_buffer_zero(r->ctx, &r->counters, err) ||
        !vkrt_renderer_trace(r, rays, count, any_hit, hits, 1, NULL, err) ||
        !gpu_buffer_download(r->ctx, &r->counters, &c, sizeof c, err))
        return false;
    double rays_traced = c.trace_rays ? c.trace_rays : 1;
    double slots = (double)c.trace_widest * c.subgroup_size;
    *stats = (vkrt_traversal_stats){
        .rays = c.trace_rays,
        .steps_per_ray = c.trace_steps / rays_traced,
        .tests_per_ray = c.trace_tests / rays_traced,
        .simd_utilisation = slots > 0 ? c.trace_busy / slots : 0,
        .subgroup_size = c.subgroup_size,
    };
    return true;
}

void vkrt_renderer_destroy(vkrt_renderer *r)
{
    if (!r->ctx)
        return;
    gpu_pipeline *pipelines[] = {&r->shade,        &r->prepare,   &r->count,     &r->occlusion,
                                 &r->light,        &r->trace,     &r->raygen,    &r->sort_scatter,
                                 &r->sort_scan,    &r->sort_count};
    for (size_t i = 0; i < sizeof pipelines / sizeof *pipelines; ++i)
        gpu_pipeline_destroy(r->ctx, pipelines[i]);
    /* The views before the buffers they look into. */
    gpu_buffer_view_destroy(r->ctx, &r->triangle_view);
    gpu_buffer_view_destroy(r->ctx, &r->node_view);
    destroy_ray_buffers(r);
    gpu_buffer *buffers[] = {&r->counters,      &r->image,          &r->waves,
                             &r->lights,        &r->materials,      &r->triangle_material,
                             &r->normals,       &r->texcoords,      &r->triangles,
                             &r->texture_infos, &r->texels,      &r->trace_cursor};
    for (size_t i = 0; i < sizeof buffers / sizeof *buffers; ++i)
        gpu_buffer_destroy(r->ctx, buffers[i]);
    vkrt_accel_gpu_destroy(&r->accel, r->ctx);
    free(r->light_kinds);
    for (uint32_t i = 0; r->material_names && i < r->material_count; ++i)
        free(r->material_names[i]);
    free(r->material_names);
    gpu_storage_set_destroy(r->ctx, &r->set);
    memset(r, 0, sizeof *r);
}
