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

/* The wavefront's one descriptor set (set 0), binding by binding: glsl/lib/bindings.glsl declares
 * each buffer at its number and src/render/renderer_buffers.c (renderer_bind_all) binds it. The storage buffers come
 * first, numbered from 0 without gaps, then the uniform texel buffers. */
#define VKRT_BINDING_RAYS 0
#define VKRT_BINDING_HITS 1
#define VKRT_BINDING_TRIANGLES 2
#define VKRT_BINDING_NORMALS 3
#define VKRT_BINDING_TRIANGLE_MATERIAL 4
#define VKRT_BINDING_MATERIALS 5
#define VKRT_BINDING_LIGHTS 6
#define VKRT_BINDING_IMAGE 7
#define VKRT_BINDING_COUNTERS 8
#define VKRT_BINDING_GRID_INFO 9
#define VKRT_BINDING_ACCEL_NODES 10
#define VKRT_BINDING_GRID_REFS 11
#define VKRT_BINDING_RAYS_B 12
#define VKRT_BINDING_WAVES 13
#define VKRT_BINDING_VISIBILITY 14
#define VKRT_BINDING_SLOTS 15
#define VKRT_BINDING_TEXCOORDS 16
#define VKRT_BINDING_TEXTURE_INFOS 17
#define VKRT_BINDING_TEXELS 18
#define VKRT_BINDING_EMITTERS 19
#define VKRT_BINDING_ENVIRONMENT 20
#define VKRT_BINDING_PIXEL_STATS 21       /* adaptive sampling only (--target-error); */
#define VKRT_BINDING_ACTIVE_PIXELS 22     /* otherwise a minimal buffer each */
#define VKRT_BINDING_SAMPLE_LUMINANCE 23
#define VKRT_BINDING_SPLIT_ADDRESSES 24   /* the chunks of split arrays (below) */
#define VKRT_BINDING_MATERIAL_ORDER 25    /* hits grouped by shader (order.comp); else minimal */
#define VKRT_BINDING_PLASTIC_TABLES 26    /* @roughplastic's coat tables (below); else minimal */
#define VKRT_BINDING_AOVS 27              /* --aov's planes (below); else minimal */
#define VKRT_STORAGE_BINDINGS 28
#define VKRT_BINDING_TRIANGLE_TEXELS 28
#define VKRT_BINDING_NODE_TEXELS 29
#define VKRT_TEXEL_BINDINGS 2

/* Arrays larger than one buffer holds (src/gpu/array.h): each is split into chunks of
 * 2^s elements, s its VKRT_SPEC_SPLIT_* constant (0: one buffer, at its binding above), and the
 * kernels reach chunk c of array k at the device address split_addresses[k * VKRT_MAX_CHUNKS + c]
 * (binding VKRT_BINDING_SPLIT_ADDRESSES, an address as two words, low first). */
#define VKRT_SPLIT_TRIANGLES 0u
#define VKRT_SPLIT_NORMALS 1u
#define VKRT_SPLIT_TEXCOORDS 2u
#define VKRT_SPLIT_TRIANGLE_MATERIAL 3u
#define VKRT_SPLIT_NODES 4u
#define VKRT_SPLIT_REFS 5u
#define VKRT_SPLIT_TEXELS 6u
#define VKRT_SPLIT_ARRAY_COUNT 7u
#define VKRT_MAX_CHUNKS 64u

/* The viewer's display pass (glsl/display.comp, src/view/display.c): a set of its own. */
#define VKRT_DISPLAY_BINDING_IMAGE 0
#define VKRT_DISPLAY_BINDING_WINDOW 1

/* The display pass's push constants. */
VKRT_STRUCT(DisplayParams) {
    uvec4 size;   /* image width, height; window width, height */
    vec4 scale;   /* x: 1 / passes, y: 2^exposure, z: 1 to store red in the third byte (BGRA),
                     w: 1 to divide by each pixel's own count, its w, instead of x (sampling to a
                     target error: glsl/adapt.comp) */
    uvec4 curve;  /* x: the tone curve after exposure (glsl/tone_curves.h's VKRT_TONE_CURVE_*) */
};

