/*
 * config.h: the scene.cfg parser.
 *
 * A scene.cfg names one OBJ, an optional material file, the image settings, the lights and one
 * camera per frame (docs/scene-format.md). Parsing is pure CPU work and happens before any GPU
 * work, so a malformed file stops the program with "file:LINE: message" and nothing is rendered.
 */
#ifndef VKRT_CONFIG_H
#define VKRT_CONFIG_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "../error.h"
#include "texture.h"

typedef enum vkrt_accel_kind {
    VKRT_ACCEL_AUTO = 0,
    VKRT_ACCEL_BRUTE,
    VKRT_ACCEL_GRID,
    VKRT_ACCEL_BVH,
    VKRT_ACCEL_KDTREE,
} vkrt_accel_kind;

/* Which light transport the renderer computes (docs/scene-format.md, `integrator`). */
typedef enum vkrt_integrator {
    VKRT_INTEGRATOR_AUTO = 0, /* the renderer chooses from the scene's lights and says why */
    VKRT_INTEGRATOR_WHITTED,  /* delta lights, ambient, perfect mirrors and glass */
    VKRT_INTEGRATOR_PATH,     /* unidirectional path tracing with next-event estimation and MIS */
} vkrt_integrator;

/* Whether the BVH splits triangles between nodes (docs/scene-format.md, `bvh-splits`). */
typedef enum vkrt_bvh_splits {
    VKRT_BVH_SPLITS_AUTO = 0, /* spatial splits kept where they pay (accel_gpu.c) */
    VKRT_BVH_SPLITS_ON,       /* spatial splits (an SBVH) */
    VKRT_BVH_SPLITS_OFF,      /* object splits only: every triangle in one leaf */
} vkrt_bvh_splits;

/* The tone curve of 8-bit output and the window (docs/scene-format.md, `tonemap`); float files
 * stay linear. The numbers are glsl/tone_curves.h's VKRT_TONE_CURVE_*. */
typedef enum vkrt_tonemap {
    VKRT_TONEMAP_NONE = 0, /* radiance clipped to [0, 1], then the sRGB curve */
    VKRT_TONEMAP_ACES,     /* Stephen Hill's fit of ACES 1.0's RRT + sRGB ODT */
    VKRT_TONEMAP_AGX,      /* Benjamin Wrensch's minimal AgX (Troy Sobotka's AgX) */
} vkrt_tonemap;

typedef enum vkrt_light_kind {
    VKRT_LIGHT_AMBIENT = 0, /* uniform, unoccluded radiance from every direction: adds Kd * colour */
    VKRT_LIGHT_DIRECTIONAL, /* colour is irradiance (W/m^2) on a surface facing the light */
    VKRT_LIGHT_POINT,       /* colour is radiant intensity (W/sr); falls off with 1/d^2 */
    VKRT_LIGHT_SPOT,        /* a point light limited to a cone of half_angle_deg around direction */
} vkrt_light_kind;

typedef struct vkrt_config_light {
    vkrt_light_kind kind;
    float position[3];     /* point, spot */
    float direction[3];    /* directional (the direction light travels), spot (cone axis); unit length */
    float half_angle_deg;  /* spot: the cone's half angle, in (0, 90] */
    float colour[3];       /* non-negative; units per kind, above */
    int line;              /* where it was declared, for later messages */
} vkrt_config_light;

typedef struct vkrt_config_camera {
    float eye[3], look[3], up[3];
    float fov_deg;         /* vertical field of view, in (0, 180) */
    float aperture;        /* the thin lens's radius, scene units; 0: a pinhole */
    float focus;           /* distance of the plane in focus along the view axis; 0: |look - eye| */
    float ortho_width;     /* > 0: an orthographic camera whose view is this wide in scene units
                              (fov_deg then unused); 0: perspective */
    char name[64];         /* the scene file's name for it ("" when none), for --camera NAME */
    int line;
} vkrt_config_camera;

/* One `geometry` line: a scene file placed in the world. Several lines compose a scene; lines
 * naming the same file share its meshes (each placement is an instance of them). */
typedef struct vkrt_config_geometry {
    char *path;            /* resolved against the scene.cfg's folder */
    int line;              /* the line that named it, for messages about the file (0: none) */
    float transform[12];   /* placement, 3x4 row-major: world = transform * (x, y, z, 1) */
    bool placed;           /* false: the identity (no translate, rotate or scale was given) */
} vkrt_config_geometry;

