/* loader.c: the scene-file formats by extension (see loader.h). */
#define _POSIX_C_SOURCE 200809L
#include "loader.h"

#include <string.h>
#include <strings.h>

#include "obj/obj_load.h"

static const vkrt_scene_loader loaders[] = {
    {"obj", vkrt_obj_load},
};

static const char *const extensions[] = {".obj"};

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