/* Specialization constant ids of the wavefront kernels (0 is the workgroup size). */
#define VKRT_SPEC_WORKGROUP_SIZE 0
#define VKRT_SPEC_HAS_NORMALS 1
#define VKRT_SPEC_ACCEL_KIND 2
#define VKRT_SPEC_HAS_TEXCOORDS 3
#define VKRT_SPEC_WAVE_WORKGROUP 4
#define VKRT_SPEC_TRAVERSAL_STATS 5
#define VKRT_SPEC_BVH_WIDTH 6
#define VKRT_SPEC_TEXEL_LOADS 7
#define VKRT_SPEC_NESTED_WALK 8
#define VKRT_SPEC_INTEGRATOR 9
#define VKRT_SPEC_LIGHT_SAMPLING 10
#define VKRT_SPEC_HAS_CUTOUTS 11
#define VKRT_SPEC_EMITTER_LIGHT 12
#define VKRT_SPEC_CLAMP 13
#define VKRT_SPEC_SURFACE_MAPS 14
#define VKRT_SPEC_TARGET_ERROR 15
/* One per split array, in VKRT_SPLIT_* order: log2 of its chunks' elements, 0 for one buffer. */
#define VKRT_SPEC_SPLIT_TRIANGLES 16
#define VKRT_SPEC_SPLIT_NORMALS 17
#define VKRT_SPEC_SPLIT_TEXCOORDS 18
#define VKRT_SPEC_SPLIT_TRIANGLE_MATERIAL 19
#define VKRT_SPEC_SPLIT_NODES 20
#define VKRT_SPEC_SPLIT_REFS 21
#define VKRT_SPEC_SPLIT_TEXELS 22
#define VKRT_SPEC_MATERIAL_ORDER 23
#define VKRT_SPEC_AOVS 24

/* Integrators (VKRT_SPEC_INTEGRATOR): Whitted's (delta lights, ambient, the materials' own rays)
 * or the path tracer (next-event estimation with multiple importance sampling). */
#define VKRT_INTEGRATE_WHITTED 0u
#define VKRT_INTEGRATE_PATH 1u
/* How the path tracer samples direct light (VKRT_SPEC_LIGHT_SAMPLING): both strategies weighted by
 * the power heuristic (the default), or one alone (for tests: all three must agree). */
#define VKRT_SAMPLING_MIS 0u
#define VKRT_SAMPLING_LIGHTS 1u
#define VKRT_SAMPLING_BSDF 2u

/* Sizes both sides must agree on. The BVH's traversal stack: src/render/accel_gpu.c refuses a
 * tree whose paths could need more (one entry per level of pairs, up to 3 per level of quads).
 * The most rays one hit may cast: a material's count_rays answer above it is its error. */
#define VKRT_BVH_STACK_SIZE 64
/* The kd-tree's traversal stack: one entry per level (src/accel/kdtree.h KDTREE_MAX_DEPTH, the
 * deepest tree the builder makes, is the same number). */
#define VKRT_KD_STACK_SIZE 48
#define VKRT_MAX_CAST 64u

/* Marks a hit record of a ray that missed every triangle. */
#define VKRT_NO_HIT 0xFFFFFFFFu

/* Light kinds, as in scene.cfg. */
#define VKRT_LIGHT_KIND_AMBIENT 0u
#define VKRT_LIGHT_KIND_DIRECTIONAL 1u
#define VKRT_LIGHT_KIND_POINT 2u
#define VKRT_LIGHT_KIND_SPOT 3u

/* Flags of Ray.info.w (ray_is_dead). */
#define VKRT_RAY_DEAD 1u       /* a slot a shader reserved but did not fill, or whose importance fell
                                  under the threshold: traced by nobody, shaded by nobody */
