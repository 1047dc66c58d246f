/*
 * renderer_upload.c: the scene's geometry, materials, textures and lights in GPU buffers, in the
 * acceleration structure's triangle order (see renderer_private.h).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "renderer_private.h"

bool renderer_upload_geometry(vkrt_renderer *r, const vkrt_mesh *mesh,
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
    ok = gpu_buffer_create_from(r->ctx, &r->triangles, tris, n * sizeof *tris, "triangles", err) &&
         gpu_buffer_create_from(r->ctx, &r->triangle_material, material, n * sizeof *material, "triangle materials",
                err);
    /* Attributes no kernel will read get a minimal buffer that keeps their binding valid. */
    if (ok)
        ok = normals ? gpu_buffer_create_from(r->ctx, &r->normals, normals, n * sizeof *normals, "normals", err)
                     : gpu_buffer_create(r->ctx, &r->normals, 0, "normals", err);
    if (ok)
        ok = texcoords ? gpu_buffer_create_from(r->ctx, &r->texcoords, texcoords, n * sizeof *texcoords,
                                "texture coordinates", err)
                       : gpu_buffer_create(r->ctx, &r->texcoords, 0, "texture coordinates", err);
done:
    free(tris);
    free(material);
    free(normals);
    free(texcoords);
    return ok;
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
    bool ok = gpu_buffer_create_from(r->ctx, &r->materials, materials, mats->count * sizeof *materials, "materials",
                     err);
    free(materials);
    const vkrt_texture_set *tex = &mats->textures;
    if (ok && tex->count) {
        ok = gpu_buffer_create_from(r->ctx, &r->texture_infos, tex->info, tex->count * sizeof *tex->info,
                    "texture table", err) &&
             gpu_buffer_create_from(r->ctx, &r->texels, tex->texels, tex->texel_words * sizeof *tex->texels,
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

bool renderer_upload_lights(vkrt_renderer *r, const vkrt_config *cfg, vkrt_error *err)
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
    bool ok = gpu_buffer_create_from(r->ctx, &r->lights, lights, cfg->light_count * sizeof *lights, "lights", err);
    free(lights);
    return ok;
}

bool renderer_create_texel_views(vkrt_renderer *r, vkrt_error *err)
{
    bool whole_triangles, whole_nodes;
    if (!gpu_buffer_view_create(r->ctx, &r->triangles, &r->triangle_view, &whole_triangles, err) ||
        !gpu_buffer_view_create(r->ctx, &r->accel.nodes, &r->node_view, &whole_nodes, err))
        return false;
    /* Only the BVH's walk reads nodes through a view (the grid's cells stay storage buffers). */
    if (r->accel.stats.kind != VKRT_ACCEL_BVH)
        whole_nodes = true;
    if (r->tuning.texel_loads_required && !(whole_triangles && whole_nodes))
        return vkrt_error_set(err, "texel loads: the triangles (%zu bytes) or the structure's "
                                   "nodes (%zu) exceed %s's %u texels of a texel buffer",
                              (size_t)r->triangles.size, (size_t)r->accel.nodes.size,
                              r->ctx->properties.deviceName,
                              r->ctx->properties.limits.maxTexelBufferElements);
    r->texel_loads = r->tuning.texel_loads && whole_triangles && whole_nodes;
    return true;
}
