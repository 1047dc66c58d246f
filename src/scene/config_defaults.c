/* config_defaults.c: the settings no scene.cfg line gives, those of a scene file rendered
 * without a scene.cfg, and freeing what a config holds (config.h). */
#define _POSIX_C_SOURCE 200809L
#include <stdlib.h>
#include <string.h>

#include "config.h"

void vkrt_config_defaults(vkrt_config *c)
{
    memset(c, 0, sizeof *c);
    c->width = 640;
    c->height = 480;
    c->samples = 1;
    c->max_depth = 6;
    c->accel = VKRT_ACCEL_AUTO;
    c->integrator = VKRT_INTEGRATOR_AUTO;
    c->environment_scale = 1.0f;
}

bool vkrt_config_for_geometry(const char *path, vkrt_config *cfg, vkrt_error *err)
{
    if (cfg)
        memset(cfg, 0, sizeof *cfg);
    if (!path || !cfg)
        return vkrt_error_set(err, "scene file: no path given");
    vkrt_config c;
    vkrt_config_defaults(&c);
    c.from_scene_file = true;
    c.geometries = calloc(1, sizeof *c.geometries);
    const char *file = strrchr(path, '/');
    file = file ? file + 1 : path;
    const char *dot = strrchr(file, '.');
    size_t stem = dot && dot != file ? (size_t)(dot - file) : strlen(file);
    c.path = strdup(path);
    c.output = malloc(stem + 5);
    if (!c.geometries || !c.path || !c.output || !(c.geometries[0].path = strdup(path))) {
        vkrt_config_free(&c);
        return vkrt_error_set(err, "%s: out of memory", path);
    }
    for (int i = 0; i < 3; i++)
        c.geometries[0].transform[5 * i] = 1.0f; /* the identity: calloc zeroed the rest */
    c.geometry_count = 1;
    memcpy(c.output, file, stem);
    memcpy(c.output + stem, ".png", 5);
    *cfg = c;
    return true;
}

void vkrt_config_free(vkrt_config *cfg)
{
    if (!cfg)
        return;
    free(cfg->path);
    for (uint32_t i = 0; cfg->geometries && i < cfg->geometry_count; i++)
        free(cfg->geometries[i].path);
    free(cfg->geometries);
    free(cfg->materials);
    free(cfg->output);
    free(cfg->environment_map);
    free(cfg->lights);
    free(cfg->cameras);
    memset(cfg, 0, sizeof *cfg);
}