#define VKRT_RAY_AOV_PENDING 2u /* --aov albedo or normal: the ray's path has not yet recorded
                                  them (glsl/lib/aov.glsl): a camera ray, or one that continues
                                  its path through a delta (mirror or glass) bounce */
/* Ray.info.w above the flags: the ray's sample index in its pixel (0 .. samples - 1 over all the
 * passes of a frame), which the path tracer's sampler (lib/sampler.glsl) draws its numbers by. */
#define VKRT_RAY_SAMPLE_SHIFT 9u
#define VKRT_RAY_FLAGS ((1u << VKRT_RAY_SAMPLE_SHIFT) - 1u)
/* Ray.info.w bits 2-8, above the two flags: the ray's depth (ray_depth), 0 for camera rays;
 * scene.cfg's max-depth is at most 64, so 7 bits hold every depth a ray reaches. The sample index
 * keeps 23 bits, past any sample count a frame may have. */
#define VKRT_RAY_DEPTH_SHIFT 2u
#define VKRT_RAY_DEPTH_MASK 127u

/* One ray of the wavefront with its "image reconstruction information" (the seed's term):
 * which pixel it adds to, how much (importance), its random stream, its depth, and a payload that
 * material shaders pass from a hit to the rays it casts (and the environment shader reads).
 * Every packed lane has one meaning and is read and written through the accessor named after
 * it (glsl/lib/ray_record.glsl, in parentheses below); tests/test_layout.c checks the lanes. */
