/*
 * scene.h: a loaded scene: its scene.cfg, the model its geometry file gives (model.h, through the
 * loader of that file's format, loader.h), its material file, and the materials, shaders and
 * textures its triangles use. Pure CPU, no Vulkan.
 */
#ifndef VKRT_SCENE_H
#define VKRT_SCENE_H

#include <stdbool.h>

#include "../error.h"
#include "config.h"
#include "loader.h"
#include "material_file.h"
#include "materials.h"
#include "model.h"
#include "scene_cache.h"

typedef struct vkrt_scene {
    vkrt_config config;
    vkrt_model model;
    vkrt_material_file material_file;  /* empty when scene.cfg names none */
    vkrt_scene_materials materials;
    /* The lights and cameras everything downstream reads (the renderer, the commands, the viewer):
     * the geometry files' lights, then scene.cfg's; scene.cfg's cameras, one per frame, or where it
     * has none the geometry files', or else framed_camera (at least one). They point into model
     * and config, or into composed_lights where both gave lights, or framed_camera; nothing
     * downstream reads config or model for them. */
    const vkrt_config_light *lights;
    uint32_t light_count;
    const vkrt_config_camera *cameras;
    uint32_t camera_count;
    vkrt_config_light *composed_lights; /* malloc'd where the model and scene.cfg both gave lights */
    vkrt_config_camera framed_camera;   /* the view of the whole scene when no file gave a camera */
    double model_ms; /* wall-clock time of loading the model (--verbose) */
    double materials_ms; /* of resolving the materials: decoding their textures (--verbose) */
    vkrt_scene_cache_report model_cache; /* whether it came from the scene cache (--verbose) */
} vkrt_scene;

/* Loads the scene.cfg at path, the scene files it names, the material file and every shader and
 * texture the used materials need. On failure returns false with err naming the file and line,
 * and *scene left empty. */
bool vkrt_scene_load(const char *path, vkrt_scene *scene, vkrt_error *err);
/* path may also be a scene file alone (`vkrt render model.glb`: an extension a loader claims,
 * loader.h): it then gets vkrt_config_for_geometry's settings, its own cameras or a framed view,
 * and a uniform white sky (environment 1 1 1) when nothing in it gives light. */

/* vkrt_scene_load with the loaders' options (loader.h: the rate an animated camera is sampled
 * at); NULL: their defaults. */
bool vkrt_scene_load_with(const char *path, const vkrt_load_options *options, vkrt_scene *scene,
                          vkrt_error *err);

/* Loads only the scene.cfg and its model (with the material records, but no material file, shader
 * or texture): what tracing alone needs (`vkrt bench`). The renderer then shades every triangle
 * with the default material. Same contract as vkrt_scene_load. */
bool vkrt_scene_load_geometry(const char *path, vkrt_scene *scene, vkrt_error *err);

/* Sets the scene's lights and cameras from its model and config (the loads above call it): the
 * model's lights, then scene.cfg's; scene.cfg's cameras. False only when out of memory. */
bool vkrt_scene_compose(vkrt_scene *scene, vkrt_error *err);

/* Keeps only the camera `which` names (what `--camera` picks): a whole number N, the scene's
 * camera N counted from 0 in the order scene->cameras lists them, or else the name of one (the
 * first of that name, compared exactly). scene->cameras then points at it and camera_count is
 * 1: a flythrough becomes that one frame. On failure returns false with err saying what the
 * scene has ("no camera named 'x': the scene has 3 cameras, numbered from 0: 0 'front', 1
 * 'top', 2 (no name)", at most a few listed) and leaves the scene as it was. */
bool vkrt_scene_select_camera(vkrt_scene *scene, const char *which, vkrt_error *err);

/* Replaces the scene's environment, whatever scene.cfg said (`--environment`,
 * `--environment-map`): radiance (non-NULL) makes it that constant radiance with no map; map
 * (non-NULL) makes it that equirectangular image (the path as given, opened by the renderer),
 * at scale 1 and rotate 0. A material file's `environment` entry still takes the place of a
 * constant, as it does of scene.cfg's line: *constant_used (may be NULL) says whether the
 * constant is what rays that miss see. False with err only when out of memory. */
bool vkrt_scene_set_environment(vkrt_scene *scene, const float radiance[3], const char *map,
                                bool *constant_used, vkrt_error *err);

/* Frees the scene and zeroes it. Safe on a zeroed scene. */
void vkrt_scene_free(vkrt_scene *scene);

#endif
