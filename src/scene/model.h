/*
 * model.h: a scene as plain entities that no file format owns.
 *
 * A loader (src/scene/obj/ for Wavefront OBJ and its .mtl) translates its format into meshes,
 * instances of them, physically based materials with their texture references, lights and
 * cameras; everything downstream (materials.c, the scene cache, the renderer) reads this and never
 * the format. Unit conversions (an .mtl's Ns to roughness, a format's light units) happen in the
 * loader. Pure CPU, no Vulkan.
 */
#ifndef VKRT_MODEL_H
#define VKRT_MODEL_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "../error.h"
#include "config.h"
#include "texture.h"

/* Triangles as the kernels read them: one record per triangle corner, no index buffer. */
typedef struct vkrt_mesh {
    uint32_t triangle_count;
    float *positions;  /* 9 floats per triangle: v0 xyz, v1 xyz, v2 xyz; all finite */
    float *normals;    /* 9 floats per triangle, unit length, or NULL: the geometric normal */
    float *texcoords;  /* 6 floats per triangle, or NULL */
    float *tangents;   /* 12 floats per triangle (xyz and the bitangent's sign), or NULL; no loader
                          gives them yet and the renderer does not read them */
    int32_t *material; /* per triangle: index into vkrt_model.materials, or -1 for the default */
    float bounds_min[3], bounds_max[3]; /* of all positions; zero when there are no triangles */
} vkrt_mesh;

/* A mesh placed in the world: world = transform * (x, y, z, 1), the 3x4 matrix row-major. */
typedef struct vkrt_instance {
    uint32_t mesh;       /* index into vkrt_model.meshes */
    float transform[12];
} vkrt_instance;

/* Which scattering model a material is, as its loader decided from the format's own words
 * (materials.c maps each family to a built-in shader, docs/materials.md). */
typedef enum vkrt_bsdf {
    VKRT_BSDF_DIFFUSE,          /* Lambert of base_colour (times its texture) */
    VKRT_BSDF_GLOSSY_PHONG,     /* diffuse plus a normalised Blinn-Phong lobe of specular and
                                   specular_exponent */
    VKRT_BSDF_MIRROR,           /* perfect reflection tinted by specular */
    VKRT_BSDF_DIELECTRIC,       /* smooth glass of ior, tinted by transmission_filter */
    VKRT_BSDF_ROUGH_DIELECTRIC, /* GGX glass of ior and roughness */
    VKRT_BSDF_PRINCIPLED,       /* metallic-roughness base with optional coat and sheen */
    VKRT_BSDF_EMITTER,          /* emission only, no reflection */
} vkrt_bsdf;

/* How a texture is sampled (glTF's sampler): per axis, repeat, clamp to the edge texel or
 * mirrored repeat, as Vulkan's samplers address texels; bilinear or the nearest texel. There
 * are no mipmaps, so one filter serves: a loader gives glTF's magFilter (NEAREST: nearest, else
 * linear). glsl/lib/texture.glsl. */
typedef enum vkrt_wrap { VKRT_WRAP_REPEAT, VKRT_WRAP_CLAMP, VKRT_WRAP_MIRROR } vkrt_wrap;
typedef enum vkrt_filter { VKRT_FILTER_LINEAR, VKRT_FILTER_NEAREST } vkrt_filter;
typedef struct vkrt_sampler {
    vkrt_wrap wrap_u, wrap_v;
    vkrt_filter filter;
} vkrt_sampler;

/* An image a material reads, and how: its colour space (VKRT_TEXTURE_COLOUR: sRGB-encoded colour,
 * _DATA: linear numbers, _ALPHA: coverage, texture.h) and its sampler. */
typedef struct vkrt_texture_ref {
    char *path;              /* resolved against the referring file's folder, or NULL: none; for
                                an embedded image a name for messages ("model.glb#image 3") */
    int line;                /* the line of the material's file that named it, 0 if unknown */
    vkrt_texture_usage space;
    vkrt_sampler sampler;
    int32_t embedded;        /* index into vkrt_model.images when the image's bytes live in the
                                scene file (a .glb's buffer, a data URI), else -1: read path */
    uint32_t channel;        /* which channel a one-number map (roughness, metallic, sheen)
                                reads: 0 red .. 3 alpha (glTF's metallicRoughness: metal in 2
                                blue, roughness in 1 green); other maps read their colour */
    uint32_t uv_set;         /* which texture coordinates: 0 (TEXCOORD_0) or 1 (TEXCOORD_1);
                                materials.c refuses 1: meshes carry one set */
    /* KHR_texture_transform's offset, scale and rotation (radians) as the file gives them,
     * untouched; identity: offset 0, scale 1, rotation 0. They apply in image coordinates
     * (s, t) = (u, 1 - v) of the mesh's uv (OBJ convention, v = 0 the bottom row): s from the
     * left, t down from the top row, which is glTF's own uv before its loader flips v:
     *     (s', t') = uv_offset + [cos r  sin r; -sin r  cos r] (uv_scale[0] s, uv_scale[1] t)
     * (matrix rows, r = uv_rotation; counter-clockwise as seen with t pointing down, as the
     * extension's sample viewer and its own example read it), and the sampler wraps (s', t').
     * texture.h, vkrt_texture_uv_transform. */
    float uv_offset[2], uv_scale[2], uv_rotation;
} vkrt_texture_ref;

