/*
 * scene.h: a loaded scene: its scene.cfg and the OBJ it names. Pure CPU, no Vulkan.
 */
#ifndef VKRT_SCENE_H
#define VKRT_SCENE_H

#include <stdbool.h>

#include "../error.h"
#include "config.h"
#include "obj_load.h"

typedef struct vkrt_scene {
    vkrt_config config;
    vkrt_mesh mesh;
} vkrt_scene;

/* Loads the scene.cfg at path and the OBJ it names. On failure returns false with err naming the
 * file and line, and *scene left empty. */
bool vkrt_scene_load(const char *path, vkrt_scene *scene, vkrt_error *err);

/* Frees the scene and zeroes it. Safe on a zeroed scene. */
void vkrt_scene_free(vkrt_scene *scene);

#endif
