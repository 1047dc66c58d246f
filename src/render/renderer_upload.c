/*
 * renderer_upload.c: the scene's geometry, materials, textures and lights in GPU buffers, in the
 * acceleration structure's triangle order (see renderer_private.h).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../scene/emitters.h"
#include "../scene/envmap.h"
#include "../scene/colour.h"
#include "../accel/bvh_threads.h"
#include "renderer_private.h"

/* What the per-triangle arrays are made from (the model's triangles in world space,
 * vkrt_model_world): each written straight into the staging buffers, piece by piece, in the
 * structure's triangle order (a BVH's leaf order), so that the host never holds a second copy
 * of them (gigabytes at a hundred million triangles). */
typedef struct geometry_source {
    const vkrt_renderer *r;
    const vkrt_mesh *mesh;
    const vkrt_scene_materials *mats;
    /* The array being filled: what writes its elements, and their size. */
    gpu_array_fill_fn *fill;
    size_t element_size;
} geometry_source;

static void fill_triangles(void *user, size_t first, size_t count, void *dst)
{
    const geometry_source *g = user;
    Triangle *out = dst;
    for (size_t i = 0; i < count; ++i) {
        uint32_t from = vkrt_accel_original_triangle(&g->r->accel, (uint32_t)(first + i));
        const float *p = g->mesh->positions + 9 * (size_t)from;
        out[i].v0 = (vec4){p[0], p[1], p[2], 0};
        out[i].v1 = (vec4){p[3], p[4], p[5], 0};
        out[i].v2 = (vec4){p[6], p[7], p[8], 0};
    }
}

static void fill_normals(void *user, size_t first, size_t count, void *dst)
{
    const geometry_source *g = user;
    TriangleNormals *out = dst;
    for (size_t i = 0; i < count; ++i) {
        uint32_t from = vkrt_accel_original_triangle(&g->r->accel, (uint32_t)(first + i));
        const float *q = g->mesh->normals + 9 * (size_t)from;
        out[i].n0 = (vec4){q[0], q[1], q[2], 0};
        out[i].n1 = (vec4){q[3], q[4], q[5], 0};
        out[i].n2 = (vec4){q[6], q[7], q[8], 0};
    }
}

static void fill_texcoords(void *user, size_t first, size_t count, void *dst)
{
    const geometry_source *g = user;
    TriangleTexcoords *out = dst;
    for (size_t i = 0; i < count; ++i) {
        uint32_t from = vkrt_accel_original_triangle(&g->r->accel, (uint32_t)(first + i));
        const float *t = g->mesh->texcoords + 6 * (size_t)from;
        out[i].uv01 = (vec4){t[0], t[1], t[2], t[3]};
        out[i].uv2 = (vec4){t[4], t[5], 0, 0};
    }
}

static void fill_materials(void *user, size_t first, size_t count, void *dst)
{
    const geometry_source *g = user;
    uint32_t *out = dst;
    for (size_t i = 0; i < count; ++i)
        out[i] = g->mats->triangle_material[vkrt_accel_original_triangle(&g->r->accel,
                                                                         (uint32_t)(first + i))];
}

/* One thread's share of a piece (fill_on_every_core). */
typedef struct fill_share {
    const geometry_source *source;
    size_t first, count;
    unsigned char *dst;
} fill_share;

static void *fill_share_run(void *arg)
{
    const fill_share *s = arg;
    if (s->count > 0)
        s->source->fill((void *)s->source, s->first, s->count, s->dst);
    return NULL;
}

/* The source's fill over every core: a piece is 64 MiB of gathers from the mesh in the
 * structure's order, which on one thread was most of a big scene's upload (docs/performance.md).
 * The elements are independent, so the shares need no order. */
