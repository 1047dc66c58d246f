/* scene.c: loading a scene.cfg with everything it names (see scene.h). */
#define _POSIX_C_SOURCE 200809L
#include "scene.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "../clock.h"
#include "model_place.h"

/* A camera that sees the whole scene when neither scene.cfg nor the scene file gives one: from
 * the front (+z, the side glTF models face) and a little above, the box's bounding sphere just
 * inside the narrower of the image's two fields of view. */
static void frame_scene(const vkrt_model *model, const vkrt_config *cfg, vkrt_config_camera *out)
{
    static const double fov_deg = 40.0, pi = 3.14159265358979323846;
    double centre[3], radius2 = 0.0;
    for (int i = 0; i < 3; i++) {
        centre[i] = 0.5 * ((double)model->bounds_min[i] + model->bounds_max[i]);
        double half = 0.5 * ((double)model->bounds_max[i] - model->bounds_min[i]);
        radius2 += half * half;
    }
    double radius = radius2 > 0.0 ? sqrt(radius2) : 1.0;
    double half_v = 0.5 * fov_deg * pi / 180.0;
    double half_h = atan(tan(half_v) * cfg->width / cfg->height);
    double distance = radius / sin(half_v < half_h ? half_v : half_h);
    static const double towards[3] = {0.0, 0.2425356250363330, 0.9701425001453319}; /* (0,1,4)/|.| */
    memset(out, 0, sizeof *out);
    for (int i = 0; i < 3; i++) {
        out->look[i] = (float)centre[i];
        out->eye[i] = (float)(centre[i] + towards[i] * distance);
    }
    out->up[1] = 1.0f;
    out->fov_deg = (float)fov_deg;
    snprintf(out->name, sizeof out->name, "framed");
}

static bool has_emission(const vkrt_model *model)
{
    for (uint32_t i = 0; i < model->material_count; i++) {
        const vkrt_material *m = &model->materials[i];
        if (m->emission[0] > 0.0f || m->emission[1] > 0.0f || m->emission[2] > 0.0f)
            return true;
    }
    return false;
}

/* The model's lights before scene.cfg's, so a scene.cfg adds to what its geometry file says; a
 * copy only where both gave some. scene.cfg's cameras replace the file's. */