VKRT_STRUCT(Ray) {
    vec4 origin;      /* xyz origin, w: tmin (ray_tmin) */
    vec4 direction;   /* xyz unit direction, w: tmax (ray_tmax) */
    vec4 importance;  /* rgb: throughput towards the pixel (ray_throughput); w: the solid-angle
                         pdf of the BSDF sample that cast the ray, 0 where no light sample could
                         find what it hits: camera rays, delta lobes, Whitted (ray_bsdf_pdf) */
    uvec4 info;       /* x: pixel index (ray_pixel), y: hash stream state (ray_seed), z: the ray
                         cone for texture filtering, its width at the origin and its spread
                         angle, two 16-bit floats (ray_cone), w: VKRT_RAY_DEAD (ray_is_dead),
                         VKRT_RAY_AOV_PENDING (ray_aov_pending), the depth in bits 2-8
                         (ray_depth) and the sample index above
                         VKRT_RAY_SAMPLE_SHIFT (ray_sample) */
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

/* A material as the shading kernels see it: its shader (a case of the generated kernel), up to 20
 * numeric parameters and up to 8 textures (indices into the texture table). */
#define VKRT_MATERIAL_PARAMS 20u
#define VKRT_MATERIAL_TEXTURES 8u
#define VKRT_NO_TEXTURE 0xFFFFFFFFu
/* Material.info.w: where traversal reads the coverage of a cut-out (lib/cutout.glsl): none, the
 * red of texture slot 1 (map_d), or the alpha of slot 0 (an RGBA map_Kd without map_d). */
#define VKRT_CUTOUT_NONE 0u
#define VKRT_CUTOUT_MAP_D 1u
#define VKRT_CUTOUT_ALPHA 2u
#define VKRT_MATERIAL_USES_LIGHTS 1u   /* its shader reads light samples: the light kernel traces
                                          shadow rays for its hits (and for no others) */
/* The .mtl maps every built-in reads (lib/surface_maps.glsl): the shading normal from a tangent-
 * space normal map or a height map in texture slot VKRT_SLOT_DETAIL, the emission Ke times the
 * map_Ke in slot VKRT_SLOT_EMISSION. These flags of Material.info.y, or-ed over the scene's
 * materials, are also the specialization constant VKRT_SPEC_SURFACE_MAPS: a scene without a kind
 * of map compiles none of its code. */
#define VKRT_MATERIAL_NORMAL_MAP 2u
#define VKRT_MATERIAL_BUMP_MAP 4u
#define VKRT_MATERIAL_EMISSION_MAP 8u
/* Not a map, but compiled away the same way: the material has a clear coat (numbers 18-19, the
 * .mtl's Pc and Pcr; lib/microfacet.glsl). A scene without a coated material compiles no coat. */
#define VKRT_MATERIAL_COAT 16u
/* The same for the sheen (the .mtl's Ps and map_Ps: Material.maps.z and texture slot
 * VKRT_SLOT_SHEEN; lib/microfacet.glsl). */
#define VKRT_MATERIAL_SHEEN 32u
#define VKRT_SLOT_DETAIL 4u
#define VKRT_SLOT_EMISSION 5u
#define VKRT_SLOT_SHEEN 6u
VKRT_STRUCT(Material) {
    vec4 params[5];   /* parameter i is params[i / 4][i % 4] */
    uvec4 textures[2];/* texture of slot k is textures[k / 4][k % 4], or VKRT_NO_TEXTURE */
    uvec4 info;       /* x: shader index in the generated kernel, y: VKRT_MATERIAL_* flags,
                         z: texture count, w: VKRT_CUTOUT_* */
    vec4 maps;        /* x: the luminance light sampling weighs the emission by, luminance(Ke
                         times the mean of map_Ke) (lib/emitters.glsl); y: the detail map's
                         multiplier (-bm); z: the sheen weight of the rough built-ins (the
                         .mtl's Ps, a material file's number 20); w: where @roughplastic's coat
                         table starts in the plastic tables (a whole number; -1: none, a smooth
                         or index-1 coat, and every other shader) */
};

/* @roughplastic's coat tables (binding VKRT_BINDING_PLASTIC_TABLES, floats; src/scene/
 * plastic_table.h says what the numbers are, lib/microfacet.glsl reads them): one table per
 * index and roughness of the scene's rough plastics, each
 *     [0]                    its row count R (1 for a material of one roughness)
 *     [1]                    (R - 1) / the roughness of its last row (0 for one row): the first
 *                            row is roughness 0 where R > 1, the rows equally spaced
 *     [2 + r * ROW_FLOATS]   row r: the coat's internal reflectance Ri, then its transmittance
 *                            T at the cosines k / (VKRT_PLASTIC_COSINES - 1), k = 0, 1, ...
 * A scene without a rough plastic uploads none (a minimal buffer). */
#define VKRT_PLASTIC_COSINES 64
#define VKRT_PLASTIC_ROW_FLOATS (1 + VKRT_PLASTIC_COSINES)
#define VKRT_PLASTIC_HEADER_FLOATS 2

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
    vec4 right;       /* camera right axis scaled by tan(fov/2) * aspect, or by half the view's
                         width when orthographic; w: lens radius (0: pinhole) */
    vec4 up;          /* camera up axis scaled by tan(fov/2), or by half the view's height when
                         orthographic; w: distance in focus */
    vec4 forward;     /* unit view direction; w: 0 perspective, 1 orthographic (raygen.comp) */
    uvec4 image;      /* x: width, y: height, z: index of this sample pass, w: samples per pixel */
    uvec4 counts;     /* x: triangles, y: lights, z: rays in this dispatch or VKRT_RAYS_OF_WAVE,
                         w: frame seed */
    uvec4 stage;      /* x, y, z: one kernel's arguments for one dispatch, whose meaning is the
                         kernel's; each is read and set only through the accessor named for it
                         (glsl/lib/ray_record.glsl): brute-force trace: first triangle, end,
                         merge (frame_brute_*); order.comp: step (frame_order_step); adapt.comp:
                         step (frame_adapt_step). w: light visibility words per ray, the same for
                         the whole frame (frame_light_words). The push constants may not pass 128
                         bytes (Vulkan's guaranteed minimum), so the steps share lanes rather
                         than grow the struct. */
    uvec4 wave;       /* x: which ray buffer holds this depth's rays (0: A, 1: B; children go to
                         the other), y: depth, z: max depth, w: ray capacity of each buffer */
};

