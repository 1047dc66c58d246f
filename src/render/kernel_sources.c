/* kernel_sources.c: lookup of the embedded kernels (see kernel_sources.h). */
#define _POSIX_C_SOURCE 200809L
#include "kernel_sources.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../test_hooks.h"

static char *read_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    char *text = NULL;
    if (fseek(f, 0, SEEK_END) == 0) {
        long size = ftell(f);
        if (size >= 0 && fseek(f, 0, SEEK_SET) == 0 && (text = malloc((size_t)size + 1))) {
            if (fread(text, 1, (size_t)size, f) == (size_t)size) {
                text[size] = '\0';
            } else {
                free(text);
                text = NULL;
            }
        }
    }
    fclose(f);
    return text;
}

char *vkrt_kernel_source_lookup(void *user, const char *path)
{
    (void)user;
    const char *dir = vkrt_test_hooks_get()->glsl_dir;
    if (dir && *dir) {
        char full[4096];
        if (snprintf(full, sizeof full, "%s/%s", dir, path) >= (int)sizeof full)
            return NULL;
        return read_file(full);
    }
    for (const vkrt_kernel_source *k = vkrt_kernel_sources; k->path; ++k)
        if (strcmp(k->path, path) == 0)
            return strdup(k->text);
    return NULL;
}
