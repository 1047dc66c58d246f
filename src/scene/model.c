/* model.c: the scene model's defaults, its world box, its flattening and the dropping of
 * triangles of zero area (see model.h). */
#include "model.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

const float vkrt_identity_transform[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};

static const float default_base_colour = 0.8f;

double vkrt_triangle_area(const float *positions, uint32_t t)
{
    const float *v = positions + (size_t)t * 9;
    double e1[3], e2[3];
    for (int k = 0; k < 3; k++) {
        e1[k] = (double)v[3 + k] - v[k];
        e2[k] = (double)v[6 + k] - v[k];
    }
    double cx = e1[1] * e2[2] - e1[2] * e2[1];
    double cy = e1[2] * e2[0] - e1[0] * e2[2];
    double cz = e1[0] * e2[1] - e1[1] * e2[0];
    return 0.5 * sqrt(cx * cx + cy * cy + cz * cz);
}

/* Moves the per-triangle record of `size` floats (or ints) from triangle `from` to `to`. */
static void move_record(void *array, size_t size, uint32_t from, uint32_t to)
{
    if (array && from != to)
        memmove((char *)array + (size_t)to * size, (char *)array + (size_t)from * size, size);
}

uint32_t vkrt_mesh_drop_degenerate(vkrt_mesh *mesh)
{
    uint32_t kept = 0;
    for (uint32_t t = 0; t < mesh->triangle_count; t++) {
        if (!(vkrt_triangle_area(mesh->positions, t) > 0.0))
            continue;
        move_record(mesh->positions, 9 * sizeof(float), t, kept);
        move_record(mesh->normals, 9 * sizeof(float), t, kept);
        move_record(mesh->texcoords, 6 * sizeof(float), t, kept);
        move_record(mesh->tangents, 12 * sizeof(float), t, kept);
        move_record(mesh->material, sizeof(int32_t), t, kept);
        kept++;
    }
    uint32_t dropped = mesh->triangle_count - kept;
    if (dropped == 0)
        return 0;
    mesh->triangle_count = kept;
    for (int a = 0; a < 3; a++) {
        mesh->bounds_min[a] = kept ? mesh->positions[a] : 0.0f;
        mesh->bounds_max[a] = mesh->bounds_min[a];
    }
    for (size_t i = 0; i < (size_t)kept * 3; i++)
        for (int a = 0; a < 3; a++) {
            float v = mesh->positions[3 * i + a];
            mesh->bounds_min[a] = v < mesh->bounds_min[a] ? v : mesh->bounds_min[a];
            mesh->bounds_max[a] = v > mesh->bounds_max[a] ? v : mesh->bounds_max[a];
        }
    return dropped;
}

void vkrt_mesh_free(vkrt_mesh *mesh)
{
    if (!mesh)
        return;
    void *arrays[] = {mesh->positions, mesh->normals, mesh->texcoords, mesh->tangents,
                      mesh->material};
    for (size_t i = 0; i < sizeof arrays / sizeof *arrays; ++i)
        free(arrays[i]);
    memset(mesh, 0, sizeof *mesh);
}

void vkrt_material_free_strings(vkrt_material *material)
{
    free(material->name);
    free(material->file);
    for (int k = 0; k < VKRT_MAP_COUNT; ++k)
        free(material->maps[k].path);
    material->name = material->file = NULL;
    for (int k = 0; k < VKRT_MAP_COUNT; ++k)
        material->maps[k].path = NULL;
}

void vkrt_model_free(vkrt_model *model)
{
    if (!model)
        return;
    for (uint32_t i = 0; model->meshes && i < model->mesh_count; ++i)
        vkrt_mesh_free(&model->meshes[i]);
    free(model->meshes);
    free(model->instances);
    for (uint32_t i = 0; model->materials && i < model->material_count; ++i)
        vkrt_material_free_strings(&model->materials[i]);
    free(model->materials);
    free(model->lights);
    free(model->cameras);
    for (uint32_t i = 0; model->images && i < model->image_count; ++i) {
        free(model->images[i].name);
        free(model->images[i].bytes);
    }
    free(model->images);
    free(model->warnings_all);
    free(model->inputs);
    memset(model, 0, sizeof *model);
}

