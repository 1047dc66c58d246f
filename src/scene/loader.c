/* loader.c: the scene-file formats by extension (see loader.h). */
#define _POSIX_C_SOURCE 200809L
#include "loader.h"

#include <string.h>
#include <strings.h>

#include "gltf/gltf_load.h"
#include "obj/obj_load.h"

/* An OBJ has nothing an option changes. */
static bool load_obj(const char *path, const vkrt_load_options *options, vkrt_model *model,
                     vkrt_error *err)
{
    (void)options;
    return vkrt_obj_load(path, model, err);
}

/* The first entry is the fallback for unknown extensions. */
static const vkrt_scene_loader loaders[] = {
    {"obj", load_obj},
    {"gltf", vkrt_gltf_load},
    {"gltf", vkrt_gltf_load},
};

static const char *const extensions[] = {".obj", ".gltf", ".glb"};

vkrt_load_options vkrt_load_options_resolve(const vkrt_load_options *options)
{
    vkrt_load_options resolved = options ? *options : (vkrt_load_options){0};
    if (!(resolved.fps > 0.0f))
        resolved.fps = VKRT_LOAD_DEFAULT_FPS;
    return resolved;
}

/* The index of the loader claiming path's extension, or -1. */
static int claimed_by(const char *path)
{
    size_t length = path ? strlen(path) : 0;
    for (size_t i = 0; i < sizeof loaders / sizeof *loaders; ++i) {
        size_t n = strlen(extensions[i]);
        if (length >= n && strcasecmp(path + length - n, extensions[i]) == 0)
            return (int)i;
    }
    return -1;
}

const vkrt_scene_loader *vkrt_scene_loader_for(const char *path)
{
    int i = claimed_by(path);
    return &loaders[i < 0 ? 0 : i];
}

bool vkrt_scene_loader_claims(const char *path)
{
    return claimed_by(path) >= 0;
}
