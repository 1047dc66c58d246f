/* scene.c: loading a scene.cfg with everything it names (see scene.h). */
#define _POSIX_C_SOURCE 200809L
#include "scene.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../clock.h"

/* The model's lights before scene.cfg's, so a scene.cfg adds to what its geometry file says; a
 * copy only where both gave some. */
bool vkrt_scene_compose(vkrt_scene *scene, vkrt_error *err)
{
    const vkrt_model *model = &scene->model;
    const vkrt_config *cfg = &scene->config;
    free(scene->composed_lights);
    scene->composed_lights = NULL;
    scene->cameras = cfg->cameras;
    scene->camera_count = cfg->camera_count;
    if (model->light_count == 0 || cfg->light_count == 0) {
        bool from_model = model->light_count > 0;
        scene->lights = from_model ? model->lights : cfg->lights;
        scene->light_count = from_model ? model->light_count : cfg->light_count;
        return true;
    }
    uint32_t count = model->light_count + cfg->light_count;
    scene->composed_lights = malloc(count * sizeof *scene->composed_lights);
    if (!scene->composed_lights)
        return vkrt_error_set(err, "out of memory");
    memcpy(scene->composed_lights, model->lights, model->light_count * sizeof *model->lights);
    memcpy(scene->composed_lights + model->light_count, cfg->lights,
           cfg->light_count * sizeof *cfg->lights);
    scene->lights = scene->composed_lights;
    scene->light_count = count;
    return true;
}

bool vkrt_scene_load_geometry(const char *path, vkrt_scene *scene, vkrt_error *err)
{
    memset(scene, 0, sizeof *scene);
    if (!vkrt_config_load(path, &scene->config, err))
        return false;
    double start = vkrt_clock_ms();
    const char *geometry = scene->config.geometry;
    bool loaded = vkrt_scene_cache_load(vkrt_scene_loader_for(geometry), geometry, &scene->model,
                                        &scene->model_cache, err);
    scene->model_ms = vkrt_clock_ms() - start;
    if (!loaded) {
        /* Say which scene.cfg line asked for the file: the loader's own message follows. */
        vkrt_error_prefix(err, "%s:%d: geometry", path, scene->config.geometry_line);
        vkrt_scene_free(scene);
        return false;
    }
    if (!vkrt_scene_compose(scene, err)) {
        vkrt_scene_free(scene);
        return false;
    }
    return true;
}

bool vkrt_scene_load(const char *path, vkrt_scene *scene, vkrt_error *err)
{
    if (!vkrt_scene_load_geometry(path, scene, err))
        return false;
    if (scene->config.materials &&
        !vkrt_material_file_load(scene->config.materials, &scene->material_file, err)) {
        vkrt_scene_free(scene);
        return false;
    }
    if (!vkrt_scene_materials_resolve(&scene->config, &scene->model,
                                      scene->config.materials ? &scene->material_file : NULL,
                                      &scene->materials, err)) {
        vkrt_scene_free(scene);
        return false;
    }
    return true;
}

/* Writes into out (size bytes) what the scene has: "the scene has 3 cameras, numbered from 0:
 * 0 'front', 1 (no name), 2 'top'", the first few listed. */
static void describe_cameras(const vkrt_scene *scene, char *out, size_t size)
{
    enum { LISTED = 8 };
    uint32_t count = scene->camera_count;
    size_t used = (size_t)snprintf(out, size, "the scene has %u camera%s, numbered from 0",
                                   count, count == 1 ? "" : "s");
    for (uint32_t i = 0; i < count && i < LISTED && used < size; ++i) {
        const char *name = scene->cameras[i].name;
        used += (size_t)snprintf(out + used, size - used, "%s %u %s%s%s", i ? "," : ":", i,
                                 name[0] ? "'" : "(no name)", name, name[0] ? "'" : "");
    }
    if (count > LISTED && used < size)
        snprintf(out + used, size - used, ", ... %u", count - 1);
}

bool vkrt_scene_select_camera(vkrt_scene *scene, const char *which, vkrt_error *err)
{
    uint32_t count = scene->camera_count;
    char *end;
    errno = 0;
    unsigned long long number = strtoull(which, &end, 10);
    bool is_number = which[0] >= '0' && which[0] <= '9' && *end == '\0' && errno == 0;
    char about[600];
    if (is_number) {
        if (number < count) {
            scene->cameras += number;
            scene->camera_count = 1;
            return true;
        }
        describe_cameras(scene, about, sizeof about);
        return vkrt_error_set(err, "no camera %s: %s", which, about);
    }
    for (uint32_t i = 0; i < count; ++i)
        if (strcmp(scene->cameras[i].name, which) == 0) {
            scene->cameras += i;
            scene->camera_count = 1;
            return true;
        }
    describe_cameras(scene, about, sizeof about);
    return vkrt_error_set(err, "no camera named '%s': %s", which, about);
}

bool vkrt_scene_set_environment(vkrt_scene *scene, const float radiance[3], const char *map,
                                bool *constant_used, vkrt_error *err)
{
    vkrt_config *cfg = &scene->config;
    if (map) {
        char *copy = strdup(map);
        if (!copy)
            return vkrt_error_set(err, "out of memory");
        free(cfg->environment_map);
        cfg->environment_map = copy;
        cfg->environment_map_line = 0; /* named on the command line, not on a line */
        cfg->environment_scale = 1;
        cfg->environment_rotate = 0;
    }
    bool used = false;
    if (radiance) {
        free(cfg->environment_map);
        cfg->environment_map = NULL;
        cfg->environment_map_line = 0;
        memcpy(cfg->environment, radiance, sizeof cfg->environment);
        used = vkrt_scene_materials_update_environment(
            &scene->materials, cfg, cfg->materials ? &scene->material_file : NULL);
    }
    if (constant_used)
        *constant_used = used;
    return true;
}

void vkrt_scene_free(vkrt_scene *scene)
{
    vkrt_scene_cache_finish(&scene->model_cache); /* its thread reads the model */
    free(scene->composed_lights);
    vkrt_scene_materials_free(&scene->materials);
    vkrt_material_file_free(&scene->material_file);
    vkrt_model_free(&scene->model);
    vkrt_config_free(&scene->config);
    memset(scene, 0, sizeof *scene);
}