void vkrt_material_defaults(vkrt_material *m)
{
    memset(m, 0, sizeof *m);
    m->bsdf = VKRT_BSDF_DIFFUSE;
    for (int i = 0; i < 3; ++i) {
        m->base_colour[i] = default_base_colour;
        m->transmission_filter[i] = 1.0f;
    }
    m->opacity = 1.0f;
    m->ior = 1.0f;
    m->roughness = 1.0f;
    m->detail_scale = 1.0f;
    static const vkrt_texture_usage space[VKRT_MAP_COUNT] = {
        [VKRT_MAP_BASE_COLOUR] = VKRT_TEXTURE_COLOUR, [VKRT_MAP_COVERAGE] = VKRT_TEXTURE_ALPHA,
        [VKRT_MAP_ROUGHNESS] = VKRT_TEXTURE_DATA,     [VKRT_MAP_METALLIC] = VKRT_TEXTURE_DATA,
        [VKRT_MAP_SHEEN] = VKRT_TEXTURE_DATA,         [VKRT_MAP_DETAIL] = VKRT_TEXTURE_DATA,
        [VKRT_MAP_EMISSION] = VKRT_TEXTURE_COLOUR,
    };
    for (int k = 0; k < VKRT_MAP_COUNT; ++k) {
        m->maps[k].space = space[k];
        m->maps[k].embedded = -1;
        m->maps[k].uv_scale[0] = m->maps[k].uv_scale[1] = 1.0f;
    }
    m->detail_kind = VKRT_DETAIL_BY_IMAGE;
}

static bool is_identity(const float t[12])
{
    return memcmp(t, vkrt_identity_transform, sizeof vkrt_identity_transform) == 0;
}

void vkrt_transform_point(const float t[12], const float p[3], float out[3])
{
    float r[3];
    for (int k = 0; k < 3; ++k)
        r[k] = (float)((double)t[4 * k] * p[0] + (double)t[4 * k + 1] * p[1] +
                       (double)t[4 * k + 2] * p[2] + (double)t[4 * k + 3]);
    memcpy(out, r, sizeof r);
}

bool vkrt_model_finish(vkrt_model *model, vkrt_error *err)
{
    uint64_t triangles = 0;
    for (uint32_t i = 0; i < model->instance_count; ++i) {
        const vkrt_instance *inst = &model->instances[i];
        if (inst->mesh >= model->mesh_count)
            return vkrt_error_set(err, "instance %u names mesh %u of %u", i, inst->mesh,
                                  model->mesh_count);
        const vkrt_mesh *mesh = &model->meshes[inst->mesh];
        triangles += mesh->triangle_count;
        float lo[3], hi[3];
        if (is_identity(inst->transform)) {
            memcpy(lo, mesh->bounds_min, sizeof lo);
            memcpy(hi, mesh->bounds_max, sizeof hi);
        } else {
            /* The box of the mesh box's eight corners transformed: it holds every point. */
            for (int c = 0; c < 8; ++c) {
                const float corner[3] = {c & 1 ? mesh->bounds_max[0] : mesh->bounds_min[0],
                                         c & 2 ? mesh->bounds_max[1] : mesh->bounds_min[1],
                                         c & 4 ? mesh->bounds_max[2] : mesh->bounds_min[2]};
                float p[3];
                vkrt_transform_point(inst->transform, corner, p);
                for (int a = 0; a < 3; ++a) {
                    lo[a] = c == 0 || p[a] < lo[a] ? p[a] : lo[a];
                    hi[a] = c == 0 || p[a] > hi[a] ? p[a] : hi[a];
                }
            }
        }
        for (int a = 0; a < 3; ++a) {
            model->bounds_min[a] = i == 0 || lo[a] < model->bounds_min[a] ? lo[a]
                                                                          : model->bounds_min[a];
            model->bounds_max[a] = i == 0 || hi[a] > model->bounds_max[a] ? hi[a]
                                                                          : model->bounds_max[a];
        }
    }
    /* Hits number the instances' triangles in 32 bits, one value kept for "no hit"; a flat
     * structure holds fewer (vkrt_model_world), a two-level BVH this many. */
    if (triangles >= UINT32_MAX)
        return vkrt_error_set(err, "too many triangles over all instances (%llu, at most %u)",
                              (unsigned long long)triangles, UINT32_MAX - 1);
    model->triangle_count = (uint32_t)triangles;
    return true;
}