static void fill_on_every_core(void *user, size_t first, size_t count, void *dst)
{
    const geometry_source *source = user;
    /* Below this many elements a thread costs more than it saves. */
    const size_t per_thread = 16384;
    uint32_t threads = bvh_threads_default();
    if (count / per_thread < threads)
        threads = count / per_thread > 0 ? (uint32_t)(count / per_thread) : 1;
    fill_share shares[BVH_MAX_THREADS];
    size_t step = (count + threads - 1) / threads;
    for (uint32_t t = 0; t < threads; ++t) {
        size_t begin = (size_t)t * step < count ? (size_t)t * step : count;
        size_t end = begin + step < count ? begin + step : count;
        shares[t] = (fill_share){source, first + begin, end - begin,
                                 (unsigned char *)dst + begin * source->element_size};
    }
    bvh_threads_run(threads, fill_share_run, shares, sizeof shares[0]);
}

/* Creates array a of count elements and fills it; an attribute no kernel reads (count 0) gets a
 * minimal buffer that keeps its binding valid. */
static bool upload_array(vkrt_renderer *r, gpu_array *a, size_t element_size, size_t count,
                         gpu_array_fill_fn *fill, geometry_source *source, const char *what,
                         vkrt_error *err)
{
    source->fill = fill;
    source->element_size = element_size;
    return gpu_array_create(r->ctx, a, element_size, count, what, err) &&
           gpu_array_fill(r->ctx, a, fill_on_every_core, source, err);
}

bool renderer_upload_geometry(vkrt_renderer *r, const vkrt_mesh *mesh,
                              const vkrt_scene_materials *mats, vkrt_error *err)
{
    /* The structure's triangle count: with spatial splits a triangle is uploaded once per leaf. */
    size_t n = r->accel.triangle_count;
    r->triangle_count = r->accel.triangle_count;
    bool want_texcoords = mats->reads_texcoords && mesh->texcoords;
    geometry_source source = {r, mesh, mats, NULL, 0};
    return upload_array(r, &r->triangles, sizeof(Triangle), n, fill_triangles, &source,
                        "triangles", err) &&
           upload_array(r, &r->triangle_material, sizeof(uint32_t), n, fill_materials, &source,
                        "triangle materials", err) &&
           upload_array(r, &r->normals, sizeof(TriangleNormals), mesh->normals ? n : 0,
                        fill_normals, &source, "normals", err) &&
           upload_array(r, &r->texcoords, sizeof(TriangleTexcoords), want_texcoords ? n : 0,
                        fill_texcoords, &source, "texture coordinates", err);
}

/* Whether texture tex of the set has a texel whose alpha is below 1: a colour map whose alpha
 * carries coverage. */
static bool texture_has_alpha(const vkrt_texture_set *set, uint32_t tex)
{
    const vkrt_texture_info *info = &set->info[tex];
    size_t texels = (size_t)info->width * info->height;
    bool half = (info->flags & VKRT_TEXTURE_HALF) != 0;
    for (size_t i = 0; i < texels; ++i) {
        if (half) {
            /* The second word holds b and a as half floats, a in the high half: below 1.0
             * (0x3C00) for any non-negative alpha under one. */
            uint32_t a = set->texels[info->offset + 2 * i + 1] >> 16;
            if (a < 0x3C00u)
                return true;
        } else if ((set->texels[info->offset + i] >> 24) < 255u) {
            return true;
        }
    }
    return false;
}

/* Where traversal reads material m's cut-out (lib/cutout.glsl): the built-ins that read the
 * .mtl's map_Kd (slot 0) and map_d (slot 1) are cut out by map_d, or without one by an alpha
 * channel of map_Kd. */
static uint32_t material_cutout(const vkrt_scene_materials *mats, uint32_t m)
{
    static const char *const cut[] = {"diffuse", "textured", "phong", "mirror", "pbr"};
    const vkrt_scene_material *mat = &mats->list[m];
    const char *builtin = mats->shaders[mat->shader].builtin;
    bool reads_mtl_maps = false;
    for (size_t i = 0; builtin && i < sizeof cut / sizeof *cut; ++i)
        reads_mtl_maps |= strcmp(builtin, cut[i]) == 0;
    if (!reads_mtl_maps)
        return VKRT_CUTOUT_NONE;
    if (mat->textures[1] != VKRT_SCENE_NO_TEXTURE)
        return VKRT_CUTOUT_MAP_D;
    if (mat->textures[0] != VKRT_SCENE_NO_TEXTURE &&
        texture_has_alpha(&mats->textures, mat->textures[0]))
        return VKRT_CUTOUT_ALPHA;
    return VKRT_CUTOUT_NONE;
}

