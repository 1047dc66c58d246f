/* model_place.c: several scene files, placed, as one model (see model_place.h). */
#include "model_place.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void vkrt_transform_compose(const float a[12], const float b[12], float out[12])
{
    float r[12];
    for (int row = 0; row < 3; row++)
        for (int col = 0; col < 4; col++) {
            double v = col == 3 ? a[4 * row + 3] : 0.0;
            for (int k = 0; k < 3; k++)
                v += (double)a[4 * row + k] * b[4 * k + col];
            r[4 * row + col] = (float)v;
        }
    memcpy(out, r, sizeof r);
}

/* A direction through the transform's linear part, made unit again (unchanged if it vanishes). */
static void place_direction(const float t[12], const float d[3], float out[3])
{
    double r[3];
    for (int row = 0; row < 3; row++)
        r[row] = (double)t[4 * row] * d[0] + (double)t[4 * row + 1] * d[1] +
                 (double)t[4 * row + 2] * d[2];
    double len = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    if (!(len > 0.0))
        return;
    for (int i = 0; i < 3; i++)
        out[i] = (float)(r[i] / len);
}

/* *dst = *dst + "\n" + add (either may be NULL); false when memory runs out. */
static bool append_lines(char **dst, const char *add)
{
    if (!add || !*add)
        return true;
    size_t have = *dst ? strlen(*dst) : 0, more = strlen(add);
    char *grown = realloc(*dst, have + more + 2);
    if (!grown)
        return false;
    if (have && grown[have - 1] != '\n')
        grown[have++] = '\n';
    memcpy(grown + have, add, more + 1);
    *dst = grown;
    return true;
}

/* Grows *array (count items of size bytes) by more; false when memory runs out. */
static bool grow(void **array, uint32_t count, uint64_t more, size_t size)
{
    if (more == 0)
        return true;
    if (count + more > UINT32_MAX)
        return false;
    void *grown = realloc(*array, (size_t)(count + more) * size);
    if (!grown)
        return false;
    *array = grown;
    return true;
}

bool vkrt_model_place(vkrt_model *dst, vkrt_model *src, const float (*placements)[12],
                      uint32_t placement_count, vkrt_error *err)
{
    uint64_t n = placement_count;
    if (!grow((void **)&dst->meshes, dst->mesh_count, src->mesh_count, sizeof *dst->meshes) ||
        !grow((void **)&dst->materials, dst->material_count, src->material_count,
              sizeof *dst->materials) ||
        !grow((void **)&dst->images, dst->image_count, src->image_count, sizeof *dst->images) ||
        !grow((void **)&dst->instances, dst->instance_count, n * src->instance_count,
              sizeof *dst->instances) ||
        !grow((void **)&dst->lights, dst->light_count, n * src->light_count,
              sizeof *dst->lights) ||
        !grow((void **)&dst->cameras, dst->camera_count, n * src->camera_count,
              sizeof *dst->cameras) ||
        !append_lines(&dst->warnings_all, src->warnings_all) ||
        !append_lines(&dst->inputs, src->inputs))
        return vkrt_error_set(err, "out of memory placing the scene's files");

    /* Nothing below fails: src's arrays move over. */
    for (uint32_t m = 0; m < src->mesh_count; m++) {
        vkrt_mesh *mesh = &src->meshes[m];
        for (uint32_t t = 0; mesh->material && t < mesh->triangle_count; t++)
            if (mesh->material[t] >= 0)
                mesh->material[t] += (int32_t)dst->material_count;
        dst->meshes[dst->mesh_count + m] = *mesh;
    }
    for (uint32_t i = 0; i < src->material_count; i++) {
        vkrt_material *material = &src->materials[i];
        for (int k = 0; k < VKRT_MAP_COUNT; k++)
            if (material->maps[k].embedded >= 0)
                material->maps[k].embedded += (int32_t)dst->image_count;
        dst->materials[dst->material_count + i] = *material;
    }
    if (src->image_count)
        memcpy(dst->images + dst->image_count, src->images, src->image_count * sizeof *src->images);
    for (uint64_t p = 0; p < n; p++) {
        const float *place = placements[p];
        for (uint32_t i = 0; i < src->instance_count; i++) {
            vkrt_instance *out = &dst->instances[dst->instance_count++];
            out->mesh = src->instances[i].mesh + dst->mesh_count;
            vkrt_transform_compose(place, src->instances[i].transform, out->transform);
        }
        for (uint32_t i = 0; i < src->light_count; i++) {
            vkrt_config_light *light = &dst->lights[dst->light_count++];
            *light = src->lights[i];
            vkrt_transform_point(place, light->position, light->position);
            place_direction(place, light->direction, light->direction);
        }
        for (uint32_t i = 0; i < src->camera_count; i++) {
            vkrt_config_camera *camera = &dst->cameras[dst->camera_count++];
            *camera = src->cameras[i];
            vkrt_transform_point(place, camera->eye, camera->eye);
            vkrt_transform_point(place, camera->look, camera->look);
            place_direction(place, camera->up, camera->up);
        }
    }
    dst->mesh_count += src->mesh_count;
    dst->material_count += src->material_count;
    dst->image_count += src->image_count;
    size_t have = strlen(dst->warnings), more = strlen(src->warnings);
    if (more && have + more + 2 <= sizeof dst->warnings) {
        if (have)
            dst->warnings[have++] = '\n';
        memcpy(dst->warnings + have, src->warnings, more + 1);
    }
    dst->inputs_missing = dst->inputs_missing || src->inputs_missing;
    /* The arrays' elements now belong to dst; free src's shells alone. */
    free(src->meshes);
    free(src->materials);
    free(src->images);
    src->meshes = NULL, src->materials = NULL, src->images = NULL;
    src->mesh_count = src->material_count = src->image_count = 0;
    vkrt_model_free(src);
    return true;
}