bool vkrt_scene_compose(vkrt_scene *scene, vkrt_error *err)
{
    const vkrt_model *model = &scene->model;
    const vkrt_config *cfg = &scene->config;
    free(scene->composed_lights);
    scene->composed_lights = NULL;
    if (cfg->camera_count > 0) {
        scene->cameras = cfg->cameras;
        scene->camera_count = cfg->camera_count;
    } else if (model->camera_count > 0) {
        scene->cameras = model->cameras;
        scene->camera_count = model->camera_count;
    } else {
        frame_scene(model, cfg, &scene->framed_camera);
        scene->cameras = &scene->framed_camera;
        scene->camera_count = 1;
    }
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

/* Loads geometry line i's file (through the scene cache) into *model; the error names the line. */
static bool load_file(vkrt_scene *scene, uint32_t i, const vkrt_load_options *options,
                      vkrt_model *model, vkrt_scene_cache_report *report, vkrt_error *err)
{
    const vkrt_config_geometry *g = &scene->config.geometries[i];
    if (vkrt_scene_cache_load(vkrt_scene_loader_for(g->path), g->path, options, model, report,
                              err))
        return true;
    /* Say which scene.cfg line asked for the file: the loader's own message follows. */
    if (!scene->config.from_scene_file)
        vkrt_error_prefix(err, "%s:%d: geometry", scene->config.path, g->line);
    return false;
}

/* Every geometry line's file placed into scene->model: one unplaced file is the model as its
 * loader gave it (to the bit); otherwise each file is loaded once and placed once per line that
 * names it. */
static bool load_geometries(vkrt_scene *scene, const vkrt_load_options *options, vkrt_error *err)
{
    const vkrt_config *cfg = &scene->config;
    if (cfg->geometry_count == 1 && !cfg->geometries[0].placed)
        return load_file(scene, 0, options, &scene->model, &scene->model_cache, err);
    float(*placements)[12] = malloc(cfg->geometry_count * sizeof *placements);
    if (!placements)
        return vkrt_error_set(err, "out of memory");
    bool ok = true;
    for (uint32_t i = 0; ok && i < cfg->geometry_count; i++) {
        bool seen = false;
        for (uint32_t j = 0; j < i && !seen; j++)
            seen = strcmp(cfg->geometries[j].path, cfg->geometries[i].path) == 0;
        if (seen)
            continue;
        uint32_t count = 0;
        for (uint32_t j = i; j < cfg->geometry_count; j++)
            if (strcmp(cfg->geometries[j].path, cfg->geometries[i].path) == 0)
                memcpy(placements[count++], cfg->geometries[j].transform, sizeof *placements);
        vkrt_model file = {0};
        /* The first file's report is the one --verbose shows; its entry is stored before the
         * model moves (the storing thread reads it). */
        vkrt_scene_cache_report *report = i == 0 ? &scene->model_cache : NULL;
        ok = load_file(scene, i, options, &file, report, err);
        if (ok && report)
            vkrt_scene_cache_finish(report);
        ok = ok && vkrt_model_place(&scene->model, &file, placements, count, err);
        vkrt_model_free(&file);
    }
    free(placements);
    return ok && vkrt_model_finish(&scene->model, err);
}

/* Loads the scene.cfg at path, or makes the settings of a scene file given alone. */
static bool load_config(const char *path, vkrt_config *cfg, vkrt_error *err)
{
    size_t n = strlen(path);
    bool scene_file = n < 4 || strcasecmp(path + n - 4, ".cfg") != 0;
    scene_file = scene_file && vkrt_scene_loader_claims(path);
    return scene_file ? vkrt_config_for_geometry(path, cfg, err)
                      : vkrt_config_load(path, cfg, err);
}

static bool load_geometry_with(const char *path, const vkrt_load_options *options,
                               vkrt_scene *scene, vkrt_error *err)
{
    memset(scene, 0, sizeof *scene);
    if (!load_config(path, &scene->config, err))
        return false;
    double start = vkrt_clock_ms();
    bool loaded = load_geometries(scene, options, err);
    scene->model_ms = vkrt_clock_ms() - start;
    if (!loaded || !vkrt_scene_compose(scene, err)) {
        vkrt_scene_free(scene);
        return false;
    }
    vkrt_config *cfg = &scene->config;
    if (cfg->from_scene_file) {
        /* A file with nothing that gives light is seen under a uniform white sky. */
        if (scene->light_count == 0 && !has_emission(&scene->model))
            cfg->environment[0] = cfg->environment[1] = cfg->environment[2] = 1.0f;
        /* One image per camera of a flythrough: "model0000.png", "model0001.png", ... */
        size_t stem = strlen(cfg->output) - 4;
        char *pattern = scene->camera_count > 1 ? malloc(stem + 9) : NULL;
        if (pattern) {
            memcpy(pattern, cfg->output, stem);
            memcpy(pattern + stem, "%04d.png", 9);
            free(cfg->output);
            cfg->output = pattern;
        }
    }
    return true;
}

bool vkrt_scene_load_geometry(const char *path, vkrt_scene *scene, vkrt_error *err)
{
    return load_geometry_with(path, NULL, scene, err);
}

bool vkrt_scene_load(const char *path, vkrt_scene *scene, vkrt_error *err)
{
    return vkrt_scene_load_with(path, NULL, scene, err);
}

bool vkrt_scene_load_with(const char *path, const vkrt_load_options *options, vkrt_scene *scene,
                          vkrt_error *err)
{
    if (!load_geometry_with(path, options, scene, err))
        return false;
    if (scene->config.materials &&
        !vkrt_material_file_load(scene->config.materials, &scene->material_file, err)) {
        vkrt_scene_free(scene);
        return false;
    }
    double start = vkrt_clock_ms();
    bool resolved = vkrt_scene_materials_resolve(
        &scene->config, &scene->model, scene->config.materials ? &scene->material_file : NULL,
        &scene->materials, err);
    scene->materials_ms = vkrt_clock_ms() - start;
    if (!resolved) {
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