/* An image held in memory as its file's encoded bytes (PNG, JPEG, ...): a .glb's or data URI's. */
typedef struct vkrt_image_blob {
    char *name;          /* for messages: "model.glb: image 3 (\"wood\")" */
    unsigned char *bytes;
    size_t size;
} vkrt_image_blob;

/* A normal-detail texture's meaning. */
typedef enum vkrt_detail_kind {
    VKRT_DETAIL_NORMAL,    /* a tangent-space normal map */
    VKRT_DETAIL_HEIGHT,    /* a height (bump) map */
    VKRT_DETAIL_BY_IMAGE,  /* either, told apart by the image (vkrt_texture_is_normal_map) */
} vkrt_detail_kind;

/* The textures of a material, each multiplying its number below. */
enum {
    VKRT_MAP_BASE_COLOUR, /* colour; its alpha cuts the surface out where it has one */
    VKRT_MAP_COVERAGE,    /* alpha: cuts the surface out */
    VKRT_MAP_ROUGHNESS,   /* data, one channel (vkrt_texture_ref.channel, red by default) */
    VKRT_MAP_METALLIC,    /* data, one channel (vkrt_texture_ref.channel, red by default) */
    VKRT_MAP_SHEEN,       /* data, one channel (vkrt_texture_ref.channel, red by default) */
    VKRT_MAP_DETAIL,      /* data: normal or height map (detail_kind) */
    VKRT_MAP_EMISSION,    /* colour */
    VKRT_MAP_COUNT
};

/* One physically based material. Fields a family does not use are kept (a user's shader may read
 * any of them through the built-ins' parameter layout, docs/materials.md). A material the
 * scene's material file names is shaded by that file's shader and numbers instead
 * (vkrt_scene_materials_resolve): the user-shader escape hatch, applied after the load so that
 * the model stays what the loader read and can be cached. */
typedef struct vkrt_material {
    char *name;
    char *file;                 /* the file that defined it, for messages (never NULL) */
    vkrt_bsdf bsdf;
    float base_colour[3];       /* diffuse albedo, linear RGB */
    float opacity;              /* 1: opaque; below 1 the rest of the light passes straight */
    float specular[3];          /* specular reflectance (Phong lobe, mirror tint) */
    float specular_exponent;    /* the Blinn-Phong exponent of VKRT_BSDF_GLOSSY_PHONG */
    float emission[3];          /* emitted radiance, linear RGB */
    float ior;                  /* index of refraction; 0 or 1 where the format gives none */
    float transmission_filter[3]; /* glass's tint; all 0 means clear */
    float roughness;            /* perceptual: GGX alpha = roughness^2 */
    float metallic;
    float coat, coat_roughness; /* the clear coat's weight in [0, 1] and its roughness */
    float sheen;                /* the sheen's weight */
    vkrt_texture_ref maps[VKRT_MAP_COUNT];
    vkrt_detail_kind detail_kind;
    float detail_scale;         /* the normal map's strength or the height map's multiplier */
} vkrt_material;

typedef struct vkrt_model {
    vkrt_mesh *meshes;
    uint32_t mesh_count;
    vkrt_instance *instances;
    uint32_t instance_count;
    vkrt_material *materials;
    uint32_t material_count;
    /* Lights and cameras the geometry file itself defines (none for OBJ); vkrt_scene puts them
     * together with scene.cfg's (scene.h), and downstream reads only that. */
    vkrt_config_light *lights;
    uint32_t light_count;
    vkrt_config_camera *cameras;
    uint32_t camera_count;
    vkrt_image_blob *images; /* embedded images the texture refs name by index */
    uint32_t image_count;
    uint32_t triangle_count;            /* over all instances: the triangles the renderer traces */
    float bounds_min[3], bounds_max[3]; /* a world-space box of all instances: an identity
                                           instance's mesh box, else its corners transformed */
    /* Warnings, one a line, "file:LINE: warning: what", folded by kind ("x.mtl: warning: 35
     * materials ..."), whole lines while they fit, or "". */
    char warnings[1024];
    char *warnings_all; /* the same unfolded (malloc'd), or NULL when there are none */
    /* The files the load read besides the scene file, one path a line (malloc'd, NULL when
     * none), and whether one it named was not found: the scene cache's key (scene_cache.h). */
    char *inputs;
    bool inputs_missing;
} vkrt_model;

