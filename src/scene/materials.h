/*
 * materials.h: which shader, parameters and textures every triangle of a scene is shaded with.
 *
 * Sources, by precedence: a material of the material file (docs/material-file.md) named as the
 * model's record a triangle names (the user-shader escape hatch); else that record (model.h),
 * mapped to a built-in shader (glsl/materials/) by its BSDF family, its numbers in the built-ins'
 * parameter layout (docs/materials.md); else, for triangles without a material, the built-in
 * diffuse of albedo 0.8. Nothing here knows which file format the model came from. Only materials some triangle uses are
 * kept, and only their shaders and textures are loaded: the shading kernel is generated from
 * exactly this list. The environment (rays that miss) is one more material: the material file's
 * `environment` entry, or the built-in constant environment of scene.cfg's colour.
 * Pure CPU: shader sources are read here, compiled by the renderer.
 */
#ifndef VKRT_MATERIALS_H
#define VKRT_MATERIALS_H

#include <stdbool.h>
#include <stdint.h>

#include "../error.h"
#include "config.h"
#include "material_file.h"
#include "model.h"
#include "texture.h"

#define VKRT_MATERIAL_PARAM_COUNT 20
#define VKRT_MATERIAL_TEXTURE_SLOTS 8
#define VKRT_SCENE_NO_TEXTURE UINT32_MAX

/* A shader the scene uses: a built-in (glsl/materials/<builtin>.glsl) or a user's file. */
typedef struct vkrt_shader_source {
    char *builtin;    /* built-in name, or NULL */
    char *path;       /* user shader path as resolved, or NULL */
    char *text;       /* the user shader's source, or NULL for a built-in */
    char *referrer;   /* "file:LINE: material 'name'" of the first material using it, for messages */
} vkrt_shader_source;

typedef struct vkrt_scene_material {
    char *name;
    char *referrer;   /* where it was defined: "mats.txt:3", "x.mtl", or "(default)" */
    uint32_t shader;  /* index into vkrt_scene_materials.shaders */
    float params[VKRT_MATERIAL_PARAM_COUNT];
    uint32_t textures[VKRT_MATERIAL_TEXTURE_SLOTS]; /* texture set indices or VKRT_SCENE_NO_TEXTURE */
    uint32_t texture_count;
    uint32_t maps;           /* VKRT_MATERIAL_NORMAL_MAP, _BUMP_MAP, _EMISSION_MAP, _COAT, _SHEEN
                                (glsl/shared.h) */
    float sheen;             /* the rough built-ins' sheen weight in [0, 1]: the record's sheen, a
                                material file's number 20 */
    float detail_multiplier; /* the record's detail_scale, 1 by default */
} vkrt_scene_material;

typedef struct vkrt_scene_materials {
    vkrt_scene_material *list;     /* the used materials, then the environment */
    uint32_t count;
    uint32_t environment;          /* index of the environment in list (the last) */
    uint32_t *triangle_material;   /* per triangle of the meshes instances use, each mesh once,
                                      in the order of their first instances: mesh m's triangle
                                      k at mesh_first[m] + k; index into list */
    uint32_t *mesh_first;          /* per mesh of the model: its first entry in
                                      triangle_material, UINT32_MAX for a mesh no instance uses */
    uint32_t triangle_count;       /* entries in triangle_material */
    vkrt_shader_source *shaders;
    uint32_t shader_count;
    vkrt_texture_set textures;
    bool reads_texcoords;          /* some used material has a texture */
} vkrt_scene_materials;

/* Names of the built-in material shaders (glsl/materials/<name>.glsl); NULL-terminated. */
extern const char *const vkrt_builtin_shaders[];

/* Resolves the materials of model under cfg, with file (may be NULL) taking precedence. On failure
 * err names the file and line at fault (a missing texture says which material file and line
 * asked for it; a map on a second uv set, TEXCOORD_1, is refused there) and *out is left
 * empty. Each map's texture index is the entry that reads the image as the map's vkrt_texture_ref
 * says (vkrt_texture_set_view): its sampler, its KHR_texture_transform and, for the roughness,
 * metallic and sheen maps, its channel. */
bool vkrt_scene_materials_resolve(const vkrt_config *cfg, const vkrt_model *model,
                                  const vkrt_material_file *file, vkrt_scene_materials *out,
                                  vkrt_error *err);

/* The scene material of every triangle of the model's instances, instance after instance
 * (vkrt_model_world's order), into *world: where every instance places a mesh of its own, that
 * order is triangle_material's, which *world then is (*owned NULL, nothing allocated); else a
 * new array, also in *owned for the caller to free. False with err set when memory runs out. */
bool vkrt_scene_materials_world(const vkrt_scene_materials *m, const vkrt_model *model,
                                const uint32_t **world, uint32_t **owned, vkrt_error *err);

/* After cfg->environment has changed (vkrt_scene_set_environment): the built-in constant
 * environment takes its radiance. Returns false, changing nothing, where file's `environment`
 * entry is the environment: as with scene.cfg's `environment` line, the entry takes its place. */
bool vkrt_scene_materials_update_environment(vkrt_scene_materials *m, const vkrt_config *cfg,
                                             const vkrt_material_file *file);

/* Frees and zeroes. Safe on a zeroed struct. */
void vkrt_scene_materials_free(vkrt_scene_materials *m);

#endif
