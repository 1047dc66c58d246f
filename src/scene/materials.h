/*
 * materials.h: which shader, parameters and textures every triangle of a scene is shaded with.
 *
 * Sources, by precedence: a material of the material file (docs/material-file.md) whose name the
 * OBJ's `usemtl` names; else the OBJ's .mtl material, mapped to a built-in shader
 * (glsl/materials/) by its illumination model and fields (docs/materials.md); else, for triangles
 * without a material, the built-in diffuse of albedo 0.8. Only materials some triangle uses are
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
#include "obj_load.h"
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
    float sheen;             /* the rough built-ins' sheen weight in [0, 1]: the .mtl's Ps (1 where
                                a map_Ps replaces it), a material file's number 20 */
    float detail_multiplier; /* the normal or bump map's -bm, 1 by default */
} vkrt_scene_material;

typedef struct vkrt_scene_materials {
    vkrt_scene_material *list;     /* the used materials, then the environment */
    uint32_t count;
    uint32_t environment;          /* index of the environment in list (the last) */
    uint32_t *triangle_material;   /* per triangle, in OBJ order: index into list */
    vkrt_shader_source *shaders;
    uint32_t shader_count;
    vkrt_texture_set textures;
    bool reads_texcoords;          /* some used material has a texture */
} vkrt_scene_materials;

/* Names of the built-in material shaders (glsl/materials/<name>.glsl); NULL-terminated. */
extern const char *const vkrt_builtin_shaders[];

/* Resolves the materials of mesh under cfg, with file (may be NULL) taking precedence. On failure
 * err names the file and line at fault (a missing texture says which .mtl or material-file line
 * asked for it) and *out is left empty. */
bool vkrt_scene_materials_resolve(const vkrt_config *cfg, const vkrt_mesh *mesh,
                                  const vkrt_material_file *file, vkrt_scene_materials *out,
                                  vkrt_error *err);

/* The GGX roughness (glsl/lib/microfacet.glsl: alpha = roughness^2) of a Blinn-Phong exponent
 * ns, for .mtl materials without Pr: alpha = sqrt(2 / (ns + 2)), the exponent whose Phong lobe
 * matches a Beckmann lobe of width alpha (Walter et al. 2007, "Microfacet Models for
 * Refraction through Rough Surfaces", section 5.2; GGX and Beckmann agree near the peak). Ns 0
 * is roughness 1. */
float vkrt_ns_roughness(float ns);

/* Frees and zeroes. Safe on a zeroed struct. */
void vkrt_scene_materials_free(vkrt_scene_materials *m);

#endif