/* counts.z: the dispatch covers the rays of wave[depth] (indirect), not a count from the host. */
#define VKRT_RAYS_OF_WAVE 0xFFFFFFFFu

/* One generation of rays: the indirect dispatch that covers it and how many rays it asked for.
 * ray_count may exceed the capacity: then the rays past it were not stored, and the host grows
 * the buffers and renders the frame again (see src/render/renderer_frame.c). */
VKRT_STRUCT(WaveState) {
    uint groups_x;
    uint groups_y;
    uint groups_z;
    uint ray_count;
};

/* An inner node of the binary BVH, 64 bytes (src/accel/bvh_pairs.h, bvh_pair, has the same
 * bytes): both children's boxes, x = (a.lo.x, a.hi.x, b.lo.x, b.hi.x), likewise y and z.
 * refs.xy: children a and b, another BvhPair's index or a leaf reference (VKRT_BVH_LEAF, below);
 * refs.zw unused. */
VKRT_STRUCT(BvhPair) {
    vec4 x;
    vec4 y;
    vec4 z;
    uvec4 refs;
};

/* A node of the 4-wide BVH, 64 bytes (src/accel/bvh_quads.h, bvh_quad, has the same bytes and
 * says how it is made). Child k's box is origin.xyz + byte k of its plane words * scale, per
 * axis, with scale = 2^(e - 127) for the exponent byte e of that axis.
 * origin.w: uint bits: exponents of x, y, z in bits 0-7, 8-15, 16-23; child count in 24-31.
 * planes: x lo, x hi, y lo, y hi (a byte per child); planes_z: z lo, z hi, unused, unused.
 * refs: per child, another node's index, or VKRT_BVH_LEAF | (count - 1) << 27 | first triangle. */
#define VKRT_BVH_LEAF 0x80000000u
VKRT_STRUCT(BvhQuad) {
    vec4 origin;
    uvec4 planes;
    uvec4 planes_z;
    uvec4 refs;
};

/* A texture as a material's map reads it (src/scene/texture.h fills these; glsl/lib/texture.glsl
 * reads them): an image in the texel buffer, rows from the top of the image, each row left to
 * right, with the map's sampler, uv transform and channel. Two maps that read one image with
 * different samplers, transforms or channels have an entry each, sharing the texels.
 * Wrap modes, per axis in the flags (VKRT_TEXTURE_WRAP_U/_V of the mode): repeat (0, as
 * Vulkan's REPEAT), clamp to the edge texel (1, CLAMP_TO_EDGE) or mirrored repeat (2,
 * MIRRORED_REPEAT). */
#define VKRT_TEXTURE_SRGB 1u   /* RGBA8 texels whose rgb is sRGB-encoded (colour maps) */
#define VKRT_TEXTURE_HALF 2u   /* two uints per texel: RGBA as half floats (HDR images) */
#define VKRT_TEXTURE_REPEAT 0u
#define VKRT_TEXTURE_CLAMP 1u
#define VKRT_TEXTURE_MIRROR 2u
#define VKRT_TEXTURE_WRAP_U(mode) ((mode) << 2)  /* bits 2-3: the wrap mode across (s) */
#define VKRT_TEXTURE_WRAP_V(mode) ((mode) << 4)  /* bits 4-5: the wrap mode down (t) */
#define VKRT_TEXTURE_NEAREST 64u   /* the nearest texel instead of the bilinear blend */
#define VKRT_TEXTURE_TRANSFORM 128u /* uv_transform applies (it is the identity without) */
#define VKRT_TEXTURE_CHANNEL(c) ((c) << 8) /* bits 8-9: channel c > 0 of a one-number map, put
                                              in all four components; 0: the texel as it is */