typedef struct vkrt_config {
    char *path;            /* the scene.cfg itself, as given (the scene file's own path when
                              there is no scene.cfg: vkrt_config_for_geometry) */
    vkrt_config_geometry *geometries; /* in file order; at least one */
    uint32_t geometry_count;
    char *materials;       /* material file, resolved; NULL when absent (the OBJ's .mtl is used) */
    char *output;          /* output path or frame pattern, resolved; NULL when absent */
    uint32_t width, height;   /* default 640 x 480 */
    uint32_t samples;         /* primary samples per pixel, default 1 */
    uint32_t max_depth;       /* secondary ray generations, default 6 */
    float shutter;            /* motion blur: the share of the interval to the next camera during
                                 which a frame's samples are taken, 0 (default) to 1 */
    vkrt_accel_kind accel;    /* default auto */
    vkrt_integrator integrator; /* default auto */
    vkrt_bvh_splits bvh_splits; /* default auto */
    vkrt_tonemap tonemap;     /* default none */
    bool denoise;             /* `denoise on`: the finish stage's denoiser, as --denoise asks */
    float environment[3];     /* radiance of rays that miss, default 0; unused with a map */
    char *environment_map;    /* equirectangular image (src/scene/envmap.h), resolved against the
                                 scene.cfg's folder; NULL when absent. It replaces environment[]. */
    float environment_scale;  /* radiance multiplier of the map, default 1, finite and >= 0 */
    float environment_rotate; /* rotation of the map about +y in degrees, default 0, finite */
    int environment_map_line; /* the line that named the map, for messages about the file */
    vkrt_config_light *lights;
    uint32_t light_count;
    vkrt_config_camera *cameras; /* one per frame, in file order; none: the scene file's cameras
                                    are used, or a view framed on the scene (scene.h) */
    uint32_t camera_count;
    bool from_scene_file;     /* no scene.cfg: made by vkrt_config_for_geometry */
    vkrt_texture_filter texture_filter; /* `textures`: default cone (texture.h) */
} vkrt_config;

/* Reads and parses the scene.cfg at path. Relative paths inside it are resolved against the
 * folder of path. On failure returns false, fills err with "path:LINE: message" (or
 * "path: message" for errors of the whole file, such as a missing camera) and leaves *cfg empty
 * (nothing to free). On success the caller frees *cfg with vkrt_config_free. */
bool vkrt_config_load(const char *path, vkrt_config *cfg, vkrt_error *err);

/* Parses scene.cfg text already in memory; name is used in messages, base_dir (may be "" or NULL
 * for the current folder) resolves relative paths. Same contract as vkrt_config_load. size bytes
 * are read; a NUL byte among them is an error ("not a text line"), never a silent end. */
bool vkrt_config_parse(const char *text, size_t size, const char *name, const char *base_dir,
                       vkrt_config *cfg, vkrt_error *err);

/* Zeroes *cfg and sets what no line gives: 640 x 480, 1 sample, max-depth 6, accel, integrator
 * and bvh-splits auto, environment-map scale 1 (docs/scene-format.md). */
void vkrt_config_defaults(vkrt_config *cfg);

/* The settings a scene file given alone gets (`vkrt render model.glb`): scene.cfg's defaults,
 * one geometry entry of path placed as it is, no lights or cameras, and an output named after
 * the file in the current folder ("model.png"). Same contract as vkrt_config_load. */
bool vkrt_config_for_geometry(const char *path, vkrt_config *cfg, vkrt_error *err);

/* Frees what a successful load or parse allocated, and zeroes *cfg. Safe on a zeroed struct. */
void vkrt_config_free(vkrt_config *cfg);

/* Room for any of the name lists below. */
#define VKRT_NAMES_BYTES 96

/* Every name of a setting, for messages, written into out and returned: "auto, brute, grid,
 * bvh or kdtree", "auto, whitted or path", "auto, on or off". Made from the tables the parse
 * functions read, so a message never leaves a name out. */
const char *vkrt_accel_names(char out[VKRT_NAMES_BYTES]);
const char *vkrt_integrator_names(char out[VKRT_NAMES_BYTES]);
const char *vkrt_bvh_splits_names(char out[VKRT_NAMES_BYTES]);

/* Name of an accel kind as written in scene.cfg ("auto", "brute", "grid", "bvh", "kdtree"). */
const char *vkrt_accel_name(vkrt_accel_kind kind);

/* Parses an accel name; returns false for an unknown one. */
bool vkrt_accel_parse(const char *name, vkrt_accel_kind *kind);

/* Name of an integrator as written in scene.cfg ("auto", "whitted", "path"); "unknown" for a
 * value outside the enum. */
const char *vkrt_integrator_name(vkrt_integrator integrator);

/* Parses an integrator name (exact, lower case); returns false for an unknown one and then leaves
 * *integrator unchanged. integrator may be NULL to test a name. */
bool vkrt_integrator_parse(const char *name, vkrt_integrator *integrator);

/* Name of a bvh-splits setting as written in scene.cfg ("auto", "on", "off"). */
const char *vkrt_bvh_splits_name(vkrt_bvh_splits splits);

/* Parses a bvh-splits name; returns false for an unknown one and then leaves *splits unchanged. */
bool vkrt_bvh_splits_parse(const char *name, vkrt_bvh_splits *splits);

/* Name of a tone curve as written in scene.cfg and after --tonemap ("none", "aces", "agx");
 * "unknown" for a value outside the enum. */
const char *vkrt_tonemap_name(vkrt_tonemap curve);

/* Parses a tone curve's name (exact, lower case); returns false for an unknown one and then
 * leaves *curve unchanged. */
bool vkrt_tonemap_parse(const char *name, vkrt_tonemap *curve);

/* The texture filter named as scene.cfg's `textures` line names it ("cone", "bilinear",
 * "nearest"); false for any other name. */
bool vkrt_texture_filter_parse(const char *name, vkrt_texture_filter *filter);

#endif
