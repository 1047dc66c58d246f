/*
 * scene.h: a loaded scene: its scene.cfg, the OBJ it names, its material file, and the materials,
 * shaders and textures its triangles use. Pure CPU, no Vulkan.
 */
#ifndef VKRT_SCENE_H
#define VKRT_SCENE_H

#include <stdbool.h>

#include "../error.h"
#include "config.h"
#include "material_file.h"
#include "materials.h"
#include "obj_load.h"
#include "scene_cache.h"

typedef struct vkrt_scene {
    vkrt_config config;
    vkrt_mesh mesh;
    vkrt_material_file material_file;  /* empty when scene.cfg names none */
    vkrt_scene_materials materials;
    double obj_ms; /* wall-clock time of reading the OBJ and its .mtl files (--verbose) */
    vkrt_scene_cache_report obj_cache; /* whether they came from the scene cache (--verbose) */
} vkrt_scene;

/* Loads the scene.cfg at path, the OBJ it names, the material file and every shader and texture
 * the used materials need. On failure returns false with err naming the file and line, and
 * *scene left empty. */
bool vkrt_scene_load(const char *path, vkrt_scene *scene, vkrt_error *err);

/* Loads only the scene.cfg and its OBJ (with the .mtl's fields, but no material file, shader or
 * texture): what tracing alone needs (`vkrt bench`). The renderer then shades every triangle with
 * the default material. Same contract as vkrt_scene_load. */
bool vkrt_scene_load_geometry(const char *path, vkrt_scene *scene, vkrt_error *err);

/* Frees the scene and zeroes it. Safe on a zeroed scene. */
void vkrt_scene_free(vkrt_scene *scene);

#endif
