/*
 * mtl.h: one material of an .mtl file as the file states it, and its translation into the scene
 * model's physically based record (model.h). The reading is mtl_read.cpp's; the translation
 * (mtl_material.c) is where the .mtl's illumination models, its Ns and the PBR extension's
 * numbers become a BSDF family and model units (docs/materials.md).
 */
#ifndef VKRT_MTL_H
#define VKRT_MTL_H

#include <stdbool.h>

#include "../model.h"

/* The fields vkrt reads. Absent fields keep the defaults in brackets. */
typedef struct vkrt_mtl {
    char *name;
    float kd[3];   /* diffuse albedo [0.8 0.8 0.8] */
    float ks[3];   /* specular [0 0 0] */
    float ke[3];   /* emission [0 0 0] */
    float ns;      /* Phong exponent [0] */
    float ni;      /* index of refraction [1] */
    float d;       /* opacity [1] */
    int illum;     /* illumination model [2] */
    float tf[3];   /* transmission filter, Tf (or Kt) [1 1 1] */
    char *map_kd;  /* diffuse texture path resolved against the .mtl's folder, or NULL */
    char *map_d;   /* alpha (coverage) texture path, resolved the same way, or NULL */
    char *mtl_path;/* the .mtl file the material came from (as the OBJ's mtllib reaches it), or NULL */
    int map_kd_line, map_d_line; /* line of the map_Kd / map_d statement in mtl_path (the last one,
                                    which wins), 0 if unknown: texture errors name it */
    /* The PBR extension (Blender's exporter): roughness Pr [-1: not given] and metallic Pm [0],
     * their maps (resolved as map_Kd, or NULL) and lines; clearcoat Pc and its roughness Pcr [0];
     * sheen Ps [0] and its map (the loader warns where they sit on a mirror or glass, which have
     * no sheen). */
    bool pbr;      /* the block has Pr, Pm, map_Pr or map_Pm, a Pc or Ps above 0, or a map_Ps */
    float pr, pm, pc, pcr, ps;
    char *map_pr, *map_pm, *map_ps;
    int map_pr_line, map_pm_line, map_ps_line;
    /* Surface detail and emission maps (resolved as map_Kd, or NULL) and their lines: `norm` (a
     * tangent-space normal map), `map_Bump` or `bump` (a height map, or a normal map where the
     * image is one: docs/material-file.md) with its -bm multiplier [1], and `map_Ke`. */
    char *norm, *map_bump, *map_ke;
    int norm_line, map_bump_line, map_ke_line;
    float bump_multiplier;
    bool ke_given; /* the block has Ke: without it a map_Ke is the emission itself (Ke 1 1 1) */
} vkrt_mtl;

/* The model's record of m: its family and numbers in model units, its texture references with
 * their lines and colour spaces. The strings are copied (name, mtl_path or "(.mtl)", maps); false
 * when memory runs out, with *out's strings freed. */
bool vkrt_mtl_to_material(const vkrt_mtl *m, vkrt_material *out);

/* The GGX roughness (glsl/lib/microfacet.glsl: alpha = roughness^2) of a Blinn-Phong exponent
 * ns, for .mtl materials without Pr: alpha = sqrt(2 / (ns + 2)), the exponent whose Phong lobe
 * matches a Beckmann lobe of width alpha (Walter et al. 2007, "Microfacet Models for
 * Refraction through Rough Surfaces", section 5.2; GGX and Beckmann agree near the peak). Ns 0
 * is roughness 1. */
float vkrt_ns_roughness(float ns);

/* Frees m's strings and zeroes it. */
void vkrt_mtl_free(vkrt_mtl *m);

#endif
