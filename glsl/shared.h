/*
 * shared.h: every struct that crosses between the host and the kernels, defined once.
 *
 * This file is compiled both as C (by the host, and by tests/test_layout.c) and as GLSL (every
 * kernel includes it; vkrt's shader compiler defines VKRT_GLSL). Buffers use std430 layout, so
 * every struct here is built only from 16-byte vectors (vec4, uvec4) and, at most, a final run of
 * 4-byte scalars filling a 16-byte slot: then std430 and C agree without hidden padding.
 * tests/test_layout.c writes every field on the GPU and reads it back through these C structs.
 */
#ifndef VKRT_SHARED_H
#define VKRT_SHARED_H

#ifndef VKRT_GLSL
#include <stdalign.h>
#include <stdint.h>
typedef struct vec4 { alignas(16) float x; float y, z, w; } vec4;
typedef struct uvec4 { alignas(16) uint32_t x; uint32_t y, z, w; } uvec4;
typedef uint32_t uint;
#define VKRT_STRUCT(name) typedef struct name name; struct name
#else
#define VKRT_STRUCT(name) struct name
#endif

/* Marks a hit record of a ray that missed every triangle. */
#define VKRT_NO_HIT 0xFFFFFFFFu

/* Light kinds, as in scene.cfg. */
#define VKRT_LIGHT_KIND_AMBIENT 0u
#define VKRT_LIGHT_KIND_DIRECTIONAL 1u
#define VKRT_LIGHT_KIND_POINT 2u
#define VKRT_LIGHT_KIND_SPOT 3u

/* Flags of Ray.info.w. */
#define VKRT_RAY_DEAD 1u       /* a slot a shader reserved but did not fill, or whose importance fell
                                  under the threshold: traced by nobody, shaded by nobody */

/* One ray of the wavefront with its "image reconstruction information" (the seed's term):
 * which pixel it adds to, how much (importance), its random stream, its depth, and a payload that
 * material shaders pass from a hit to the rays it casts (and the environment shader reads). */
VKRT_STRUCT(Ray) {
    vec4 origin;      /* xyz origin, w: tmin */
    vec4 direction;   /* xyz unit direction, w: tmax */
    vec4 importance;  /* rgb throughput towards the pixel, w unused */
    uvec4 info;       /* x: pixel index, y: random seed, z: depth, w: VKRT_RAY_* flags */
    vec4 payload;     /* the material's own; zero for primary rays */
};

/* The closest hit of a ray: barycentrics u (of v1) and v (of v2), or triangle == VKRT_NO_HIT. */
VKRT_STRUCT(Hit) {
    float t;
    float u;
    float v;
    uint triangle;
};

/* Triangle positions, what traversal reads (w unused). */
VKRT_STRUCT(Triangle) {
    vec4 v0;
    vec4 v1;
    vec4 v2;
};

/* Per-vertex normals of a triangle; uploaded only when the OBJ has normals. */
VKRT_STRUCT(TriangleNormals) {
    vec4 n0;
    vec4 n1;
    vec4 n2;
};

/* Per-triangle texture coordinates; uploaded only when a material of the scene reads textures. */
VKRT_STRUCT(TriangleTexcoords) {
    vec4 uv01;        /* xy: uv of v0, zw: uv of v1 */
    vec4 uv2;         /* xy: uv of v2 */
};

/* A material as the shading kernels see it: its shader (a case of the generated kernel), up to 16
 * numeric parameters and up to 8 textures (indices into the texture table). */
#define VKRT_MATERIAL_PARAMS 16u
#define VKRT_MATERIAL_TEXTURES 8u
#define VKRT_NO_TEXTURE 0xFFFFFFFFu
#define VKRT_MATERIAL_USES_LIGHTS 1u   /* its shader reads light samples: the light kernel traces
                                          shadow rays for its hits (and for no others) */
VKRT_STRUCT(Material) {
    vec4 params[4];   /* parameter i is params[i / 4][i % 4] */
    uvec4 textures[2];/* texture of slot k is textures[k / 4][k % 4], or VKRT_NO_TEXTURE */
    uvec4 info;       /* x: shader index in the generated kernel, y: VKRT_MATERIAL_* flags,
                         z: texture count, w unused */
};

/* A light in GPU form. Spot lights fall off linearly in angle from beam_angle (full intensity)
 * to cutoff_angle (zero), as Mitsuba's spot light does. */
