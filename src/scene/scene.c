/* scene.c: loading a scene.cfg with everything it names (see scene.h). */
#include "scene.h"

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
    bool loaded = vkrt_scene_cache_load(vkrt_scene_loader_for(geometry), geometry, NULL,
                                        &scene->model, &scene->model_cache, err);
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
