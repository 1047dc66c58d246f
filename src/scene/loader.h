/*
 * loader.h: the scene-file formats vkrt reads, each a function that fills the scene model
 * (model.h) from a file. A new format is one more entry in loader.c and a folder of its own
 * beside src/scene/obj/.
 */
#ifndef VKRT_LOADER_H
#define VKRT_LOADER_H

#include <stdbool.h>

#include "../error.h"
#include "model.h"

/* What a load is asked for beyond the file itself. Zero means the default (sokol's way), so
 * `(vkrt_load_options){0}` and NULL are the defaults; the scene cache's key holds the values. */
typedef struct vkrt_load_options {
    float fps; /* frames per second an animated camera is sampled at; 0: VKRT_LOAD_DEFAULT_FPS */
} vkrt_load_options;

#define VKRT_LOAD_DEFAULT_FPS 24.0f

/* options with each zero (or a NULL options) replaced by its default. */
vkrt_load_options vkrt_load_options_resolve(const vkrt_load_options *options);

typedef struct vkrt_scene_loader {
    const char *name; /* stable and short ("obj"): messages and the scene cache's key name it */
    /* Fills *model from the file at path under options (resolved: never NULL, no zeros): on
     * failure false with err set to "path:LINE: what" and *model left empty. The model's inputs
     * list every other file read. */
    bool (*load)(const char *path, const vkrt_load_options *options, vkrt_model *model,
                 vkrt_error *err);
} vkrt_scene_loader;

/* The loader of the scene file at path, chosen by its extension (case ignored); a file of any
 * other extension is read as Wavefront OBJ, which vkrt has always done. Never NULL. */
const vkrt_scene_loader *vkrt_scene_loader_for(const char *path);

/* Whether a loader claims path's extension (case ignored): such a file is a scene file, which
 * may be rendered without a scene.cfg. */
bool vkrt_scene_loader_claims(const char *path);

#endif