double vkrt_transform_cofactors(const float t[12], double cof[3][3])
{
    double m[3][3];
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            m[r][c] = t[4 * r + c];
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
            int r1 = (r + 1) % 3, r2 = (r + 2) % 3, c1 = (c + 1) % 3, c2 = (c + 2) % 3;
            cof[r][c] = m[r1][c1] * m[r2][c2] - m[r1][c2] * m[r2][c1];
        }
    return m[0][0] * cof[0][0] + m[0][1] * cof[0][1] + m[0][2] * cof[0][2];
}

/* The unit normal n transformed by the inverse transpose of t's 3x3 part (the cofactor matrix:
 * the same direction, the determinant's scale aside), in double. */
static void transform_normal(const float t[12], const float n[3], float out[3])
{
    double cof[3][3];
    double det = vkrt_transform_cofactors(t, cof);
    double sign = det < 0 ? -1.0 : 1.0; /* a mirroring transform keeps normals outward */
    double v[3], len = 0;
    for (int r = 0; r < 3; ++r) {
        v[r] = sign * (cof[r][0] * n[0] + cof[r][1] * n[1] + cof[r][2] * n[2]);
        len += v[r] * v[r];
    }
    len = sqrt(len);
    for (int r = 0; r < 3; ++r)
        out[r] = len > 0 ? (float)(v[r] / len) : 0.0f;
}

/* The unit geometric normal of the triangle at p (9 floats), +Z where it has no area. */
static void geometric_normal(const float *p, float out[3])
{
    double e1[3], e2[3];
    for (int k = 0; k < 3; ++k) {
        e1[k] = (double)p[3 + k] - p[k];
        e2[k] = (double)p[6 + k] - p[k];
    }
    double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                   e1[0] * e2[1] - e1[1] * e2[0]};
    double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int k = 0; k < 3; ++k)
        out[k] = len > 0 ? (float)(n[k] / len) : (k == 2 ? 1.0f : 0.0f);
}

