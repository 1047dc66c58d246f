/*
 * material_file.h: the material file parser.
 *
 * A material file (docs/material-file.md) gives each material an OBJ's `usemtl` can name a
 * shader, up to 8 textures and up to 16 numbers, one material per line:
 *     <name> <texture-count> <texture-file>... <shader> [<number>...]
 * The entry named `environment` is the shader for rays that miss everything. Parsing is pure
 * CPU work and touches no file but the one vkrt_material_file_load reads: paths are resolved
 * (joined to the file's folder), not opened, so a missing texture or shader is reported later
 * by the code that reads it, with the material's line.
 */
#ifndef VKRT_MATERIAL_FILE_H
#define VKRT_MATERIAL_FILE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "../error.h"

enum {
    VKRT_MATERIAL_FILE_MAX_TEXTURES = 8,
    VKRT_MATERIAL_FILE_MAX_PARAMS = 21, /* 0-19 the shader's param(i); 20 the rough built-ins' sheen */
};

typedef struct vkrt_material_def {
    char *name;
    char **textures;          /* texture_count resolved paths; NULL when there are none */
    uint32_t texture_count;
    char *shader;             /* resolved path of a user shader (ends in .glsl), or "@name" for a
                                 built-in, name of [a-z0-9_]+ (the renderer checks it exists) */
    float params[VKRT_MATERIAL_FILE_MAX_PARAMS]; /* param_count given, finite; the rest 0 */
    uint32_t param_count;
    int line;                 /* where it was defined */
} vkrt_material_def;

typedef struct vkrt_material_file {
    char *path;               /* as given (the name used in messages) */
    vkrt_material_def *defs;  /* in file order; names are unique */
    uint32_t count;
} vkrt_material_file;

/* Reads and parses the material file at path; relative paths in it are resolved against the
 * folder of path. On failure returns false, fills err with "path:LINE: message" (or "path:
 * message" when the file cannot be read) and leaves *file empty (nothing to free). On success
 * the caller frees *file with vkrt_material_file_free. A file without materials is valid. */
bool vkrt_material_file_load(const char *path, vkrt_material_file *file, vkrt_error *err);

/* Parses material file text already in memory: size bytes (a NUL among them is an error, not
 * an end); name is used in messages and kept as file->path (NULL: "material file"); base_dir
 * resolves relative paths (NULL or "" for the current folder). Same contract as
 * vkrt_material_file_load. */
bool vkrt_material_file_parse(const char *text, size_t size, const char *name,
                              const char *base_dir, vkrt_material_file *file, vkrt_error *err);

/* The material called name, or NULL if file has none (file may be NULL). */
const vkrt_material_def *vkrt_material_file_find(const vkrt_material_file *file,
                                                 const char *name);

/* Frees what a successful load or parse allocated, and zeroes *file. Safe on a zeroed struct. */
void vkrt_material_file_free(vkrt_material_file *file);

#endif