bool renderer_scan_materials(vkrt_renderer *r, const vkrt_scene_materials *mats,
                             vkrt_error *err)
{
    r->material_cutouts = calloc(mats->count ? mats->count : 1, sizeof *r->material_cutouts);
    if (!r->material_cutouts)
        return vkrt_error_set(err, "out of memory");
    for (uint32_t i = 0; i < mats->count; ++i) {
        r->material_cutouts[i] = material_cutout(mats, i);
        r->has_cutouts |= r->material_cutouts[i] != VKRT_CUTOUT_NONE;
        r->surface_maps |= mats->list[i].maps;
    }
    return true;
}

bool renderer_upload_materials(vkrt_renderer *r, const vkrt_scene_materials *mats,
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
                          (kernel->shader_uses_lights[m->shader] ? VKRT_MATERIAL_USES_LIGHTS : 0) |
                              m->maps,
                          m->texture_count, r->material_cutouts[i]};
        float ke[3];
        renderer_material_ke(mats, i, ke);
        g->maps = (vec4){(float)vkrt_luminance(ke), m->detail_multiplier, m->sheen, 0};
        size_t len = strlen(m->name) + strlen(m->referrer) + 8;
        r->material_names[i] = malloc(len);
        if (!r->material_names[i]) {
            free(materials);
            return vkrt_error_set(err, "out of memory");
        }
        snprintf(r->material_names[i], len, "'%s' (%s)", m->name, m->referrer);
    }
    bool ok = renderer_upload_plastic_tables(r, mats, materials, err) &&
              gpu_buffer_create_from(r->ctx, &r->materials, materials,
                                     mats->count * sizeof *materials, "materials", err);
    free(materials);
    const vkrt_texture_set *tex = &mats->textures;
    if (ok && tex->count) {
        ok = gpu_buffer_create_from(r->ctx, &r->texture_infos, tex->info, tex->count * sizeof *tex->info,
                    "texture table", err) &&
             gpu_array_create_from(r->ctx, &r->texels, tex->texels, sizeof *tex->texels,
                                   tex->texel_words, "texels (all textures together)", err);
    } else if (ok) {
        ok = gpu_buffer_create(r->ctx, &r->texture_infos, 0, "texture table", err) &&
             gpu_array_create(r->ctx, &r->texels, sizeof(uint32_t), 0, "texels", err);
    }
    return ok;
}

static float radians(float degrees)
{
    return degrees * 3.14159265358979f / 180.0f;
}