/* Bits 10-13: the mipmap levels stored after the image (0: the image alone). Level k is
 * max(1, width >> k) x max(1, height >> k) texels, the box-filtered level k - 1 (src/scene/
 * texture_levels.h), in the image's texel format, right after level k - 1; an image gets
 * floor(log2(max(width, height))) levels, down to 1 x 1. glsl/lib/texture.glsl picks the level
 * by the ray cone's footprint (texture_sample_footprint). */
#define VKRT_TEXTURE_LEVELS(n) ((n) << 10)
#define VKRT_TEXTURE_LEVELS_OF(flags) (((flags) >> 10) & 15u)
VKRT_STRUCT(TextureInfo) {
    uint offset;      /* index of the texture's first uint in the texel buffer */
    uint width;
    uint height;
    uint flags;       /* VKRT_TEXTURE_*; without HALF a texel is one uint, RGBA8 (r in the low byte) */
    vec4 uv_matrix;   /* with VKRT_TEXTURE_TRANSFORM, image coordinates (s, t) move to
                         (x * s + y * t + uv_offset.x, z * s + w * t + uv_offset.y) */
    vec4 uv_offset;   /* xy as above; zw unused (0) */
};

/* Which structure trace walks; a specialization constant of the trace and light kernels. */
#define VKRT_TRAVERSE_BRUTE 0u
#define VKRT_TRAVERSE_GRID 1u
#define VKRT_TRAVERSE_BVH 2u
#define VKRT_TRAVERSE_KDTREE 3u
/* The two-level BVH of an instanced scene (glsl/lib/traverse_instanced.glsl): a top-level tree
 * over the instances' world boxes and a bottom-level tree per unique mesh, in the same node
 * binding and layout (BVH_WIDTH) as VKRT_TRAVERSE_BVH's one tree. */
#define VKRT_TRAVERSE_BVH_INSTANCED 4u

/* A node of the kd-tree, 16 bytes, one texel (src/accel/kdtree.h, kd_node, has the same bytes).
 * axis 0-2: split at `split` on that axis, children a (below the plane) and b (above);
 * axis == VKRT_KD_LEAF: triangles grid_refs[a .. a + b - 1] (the references binding). The root's
 * box is the GridInfo's lo and hi. */
#define VKRT_KD_LEAF 3u
VKRT_STRUCT(KdNode) {
    float split;
    uint axis;
    uint a;
    uint b;
};

/* One placed mesh of the two-level BVH (src/render/accel_instanced.c makes them; the references
 * binding holds them, in the top-level tree's leaf order; GridInfo.dims.x says how many).
 * The uploaded per-triangle arrays (triangles, normals, texture coordinates, materials) hold each
 * unique mesh once, in its own (object) space, its bottom-level tree's leaf order, mesh after
 * mesh. A hit's triangle (Hit.triangle) is then its index in the instanced order: instance
 * after instance (this array's order), each instance's triangles in its mesh's uploaded order:
 *   Hit.triangle = info.z + (uploaded triangle - info.y).
 * glsl/lib/instances.glsl finds the instance of such an index by binary search over info.z
 * (ascending), and its uploaded triangle. The instanced count must stay below VKRT_NO_HIT.
 * world_to_object and object_to_world are the rows of 3x4 affine maps; normals go to world space
 * by the transpose of world_to_object's 3x3 part (the inverse transpose of object_to_world's). */
VKRT_STRUCT(Instance) {
    vec4 world_to_object[3];
    vec4 object_to_world[3];
    uvec4 info;       /* x: root node of its mesh's bottom-level tree, y: its mesh's first uploaded
                         triangle, z: its first triangle in the instanced order, w: its mesh's
                         triangle count */
};

/* The uniform grid's frame (src/accel/grid.h): cell c = x + dims.x * (y + dims.y * z). */
VKRT_STRUCT(GridInfo) {
    vec4 lo;          /* xyz: grid bounds min */
    vec4 hi;          /* xyz: grid bounds max */
    vec4 cell_size;   /* xyz: (hi - lo) / dims */
    uvec4 dims;       /* xyz: cells per axis, w: cell count */
};

