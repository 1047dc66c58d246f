/*
 * shared_scenes.c: where the tests find the shared scenes (shared_scenes.h).
 */
#define _POSIX_C_SOURCE 200809L
#include "shared_scenes.h"

#include <stdio.h>
#include <stdlib.h>
#include <sys/stat.h>

const char *shared_scenes_dir(void)
{
    const char *dir = getenv("VKRT_SCENES_DIR");
    struct stat st;
    if (!dir || !*dir || stat(dir, &st) != 0 || !S_ISDIR(st.st_mode)) {
        printf("VKRT_SCENES_DIR %s; skipping shared-scene tests\n", dir ? "is not a folder" : "unset");
        return NULL;
    }
    return dir;
}
