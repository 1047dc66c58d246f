/*
 * obj_load.h: Wavefront OBJ (and its .mtl) loading, through tinyobjloader.
 *
 * The loader (obj_load.cpp, with its pre-scan in obj_scan.cpp and the parallel read of the
 * geometry in obj_geometry.cpp: the project's C++ files) wraps tinyobjloader behind this C
 * interface; the geometry is read on every core.
 * The result is de-indexed, one record per triangle corner, which is what the kernels read:
 * polygons become triangle fans, negative indices are resolved, faces without normals get their
 * geometric normal, and non-finite coordinates or out-of-range indices are errors naming the
 * file and line. tinyobjloader's own messages never reach the user as it words them: they are
 * translated into vkrt's ("file:LINE: what is wrong", warnings with "warning:").
 */
#ifndef VKRT_OBJ_LOAD_H
#define VKRT_OBJ_LOAD_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "../error.h"

/* One material of the .mtl, the fields vkrt reads. Absent fields keep the defaults in brackets. */
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
     * their maps (resolved as map_Kd, or NULL) and lines; clearcoat Pc and its roughness Pcr [0]
     * (materials.c makes them the coat's weight and roughness); sheen Ps [0] and its map (the
     * loader warns where they sit on a mirror or glass, which have no sheen). */
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

typedef struct vkrt_mesh {
    uint32_t triangle_count;
    float *positions;       /* 9 floats per triangle: v0 xyz, v1 xyz, v2 xyz; all finite */
    float *normals;         /* 9 floats per triangle, unit length, or NULL if no face had normals;
                               faces without normals in a file that has some get the geometric one */
    float *texcoords;       /* 6 floats per triangle, or NULL if no face had texture coordinates */
    int32_t *material;      /* per triangle: index into materials, or -1 for the default material */
    vkrt_mtl *materials;
    uint32_t material_count;
    float bounds_min[3], bounds_max[3]; /* of all positions; zero when there are no triangles */
    /* Warnings, one a line, each "file:LINE: warning: what" (file the OBJ or a .mtl; ":LINE" left
     * out where no line applies), tinyobjloader's translated. Warnings of one kind about one
     * file fold into one line with their count and the first few names: "x.mtl: warning: 35
     * materials define both d and Tr; d is used (a, b, c, ...)". Whole lines while they fit, or "". */
    char warnings[1024];
    char *warnings_all;     /* the same unfolded: every warning on its own line (malloc'd), or NULL
                               when there are none */
    /* What the load read besides the OBJ, for the scene cache (scene_cache.h): the .mtl files,
     * one path a line (malloc'd, NULL when none), and whether an mtllib named one not found. */
    char *mtl_files;
    bool mtl_missing;
} vkrt_mesh;

/* Loads the OBJ at path with the .mtl files it names. On failure returns false with err set to
 * "path:LINE: message" where a line is known ("path: message" otherwise) and *mesh left empty.
 * A file with no triangles is an error. */
bool vkrt_obj_load(const char *path, vkrt_mesh *mesh, vkrt_error *err);

/* Parses OBJ text already in memory (size bytes; NUL bytes among them are an error, as in a file),
 * with the same checks, messages and contract as vkrt_obj_load. name stands for the path in
 * messages (NULL: "(obj)"). base_dir is the folder mtllib names are resolved against ("" for the
 * current folder); NULL means no .mtl is read at all: mtllib lines are ignored and every triangle
 * gets the default material, so the parse touches no file (what a fuzzer wants). */
bool vkrt_obj_parse(const char *text, size_t size, const char *name, const char *base_dir,
                    vkrt_mesh *mesh, vkrt_error *err);

/* vkrt_obj_parse with the geometry read in chunks of about chunk_bytes (each ends at a line end)
 * on up to `threads` threads; 0 for either is the default vkrt_obj_load uses (a few MiB, one
 * thread per core). The result does not depend on them: tests cut the text at every line. */
bool vkrt_obj_parse_split(const char *text, size_t size, const char *name, const char *base_dir,
                          size_t chunk_bytes, unsigned threads, vkrt_mesh *mesh, vkrt_error *err);

/* Writes the mesh's warnings to out, each line after prefix (e.g. "vkrt: "): the folded lines of
 * warnings, or with verbose every one (warnings_all). Writes nothing when there are none. */
void vkrt_mesh_print_warnings(const vkrt_mesh *mesh, const char *prefix, bool verbose, FILE *out);

/* Frees what vkrt_obj_load or vkrt_obj_parse allocated and zeroes *mesh. Safe on a zeroed struct. */
void vkrt_mesh_free(vkrt_mesh *mesh);

#endif