/* What the path tracer's light sampling needs to know of the scene's area lights and sky, one
 * record at the start of the emitter buffer (binding VKRT_BINDING_EMITTERS), the alias table after
 * it. An emissive triangle is chosen with probability power / total_power, power = luminance(Ke)
 * * area (src/scene/emitters.h), and a point on it uniformly: the density per unit area of a point
 * of triangle t is then luminance(Ke of t's material) / total_power, which a BSDF ray that hits
 * t needs for its MIS weight, with no table lookup. */
VKRT_STRUCT(LightInfo) {
    uint emitter_count;      /* entries of the alias table */
    float emitter_power;     /* sum of luminance(Ke) * area over them */
    uint environment_width;  /* environment map texels (0: none; the constant environment) */
    uint environment_height;
    float environment_scale; /* radiance multiplier of the map */
    float environment_rotate;/* rotation about +y, radians */
    uint environment_pixels; /* where the map's pixels (RGB floats) start in the environment
                                buffer, after its distribution (lib/environment.glsl) */
    float environment_integral; /* sum of the distribution's weights (src/scene/envmap.h) */
    uint environment_sampled;   /* 1: next-event estimation samples the environment (a map, a
                                   constant above zero or a user's environment shader) */
    uint pad0, pad1, pad2;
};

/* An entry of the alias table over the emissive triangles (Vose's method): entry i taken
 * uniformly, kept with probability `keep`, else entry `alias` is taken: each triangle comes out
 * with probability power / total power. */
VKRT_STRUCT(Emitter) {
    uint triangle;           /* index in the uploaded (acceleration structure's) order */
    float keep;
    uint alias;
    float power;             /* luminance(Ke) * area */
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
    /* Traversal statistics, kept only by pipelines made with TRAVERSAL_STATS (vkrt bench --stats):
     * rays traced, BVH nodes fetched and triangles tested (summed over the rays), the walk's loop
     * iterations in which a lane had work (a node or a leaf) summed over lanes, and the iterations
     * the subgroups' loops ran summed over subgroups: busy over widest times the subgroup size is
     * the SIMD utilisation (glsl/lib/traversal_stats.glsl). */
    uint trace_rays;
    uint trace_steps;
    uint trace_tests;
    uint trace_busy;
    uint trace_widest;
    uint subgroup_size;
    /* Adaptive sampling (--target-error) only: the pixels listed for the next pass (after the
     * last pass of a submission: those not yet converged), and the camera rays traced. */
    uint active_pixels;
    uint primary_rays;
    uint pad;
};

/* Adaptive sampling (--target-error; glsl/lib/adaptive.glsl says what it estimates). Pixels
 * darker than VKRT_ADAPTIVE_FLOOR (linear luminance; 1 is a PNG's white at exposure 0) are held to
 * an error of E times it, not E times themselves: a black or nearly black pixel would otherwise
 * ask for samples without end, for an error no display shows (E x 0.01 is below an 8-bit sRGB
 * step for any E up to 1). A pixel takes at least VKRT_ADAPTIVE_MIN_SAMPLES samples before its
 * estimate may stop it: fewer say too little of its variance (a pixel whose first samples all
 * missed a small light reads a variance of 0); a sample pass gives a pixel at most that many, so
 * that pixels stop within that many samples of their target. */
#define VKRT_ADAPTIVE_FLOOR 0.01f
#define VKRT_ADAPTIVE_MIN_SAMPLES 16u
/* A pixel none of whose samples found light takes at least this many: a dim face lit only by rare
 * indirect paths can read 0 after VKRT_ADAPTIVE_MIN_SAMPLES samples, and an estimate of 0 would
 * stop it black; a pixel that is truly black (the sky past a scene's edge) pays the difference. */