bool renderer_upload_lights(vkrt_renderer *r, const vkrt_config_light *config_lights, uint32_t count,
                            vkrt_error *err)
{
    r->light_count = count;
    r->light_kinds = calloc(count ? count : 1, sizeof *r->light_kinds);
    if (!r->light_kinds)
        return vkrt_error_set(err, "out of memory");
    Light *lights = calloc(count ? count : 1, sizeof *lights);
    if (!lights)
        return vkrt_error_set(err, "out of memory");
    for (uint32_t i = 0; i < count; ++i) {
        const vkrt_config_light *l = &config_lights[i];
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
    bool ok = gpu_buffer_create_from(r->ctx, &r->lights, lights, count * sizeof *lights, "lights", err);
    free(lights);
    return ok;
}

bool renderer_create_texel_views(vkrt_renderer *r, vkrt_error *err)
{
    bool whole_triangles, whole_nodes;
    if (!gpu_buffer_view_create(r->ctx, &r->triangles.chunks[0], &r->triangle_view,
                                &whole_triangles, err) ||
        !gpu_buffer_view_create(r->ctx, &r->accel.nodes.chunks[0], &r->node_view, &whole_nodes,
                                err))
        return false;
    /* A split array's first view holds its first chunk only. */
    whole_triangles = whole_triangles && r->triangles.chunk_count == 1;
    whole_nodes = whole_nodes && r->accel.nodes.chunk_count == 1;
    /* Only the BVH's and the kd-tree's walks read nodes through a view (the grid's cells stay
     * storage buffers). */
    if (r->accel.stats.kind != VKRT_ACCEL_BVH && r->accel.stats.kind != VKRT_ACCEL_KDTREE)
        whole_nodes = true;
    if (r->tuning.texel_loads_required && !(whole_triangles && whole_nodes))
        return vkrt_error_set(err, "texel loads: the triangles (%zu bytes) or the structure's "
                                   "nodes (%zu) exceed one buffer, or %s's %u texels of a "
                                   "texel buffer",
                              r->triangles.count * r->triangles.element_size,
                              r->accel.nodes.count * r->accel.nodes.element_size,
                              r->ctx->properties.deviceName,
                              r->ctx->properties.limits.maxTexelBufferElements);
    r->texel_loads = r->tuning.texel_loads && whole_triangles && whole_nodes;
    return true;
}

_Static_assert(GPU_ARRAY_MAX_CHUNKS == VKRT_MAX_CHUNKS, "one most chunks of a split array");

/* The arrays that may be split, in VKRT_SPLIT_* order. */
static const gpu_array *split_array(const vkrt_renderer *r, uint32_t k)
{
    const gpu_array *arrays[VKRT_SPLIT_ARRAY_COUNT] = {
        [VKRT_SPLIT_TRIANGLES] = &r->triangles,
        [VKRT_SPLIT_NORMALS] = &r->normals,
        [VKRT_SPLIT_TEXCOORDS] = &r->texcoords,
        [VKRT_SPLIT_TRIANGLE_MATERIAL] = &r->triangle_material,
        [VKRT_SPLIT_NODES] = &r->accel.nodes,
        [VKRT_SPLIT_REFS] = &r->accel.refs,
        [VKRT_SPLIT_TEXELS] = &r->texels,
    };
    return arrays[k];
}

uint32_t renderer_split_shift(const vkrt_renderer *r, uint32_t k)
{
    return split_array(r, k)->shift;
}

void renderer_data_layout_of(const vkrt_renderer *r, renderer_data_layout *layout)
{
    memset(layout, 0, sizeof *layout);
    layout->kind = r->accel.stats.kind;
    layout->two_level = r->accel.stats.two_level;
    layout->bvh_width = r->accel.stats.bvh_width;
    layout->texel_loads = r->texel_loads;
    layout->emitter_light = r->emitter_light;
    for (uint32_t k = 0; k < VKRT_SPLIT_ARRAY_COUNT; ++k)
        layout->split_shift[k] = renderer_split_shift(r, k);
}

/* Whether a texel view (16-byte texels) holds an array of bytes whole: one buffer, and within
 * the device's texel count (renderer_create_texel_views decides the same after the upload). */
static bool view_holds(const gpu_context *ctx, size_t bytes)
{
    return bytes <= ctx->split_bytes && bytes % 16 == 0 &&
           bytes / 16 <= ctx->properties.limits.maxTexelBufferElements;
}

bool renderer_data_layout_predict(const vkrt_renderer *r, const vkrt_accel_desc *accel,
                                  const vkrt_mesh *mesh, const vkrt_scene_materials *mats,
                                  renderer_data_layout *layout)
{
    memset(layout, 0, sizeof *layout);
    size_t n = mesh->triangle_count;
    layout->two_level = r->two_level;
    layout->kind = r->two_level ? VKRT_ACCEL_BVH
                                : vkrt_accel_gpu_predict(accel, mesh->triangle_count);
    if (layout->kind == VKRT_ACCEL_AUTO)
        return false;
    /* The structure's nodes: a guess where only the build knows their number (a BVH's leaves
     * hold about two triangles), which matters only for arrays near a buffer's limit; spatial
     * splits' extra triangles are left out alike. */
    size_t node_size = sizeof(uint32_t), nodes = n, refs = 0;
    if (layout->kind == VKRT_ACCEL_BVH) {
        layout->bvh_width = accel->bvh_width;
        node_size = accel->bvh_width == 2 ? sizeof(BvhPair) : sizeof(BvhQuad);
        nodes = n / accel->bvh_width;
    } else if (layout->kind == VKRT_ACCEL_KDTREE) {
        node_size = sizeof(KdNode);
        refs = n;
    } else if (layout->kind == VKRT_ACCEL_GRID) {
        refs = n;
    } else {
        nodes = 0;
    }
    const gpu_context *ctx = r->ctx;
    bool texcoords = mats->reads_texcoords && mesh->texcoords;
    uint32_t *shift = layout->split_shift;
    shift[VKRT_SPLIT_TRIANGLES] = gpu_array_shift_for(ctx, sizeof(Triangle), n);
    shift[VKRT_SPLIT_NORMALS] = gpu_array_shift_for(ctx, sizeof(TriangleNormals),
                                                    mesh->normals ? n : 0);
    shift[VKRT_SPLIT_TEXCOORDS] = gpu_array_shift_for(ctx, sizeof(TriangleTexcoords),
                                                      texcoords ? n : 0);
    shift[VKRT_SPLIT_TRIANGLE_MATERIAL] = gpu_array_shift_for(ctx, sizeof(uint32_t), n);
    shift[VKRT_SPLIT_NODES] = gpu_array_shift_for(ctx, node_size, nodes);
    shift[VKRT_SPLIT_REFS] = gpu_array_shift_for(ctx, sizeof(uint32_t), refs);
    shift[VKRT_SPLIT_TEXELS] = gpu_array_shift_for(ctx, sizeof(uint32_t),
                                                   mats->textures.count ? mats->textures.texel_words
                                                                        : 0);
    bool reads_nodes = layout->kind == VKRT_ACCEL_BVH || layout->kind == VKRT_ACCEL_KDTREE;
    layout->texel_loads = r->tuning.texel_loads && view_holds(ctx, n * sizeof(Triangle)) &&
                          (!reads_nodes || view_holds(ctx, nodes * node_size));
    /* Cleared by the light upload where every emissive triangle has zero area: rare. */
    layout->emitter_light = r->emitter_light;
    return true;
}

void vkrt_renderer_split_text(const vkrt_renderer *r, char *text, size_t size)
{
    static const char *const names[VKRT_SPLIT_ARRAY_COUNT] = {
        [VKRT_SPLIT_TRIANGLES] = "triangles",
        [VKRT_SPLIT_NORMALS] = "normals",
        [VKRT_SPLIT_TEXCOORDS] = "texture coordinates",
        [VKRT_SPLIT_TRIANGLE_MATERIAL] = "triangle materials",
        [VKRT_SPLIT_NODES] = "nodes",
        [VKRT_SPLIT_REFS] = "references",
        [VKRT_SPLIT_TEXELS] = "texels",
    };
    size_t at = 0;
    text[0] = '\0';
    for (uint32_t k = 0; k < VKRT_SPLIT_ARRAY_COUNT; ++k) {
        const gpu_array *a = split_array(r, k);
        if (a->chunk_count > 1 && at < size)
            at += (size_t)snprintf(text + at, size - at, "%s%s in %u buffers", at ? ", " : "",
                                   names[k], a->chunk_count);
    }
}

bool renderer_upload_split_addresses(vkrt_renderer *r, vkrt_error *err)
{
    uint32_t table[VKRT_SPLIT_ARRAY_COUNT * VKRT_MAX_CHUNKS * 2] = {0};
    r->split = false;
    for (uint32_t k = 0; k < VKRT_SPLIT_ARRAY_COUNT; ++k) {
        const gpu_array *a = split_array(r, k);
        if (a->shift == 0)
            continue;
        r->split = true;
        for (uint32_t c = 0; c < a->chunk_count; ++c) {
            VkDeviceAddress address = gpu_buffer_address(r->ctx, &a->chunks[c]);
            table[2 * (k * VKRT_MAX_CHUNKS + c)] = (uint32_t)address;
            table[2 * (k * VKRT_MAX_CHUNKS + c) + 1] = (uint32_t)(address >> 32);
        }
    }
    return r->split ? gpu_buffer_create_from(r->ctx, &r->split_addresses, table, sizeof table,
                                             "split array addresses", err)
                    : gpu_buffer_create(r->ctx, &r->split_addresses, 0, "split array addresses",
                                        err);
}

/* The environment is sampled for light when it can give any: a user's environment shader, or the
 * built-in constant above zero. */
static bool environment_gives_light(const vkrt_scene_materials *mats)
{
    const vkrt_scene_material *env = &mats->list[mats->environment];
    const vkrt_shader_source *shader = &mats->shaders[env->shader];
    if (!shader->builtin || strcmp(shader->builtin, "environment") != 0)
        return true;
    return env->params[0] > 0 || env->params[1] > 0 || env->params[2] > 0;
}

void renderer_material_ke(const vkrt_scene_materials *mats, uint32_t m, float ke[3])
{
    /* The built-ins whose emitted() is Ke (glsl/materials/): the others, and users' shaders,
     * give their parameters 8-10 other meanings. */
    static const char *const emitting[] = {
        "diffuse",  "textured",       "phong",           "mirror",       "glass",
        "emissive", "roughconductor", "roughdielectric", "roughplastic", "pbr"};
    const vkrt_scene_material *mat = &mats->list[m];
    const char *builtin = mats->shaders[mat->shader].builtin;
    ke[0] = ke[1] = ke[2] = 0;
    if (m == mats->environment || !builtin)
        return;
    for (size_t i = 0; i < sizeof emitting / sizeof *emitting; ++i)
        if (strcmp(builtin, emitting[i]) == 0)
            memcpy(ke, &mat->params[8], 3 * sizeof *ke);
    /* An emission map: its mean stands for it. Sampling stays unbiased whatever the weight, since
     * the emission itself is read at the point drawn (lib/emitters.glsl); the mean makes the
     * choice between triangles follow the light each gives on average. */
    if (mat->maps & VKRT_MATERIAL_EMISSION_MAP) {
        float mean[4];
        vkrt_texture_mean(&mats->textures, mat->textures[VKRT_SLOT_EMISSION], mean);
        for (int k = 0; k < 3; ++k)
            ke[k] *= mean[k];
    }
}

/* The alias table over the emissive triangles (src/scene/emitters.h) into info and *table,
 * the triangles renumbered to the structure's order the kernels see. */
static bool build_emitter_table(vkrt_renderer *r, const vkrt_mesh *world,
                                const vkrt_scene_materials *mats, LightInfo *info,
                                Emitter **table, vkrt_error *err)
{
    uint32_t n = world->triangle_count;
    float *ke = malloc((mats->count ? mats->count : 1) * 3 * sizeof *ke);
    uint32_t *uploaded = malloc((n ? n : 1) * sizeof *uploaded);
    if (!ke || !uploaded) {
        free(ke);
        free(uploaded);
        return vkrt_error_set(err, "out of memory");
    }
    for (uint32_t m = 0; m < mats->count; ++m)
        renderer_material_ke(mats, m, &ke[3 * m]);
    /* A triangle uploaded more than once (spatial splits) is sampled through any one copy. */
    for (uint32_t i = 0; i < r->accel.triangle_count; ++i)
        uploaded[vkrt_accel_original_triangle(&r->accel, i)] = i;
    vkrt_emitters e;
    bool ok = vkrt_emitters_build(world->positions, n, mats->triangle_material, ke,
                                  mats->count, &e, err);
    free(ke);
    *table = NULL;
    if (ok && e.count) {
        *table = calloc(e.count, sizeof **table);
        if (!*table)
            ok = vkrt_error_set(err, "out of memory for %u emitters", e.count);
        for (uint32_t i = 0; ok && i < e.count; ++i)
            (*table)[i] = (Emitter){uploaded[e.triangle[i]], e.keep[i], e.alias[i], e.power[i]};
        info->emitter_count = e.count;
        info->emitter_power = (float)e.total_power;
    }
    free(uploaded);
    vkrt_emitters_free(&e);
    return ok;
}

/* The environment map (scene.cfg `environment-map`), when there is one: its sampling
 * distribution and then its pixels, as lib/environment.glsl reads them, into *bytes (malloc'd),
 * and its fields of info. */
static bool build_environment(const vkrt_config *cfg, LightInfo *info, float **floats,
                              size_t *count, vkrt_error *err)
{
    *floats = NULL;
    *count = 0;
    if (!cfg->environment_map)
        return true;
    /* Where the map was named: a scene.cfg line, or (line 0) the command line, whose message
     * needs no referrer ("environment-map 'sky.hdr': ..."). */
    char referrer[64] = "";
    if (cfg->environment_map_line > 0)
        snprintf(referrer, sizeof referrer, "%s:%d", cfg->path ? cfg->path : "scene.cfg",
                 cfg->environment_map_line);
    vkrt_envmap_image image;
    vkrt_envmap_distribution dist;
    if (!vkrt_envmap_load(cfg->environment_map, referrer, &image, err))
        return false;
    bool ok = vkrt_envmap_distribution_build(image.rgb, image.width, image.height, &dist, err);
    size_t pixels = (size_t)image.width * image.height * 3;
    if (ok) {
        *count = dist.float_count + pixels;
        *floats = malloc(*count * sizeof **floats);
        if (!*floats)
            ok = vkrt_error_set(err, "out of memory for the environment map");
    }
    if (ok) {
        memcpy(*floats, dist.data, dist.float_count * sizeof **floats);
        memcpy(*floats + dist.float_count, image.rgb, pixels * sizeof **floats);
        vkrt_envmap_light_info(&dist, cfg->environment_scale, cfg->environment_rotate, info);
        /* Where the pixels start (lib/environment.glsl). */
        info->environment_pixels = (uint32_t)dist.float_count;
    }
    vkrt_envmap_distribution_free(&dist);
    vkrt_envmap_image_free(&image);
    return ok;
}

bool renderer_upload_light_sampling(vkrt_renderer *r, const vkrt_scene *scene,
                                    const vkrt_mesh *world, const vkrt_scene_materials *mats,
                                    vkrt_error *err)
{
    LightInfo info = {0};
    Emitter *table = NULL;
    float *environment = NULL;
    size_t environment_floats = 0;
    bool path = r->integrator == VKRT_INTEGRATOR_PATH;
    bool ok = (!(path || r->emitter_light) ||
               build_emitter_table(r, world, mats, &info, &table, err)) &&
              build_environment(&scene->config, &info, &environment, &environment_floats, err);
    /* Ke on triangles of zero area only: nothing to sample, so no emitter light is compiled (its
     * visibility word stays, unused). */
    r->emitter_light = r->emitter_light && info.emitter_count > 0;
    if (!path)
        info.environment_sampled = 0;
    else if (!scene->config.environment_map)
        info.environment_sampled = environment_gives_light(mats);
    size_t table_bytes = (size_t)info.emitter_count * sizeof *table;
    uint8_t *bytes = ok ? malloc(sizeof info + table_bytes) : NULL;
    if (ok && !bytes)
        ok = vkrt_error_set(err, "out of memory");
    if (ok) {
        memcpy(bytes, &info, sizeof info);
        if (table_bytes)
            memcpy(bytes + sizeof info, table, table_bytes);
        ok = gpu_buffer_create_from(r->ctx, &r->emitters, bytes, sizeof info + table_bytes,
                                    "emissive triangles", err) &&
             (environment_floats
                  ? gpu_buffer_create_from(r->ctx, &r->environment, environment,
                                           environment_floats * sizeof *environment,
                                           "environment map", err)
                  : gpu_buffer_create(r->ctx, &r->environment, 0, "environment map", err));
    }
    free(bytes);
    free(table);
    free(environment);
    return ok;
}