/* p transformed by t (a point: w = 1), in double and rounded once; out may be p. */
void vkrt_transform_point(const float t[12], const float p[3], float out[3]);

/* The 3x4 identity. */
extern const float vkrt_identity_transform[12];

/* Frees what the model holds and zeroes it. Safe on a zeroed model. */
void vkrt_model_free(vkrt_model *model);

/* Frees a material's strings (name, file, texture paths); the record itself is the caller's. */
void vkrt_material_free_strings(vkrt_material *material);

/* A material with every number at its format-neutral default (grey base colour 0.8, opaque,
 * no specular, emission or maps, ior 1, filter 1 1 1, roughness 1, detail scale 1, the maps'
 * colour spaces as the VKRT_MAP_* list gives them, samplers repeat and linear): what a loader
 * starts each record from. Its memory is zeroed first (the scene cache hashes the record's bytes,
 * padding included); strings are NULL. */
void vkrt_material_defaults(vkrt_material *material);

/* Sets triangle_count and the world box from the instances (identity instances take their mesh's
 * box as it is, to the bit); false, with err set, when an instance names a mesh that is not
 * there or the triangles do not fit 32-bit counts of 9 floats. Loaders call it last. */
bool vkrt_model_finish(vkrt_model *model, vkrt_error *err);

/* The cofactor matrix of t's 3x3 part into cof, and its determinant, in double: the inverse of
 * the 3x3 part is cof's transpose over the determinant, its inverse transpose cof over it. */
double vkrt_transform_cofactors(const float t[12], double cof[3][3]);

/* The most triangles a flattened model may have: 9 floats each, addressed by uint32. */
#define VKRT_MODEL_FLAT_MAX_TRIANGLES (UINT32_MAX / 9)

/* The triangles of every instance in world space, instance after instance, as one mesh: with one
 * identity instance, that mesh's own arrays (*copied false, nothing allocated: the caller must
 * not free them); otherwise new arrays (*copied true, freed with vkrt_mesh_free): positions
 * transformed, normals by the inverse transpose and made unit again (meshes without normals get
 * their geometric normal where another mesh has some), texture coordinates and material indices
 * copied (0 where a mesh has none), tangents NULL, the box that of the positions. False with
 * err set when memory runs out or there are more than VKRT_MODEL_FLAT_MAX_TRIANGLES. */
bool vkrt_model_world(const vkrt_model *model, vkrt_mesh *world, bool *copied, vkrt_error *err);

/* Each instance's first triangle in vkrt_model_world's order, as a new array of instance_count
 * entries (free() it); NULL when memory runs out. */
uint32_t *vkrt_model_instance_firsts(const vkrt_model *model);

/* Triangle t of vkrt_model_world's order in world space (9 floats), bit for bit the positions
 * vkrt_model_world writes, without flattening: its instance is found by binary search over firsts
 * (vkrt_model_instance_firsts). t must be below the model's triangle_count. */
void vkrt_model_world_triangle(const vkrt_model *model, const uint32_t *firsts, uint32_t t,
                               float out[9]);

/* The bytes the model's mesh arrays take in host memory. */
double vkrt_model_host_bytes(const vkrt_model *model);

/* The area of triangle t of positions (9 floats a triangle), in double from the float corners:
 * 0 exactly where the corners lie on a line or at one point. */
double vkrt_triangle_area(const float *positions, uint32_t t);

/* Removes from mesh its triangles of zero area (vkrt_triangle_area: lines and points, which no
 * ray hits and no light samples), keeping the others in order with their normals, texture
 * coordinates, tangents and materials, and sets the box to the positions left; returns how many
 * it removed (the arrays keep their size; the mesh is untouched when none). A loader calls it
 * before vkrt_model_finish, and refuses a mesh left with no triangles. */
uint32_t vkrt_mesh_drop_degenerate(vkrt_mesh *mesh);

/* Frees a mesh's arrays and zeroes it. Safe on a zeroed mesh. */
void vkrt_mesh_free(vkrt_mesh *mesh);

/* Writes the model's warnings to out, each line after prefix (e.g. "vkrt: "): the folded lines,
 * or with verbose every one (warnings_all). Writes nothing when there are none. */
void vkrt_model_print_warnings(const vkrt_model *model, const char *prefix, bool verbose,
                               FILE *out);

#endif