#define VKRT_ADAPTIVE_MIN_DARK_SAMPLES 64u

/* A pixel's luminance statistics, from which glsl/lib/adaptive.glsl estimates its error. */
VKRT_STRUCT(PixelStats) {
    float mean;       /* mean luminance of the pixel's samples */
    float m2;         /* their sum of squared deviations from it (Welford) */
    uint samples;     /* samples taken */
    uint listed;      /* VKRT_PIXEL_* flags (glsl/adapt.comp) */
};

/* PixelStats.listed: the pixel takes samples (set when the frame starts; once cleared, it stays
 * cleared for the frame); its own estimate (or its count, under the fewest) asks for more and it
 * is below the cap. */
#define VKRT_PIXEL_LISTED 1u
#define VKRT_PIXEL_UNCONVERGED 2u

/* AOVs (--aov; glsl/lib/aov.glsl records them, src/render/renderer_aov.c reads them back): the
 * bits of the specialization constant VKRT_SPEC_AOVS (0: none, and no code). Each AOV asked for
 * is a plane of one vec4 per pixel in the buffer at VKRT_BINDING_AOVS, the planes in the order of
 * their bits, only those asked for (plane of AOV a: the count of the bits below a that are set).
 * Each sample of a pixel adds to its planes:
 *   ALBEDO    rgb: the albedo at the path's first non-delta hit (lib/aov.glsl), w unused
 *   NORMAL    xyz: the shading normal there (unit; 0 where the path escaped), w unused
 *   DEPTH     x: the camera ray's hit distance t, y: 1 (the samples that hit), where it hit
 *   POSITION  xyz: the camera ray's hit point, w: 1, where it hit
 * so that the host divides ALBEDO and NORMAL by the pixel's samples and DEPTH and POSITION by
 * the samples that hit. */
#define VKRT_AOV_ALBEDO 1u
#define VKRT_AOV_NORMAL 2u
#define VKRT_AOV_DEPTH 4u
#define VKRT_AOV_POSITION 8u
#define VKRT_AOV_ALL 15u
/* The AOVs recorded where a path meets its first non-delta surface (the others at its first hit). */
#define VKRT_AOV_SURFACE (VKRT_AOV_ALBEDO | VKRT_AOV_NORMAL)

/* Hits grouped by shader (order.comp, binding VKRT_BINDING_MATERIAL_ORDER): per depth
 * VKRT_ORDER_BINS counts and VKRT_ORDER_BINS cursors, then the ray index of every place in the
 * grouped order. Shaders past VKRT_ORDER_BINS - 2 share a bin; the last bin holds the misses
 * and the dead rays. order.comp's step (frame_order_step): count the hits of each bin, or place
 * them. */
#define VKRT_ORDER_BINS 64u
/* The camera's hits stay in pixel order: neighbouring pixels mostly share a material, and their
 * shadow rays keep each other company through the structure. */
#define VKRT_ORDER_FIRST_DEPTH 1u
#define VKRT_ORDER_COUNT 0u
#define VKRT_ORDER_PLACE 1u

/* adapt.comp's step (frame_adapt_step): fold the pass's samples and judge each listed pixel by its
 * own estimate, or keep listed each listed pixel with an unconverged pixel in its 3x3
 * neighbourhood. */
#define VKRT_ADAPT_FOLD 0u
#define VKRT_ADAPT_SELECT 1u

/* The pixels the next sample pass traces (binding VKRT_BINDING_ACTIVE_PIXELS: this header, then
 * the pixel indices, in raygen's tile order). */
VKRT_STRUCT(ActivePixels) {
    uint groups_x;    /* raygen's indirect dispatch: count x the pass's samples per pixel */
    uint groups_y;
    uint groups_z;
    uint count;       /* pixels in the list */
    uint appended;    /* pixels adapt.comp has listed so far for the pass after */
    uint pad0, pad1, pad2;
};

#endif