bool vkrt_model_world(const vkrt_model *model, vkrt_mesh *world, bool *copied, vkrt_error *err)
{
    memset(world, 0, sizeof *world);
    *copied = false;
    if (model->instance_count == 1 && model->instances[0].mesh < model->mesh_count &&
        is_identity(model->instances[0].transform)) {
        *world = model->meshes[model->instances[0].mesh];
        world->tangents = NULL;
        return true;
    }
    /* 9 floats per triangle must stay addressable by uint32 (the kernels' indices). */
    if (model->triangle_count > VKRT_MODEL_FLAT_MAX_TRIANGLES)
        return vkrt_error_set(err,
                              "%u triangles over all instances are too many to flatten (at most "
                              "%u); a two-level BVH holds them (accel bvh)",
                              model->triangle_count, VKRT_MODEL_FLAT_MAX_TRIANGLES);
    bool normals = false, texcoords = false;
    for (uint32_t i = 0; i < model->instance_count; ++i) {
        const vkrt_mesh *mesh = &model->meshes[model->instances[i].mesh];
        normals = normals || mesh->normals;
        texcoords = texcoords || mesh->texcoords;
    }
    size_t n = model->triangle_count;
    world->triangle_count = model->triangle_count;
    world->positions = malloc((n ? n : 1) * 9 * sizeof(float));
    world->material = malloc((n ? n : 1) * sizeof(int32_t));
    world->normals = normals ? malloc((n ? n : 1) * 9 * sizeof(float)) : NULL;
    world->texcoords = texcoords ? calloc(n ? n : 1, 6 * sizeof(float)) : NULL;
    if (!world->positions || !world->material || (normals && !world->normals) ||
        (texcoords && !world->texcoords)) {
        vkrt_mesh_free(world);
        return vkrt_error_set(err, "out of memory flattening %zu triangles", n);
    }
    *copied = true;
    size_t t = 0;
    for (uint32_t i = 0; i < model->instance_count; ++i) {
        const vkrt_instance *inst = &model->instances[i];
        const vkrt_mesh *mesh = &model->meshes[inst->mesh];
        for (uint32_t k = 0; k < mesh->triangle_count; ++k, ++t) {
            float *p = world->positions + 9 * t;
            for (int c = 0; c < 3; ++c)
                vkrt_transform_point(inst->transform, mesh->positions + 9 * (size_t)k + 3 * c,
                                p + 3 * c);
            world->material[t] = mesh->material[k];
            if (mesh->texcoords)
                memcpy(world->texcoords + 6 * t, mesh->texcoords + 6 * (size_t)k,
                       6 * sizeof(float));
            if (!normals)
                continue;
            for (int c = 0; c < 3; ++c) {
                float *out = world->normals + 9 * t + 3 * c;
                if (mesh->normals)
                    transform_normal(inst->transform, mesh->normals + 9 * (size_t)k + 3 * c, out);
                else
                    geometric_normal(p, out);
            }
        }
    }
    for (size_t v = 0; v < 3 * n; ++v)
        for (int a = 0; a < 3; ++a) {
            float x = world->positions[3 * v + a];
            world->bounds_min[a] = v == 0 || x < world->bounds_min[a] ? x : world->bounds_min[a];
            world->bounds_max[a] = v == 0 || x > world->bounds_max[a] ? x : world->bounds_max[a];
        }
    return true;
}

uint32_t *vkrt_model_instance_firsts(const vkrt_model *model)
{
    uint32_t count = model->instance_count;
    uint32_t *firsts = malloc((count ? count : 1) * sizeof *firsts);
    uint32_t t = 0;
    for (uint32_t i = 0; firsts && i < count; ++i) {
        firsts[i] = t;
        t += model->meshes[model->instances[i].mesh].triangle_count;
    }
    return firsts;
}

void vkrt_model_world_triangle(const vkrt_model *model, const uint32_t *firsts, uint32_t t,
                               float out[9])
{
    /* The last instance whose first triangle is at most t: an empty instance shares its first
     * with the next, so the one found holds t. */
    uint32_t lo = 0, hi = model->instance_count;
    while (hi - lo > 1) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (firsts[mid] <= t)
            lo = mid;
        else
            hi = mid;
    }
    const vkrt_instance *inst = &model->instances[lo];
    const float *p = model->meshes[inst->mesh].positions + 9 * (size_t)(t - firsts[lo]);
    /* vkrt_model_world takes one identity instance's positions as they are. */
    if (model->instance_count == 1 && is_identity(inst->transform)) {
        memcpy(out, p, 9 * sizeof *out);
        return;
    }
    for (int c = 0; c < 3; ++c)
        vkrt_transform_point(inst->transform, p + 3 * c, out + 3 * c);
}

double vkrt_model_host_bytes(const vkrt_model *model)
{
    double bytes = 0;
    for (uint32_t i = 0; i < model->mesh_count; ++i) {
        const vkrt_mesh *m = &model->meshes[i];
        size_t per_triangle = 9 * sizeof(float) * (1 + (m->normals != NULL)) +
                              6 * sizeof(float) * (m->texcoords != NULL) +
                              12 * sizeof(float) * (m->tangents != NULL) + sizeof(int32_t);
        bytes += (double)m->triangle_count * per_triangle;
    }
    return bytes;
}

void vkrt_model_print_warnings(const vkrt_model *model, const char *prefix, bool verbose,
                               FILE *out)
{
    const char *text = verbose && model->warnings_all ? model->warnings_all : model->warnings;
    while (*text) {
        size_t n = strcspn(text, "\n");
        fprintf(out, "%s%.*s\n", prefix ? prefix : "", (int)n, text);
        text += n + (text[n] == '\n');
    }
}