VKRT_STRUCT(Light) {
    vec4 position;    /* xyz: point and spot position; w: spot cutoff angle (radians) */
    vec4 direction;   /* xyz: unit direction light travels (directional, spot axis); w: cos(cutoff) */
    vec4 colour;      /* rgb: radiance (ambient), irradiance (directional), intensity (point, spot); w: spot beam angle */
    uvec4 info;       /* x: VKRT_LIGHT_KIND_* */
};

/* Everything a frame's kernels need besides buffers; sent as push constants (<= 128 bytes). */
VKRT_STRUCT(FrameParams) {
    vec4 eye;         /* xyz camera position, w: importance under which a cast ray is dropped */
    vec4 right;       /* camera right axis scaled by tan(fov/2) * aspect */
    vec4 up;          /* camera up axis scaled by tan(fov/2) */
    vec4 forward;     /* unit view direction */
    uvec4 image;      /* x: width, y: height, z: index of this sample pass, w: samples per pixel */
    uvec4 counts;     /* x: triangles, y: lights, z: rays in this dispatch or VKRT_RAYS_OF_WAVE,
                         w: frame seed */
    uvec4 range;      /* brute force: x..y-1 are the triangles this dispatch tests; z != 0: merge
                         with the hits of earlier dispatches (see traverse_brute.glsl); w: light
                         visibility words per ray */
    uvec4 wave;       /* x: which ray buffer holds this depth's rays (0: A, 1: B; children go to
                         the other), y: depth, z: max depth, w: ray capacity of each buffer */
};

/* counts.z: the dispatch covers the rays of wave[depth] (indirect), not a count from the host. */
#define VKRT_RAYS_OF_WAVE 0xFFFFFFFFu

/* One generation of rays: the indirect dispatch that covers it and how many rays it asked for.
 * ray_count may exceed the capacity: then the rays past it were not stored, and the host grows
 * the buffers and renders the frame again (see src/render/renderer.c). */
VKRT_STRUCT(WaveState) {
    uint groups_x;
    uint groups_y;
    uint groups_z;
    uint ray_count;
};

/* A BVH node, 32 bytes (src/accel/bvh.h, bvh_node, has the same bytes). lo.w and hi.w hold uint
 * bits (floatBitsToUint): lo.w is the left child (inner node; the right child follows it) or the
 * first triangle (leaf), hi.w is the triangle count, 0 for inner nodes. */
VKRT_STRUCT(BvhNode) {
    vec4 lo;
    vec4 hi;
};

/* A texture in the texel buffer (src/scene/texture.h fills these; glsl/lib/texture.glsl reads them).
 * Texels are rows from the top of the image, each row left to right. */
#define VKRT_TEXTURE_SRGB 1u   /* RGBA8 texels whose rgb is sRGB-encoded (colour maps) */
#define VKRT_TEXTURE_HALF 2u   /* two uints per texel: RGBA as half floats (HDR images) */
VKRT_STRUCT(TextureInfo) {
    uint offset;      /* index of the texture's first uint in the texel buffer */
    uint width;
    uint height;
    uint flags;       /* VKRT_TEXTURE_*; without HALF a texel is one uint, RGBA8 (r in the low byte) */
};

/* Which structure trace walks; a specialization constant of the trace and light kernels. */
#define VKRT_TRAVERSE_BRUTE 0u
#define VKRT_TRAVERSE_GRID 1u
#define VKRT_TRAVERSE_BVH 2u

/* The uniform grid's frame (src/accel/grid.h): cell c = x + dims.x * (y + dims.y * z). */
VKRT_STRUCT(GridInfo) {
    vec4 lo;          /* xyz: grid bounds min */
    vec4 hi;          /* xyz: grid bounds max */
    vec4 cell_size;   /* xyz: (hi - lo) / dims */
    uvec4 dims;       /* xyz: cells per axis, w: cell count */
};

/* Counters the kernels update with atomics; the host reads them after a frame. */
VKRT_STRUCT(Counters) {
    uint shadow_rays;       /* shadow rays traced */
    uint secondary_rays;    /* rays cast by materials and traced */
    uint max_wave;          /* the largest ray_count of any wave this frame */
    uint overcast;          /* rays a shader cast beyond what its count_rays said */
    uint overcast_material; /* 1 + the material of the last such cast, 0 if none */
    uint nonfinite;         /* shading results that were NaN or infinite, dropped, not added */
    uint overcount;         /* hits whose count_rays asked for more than VKRT_MAX_CAST rays */
    uint pad2;
};

#endif
