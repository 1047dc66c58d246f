/*
 * bindings.glsl: the one descriptor set every wavefront kernel sees (set 0), and the frame's push
 * constants. The host binds the same set to every pipeline; the numbers are glsl/shared.h's
 * VKRT_BINDING_* and VKRT_SPEC_*, the names the host uses. A kernel simply ignores the buffers
 * it does not read.
 */
#ifndef VKRT_BINDINGS_GLSL
#define VKRT_BINDINGS_GLSL

#include "../shared.h"
#include "ray_record.glsl"

layout(local_size_x_id = VKRT_SPEC_WORKGROUP_SIZE) in;

/* Set when the OBJ had normals and the TriangleNormals buffer is real. */
layout(constant_id = VKRT_SPEC_HAS_NORMALS) const bool HAS_NORMALS = false;
/* Set when a material reads textures and the TriangleTexcoords buffer is real. */
layout(constant_id = VKRT_SPEC_HAS_TEXCOORDS) const bool HAS_TEXCOORDS = false;
/* The workgroup size of the wave kernels, for the kernel that writes their indirect dispatches. */
layout(constant_id = VKRT_SPEC_WAVE_WORKGROUP) const uint WAVE_WORKGROUP_SIZE = 64u;

/* Rays live in two buffers, A and B: one depth's rays in one, the rays they cast in the other
 * (frame.wave.x says which is which). Two bindings rather than two halves of one buffer, so each
 * can be as large as maxStorageBufferRange. */
layout(std430, set = 0, binding = VKRT_BINDING_RAYS) buffer RayBuffer { Ray rays[]; };
layout(std430, set = 0, binding = VKRT_BINDING_RAYS_B) buffer RayBufferB { Ray rays_b[]; };
layout(std430, set = 0, binding = VKRT_BINDING_HITS) buffer HitBuffer { Hit hits[]; };

/* The scene: its triangles (in the structure's order), their normals and materials, the
 * materials' records and the point, spot and directional lights. */
layout(std430, set = 0, binding = VKRT_BINDING_TRIANGLES) readonly buffer TriangleBuffer { Triangle triangles[]; };
layout(std430, set = 0, binding = VKRT_BINDING_NORMALS) readonly buffer NormalBuffer { TriangleNormals triangle_normals[]; };
layout(std430, set = 0, binding = VKRT_BINDING_TRIANGLE_MATERIAL) readonly buffer TriangleMaterialBuffer { uint triangle_material[]; };
layout(std430, set = 0, binding = VKRT_BINDING_MATERIALS) readonly buffer MaterialBuffer { Material materials[]; };
layout(std430, set = 0, binding = VKRT_BINDING_LIGHTS) readonly buffer LightBuffer { Light lights[]; };
layout(std430, set = 0, binding = VKRT_BINDING_IMAGE) buffer ImageBuffer { vec4 image[]; };
layout(std430, set = 0, binding = VKRT_BINDING_IMAGE) buffer ImageWords { uint image_words[]; };
layout(std430, set = 0, binding = VKRT_BINDING_COUNTERS) buffer CounterBuffer { Counters counters; };

/* The acceleration structure: the grid's frame (the kd-tree's root box); the BVH's nodes (4-wide
 * or pairs), the kd-tree's nodes or the grid's cell starts (one binding, four views: only the
 * chosen one is read); the grid's or the kd-tree's triangle references. */
layout(std430, set = 0, binding = VKRT_BINDING_GRID_INFO) readonly buffer GridInfoBuffer { GridInfo grid; };
layout(std430, set = 0, binding = VKRT_BINDING_ACCEL_NODES) readonly buffer BvhNodeBuffer { BvhQuad bvh_nodes[]; };
layout(std430, set = 0, binding = VKRT_BINDING_ACCEL_NODES) readonly buffer BvhPairBuffer { BvhPair bvh_pairs[]; };
layout(std430, set = 0, binding = VKRT_BINDING_ACCEL_NODES) readonly buffer KdNodeBuffer { KdNode kd_nodes[]; };
layout(std430, set = 0, binding = VKRT_BINDING_ACCEL_NODES) readonly buffer GridCellBuffer { uint grid_cell_start[]; };
layout(std430, set = 0, binding = VKRT_BINDING_GRID_REFS) readonly buffer GridRefBuffer { uint grid_refs[]; };
/* The two-level BVH's instances (VKRT_TRAVERSE_BVH_INSTANCED) in the references binding, their
 * count in the frame's dims.x (lib/instances.glsl). */
layout(std430, set = 0, binding = VKRT_BINDING_GRID_REFS) readonly buffer InstanceBuffer { Instance instances[]; };

/* The triangles and the structure's nodes once more, as uniform texel buffers of 16-byte texels:
 * views of the triangle and node buffers (src/render/renderer_upload.c). Traversal reads them
 * when TEXEL_LOADS is set (on CPU devices, by default): a CPU device may load from a storage
 * buffer one lane and one word at a time, each behind a bounds check and a branch, where it
 * fetches from a texel buffer with vector gathers. */
layout(set = 0, binding = VKRT_BINDING_TRIANGLE_TEXELS) uniform usamplerBuffer triangle_texels;
layout(set = 0, binding = VKRT_BINDING_NODE_TEXELS) uniform usamplerBuffer node_texels;
layout(constant_id = VKRT_SPEC_TEXEL_LOADS) const bool TEXEL_LOADS = false;

/* Set when the BVH's walk runs inner nodes and leaves in two loops of their own
 * (lib/traverse_bvh.glsl, bvh_traverse_nested): on CPU devices, by default. */
layout(constant_id = VKRT_SPEC_NESTED_WALK) const bool NESTED_WALK = false;

/* The wave machinery: one WaveState per depth, light visibility bits (frame_light_words words per
 * ray, bit k of word k / 32 set when light k reaches the hit), and for each ray the first slot and
 * number of the rays its material casts. */
layout(std430, set = 0, binding = VKRT_BINDING_WAVES) buffer WaveBuffer { WaveState waves[]; };
layout(std430, set = 0, binding = VKRT_BINDING_VISIBILITY) buffer VisibilityBuffer { uint light_visibility[]; };
layout(std430, set = 0, binding = VKRT_BINDING_SLOTS) buffer SlotBuffer { uvec2 ray_slots[]; };

/* The textures: each triangle's corners' texture coordinates, the maps' entries (glsl/shared.h
 * TextureInfo: an image read with its sampler and transform) and every image's texels. */
layout(std430, set = 0, binding = VKRT_BINDING_TEXCOORDS) readonly buffer TexcoordBuffer { TriangleTexcoords triangle_texcoords[]; };
layout(std430, set = 0, binding = VKRT_BINDING_TEXTURE_INFOS) readonly buffer TextureInfoBuffer { TextureInfo texture_infos[]; };
layout(std430, set = 0, binding = VKRT_BINDING_TEXELS) readonly buffer TexelBuffer { uint texels[]; };

/* The area lights and the sky: what light sampling needs to know of them, then the alias table
 * over the emissive triangles (glsl/shared.h LightInfo, Emitter; lib/emitters.glsl samples them). */
layout(std430, set = 0, binding = VKRT_BINDING_EMITTERS) readonly buffer EmitterBuffer {
    LightInfo light_info;
    Emitter emitters[];
};

/* Set for `vkrt bench --stats`: the traversal counts its work into counters.trace_* (slower;
 * never set for timed runs or renders). */
layout(constant_id = VKRT_SPEC_TRAVERSAL_STATS) const bool TRAVERSAL_STATS = false;

/* Children per node of the BVH's GPU layout: 2 (BvhPair) or 4 (BvhQuad). */
layout(constant_id = VKRT_SPEC_BVH_WIDTH) const uint BVH_WIDTH = 2u;

/* The integrator the kernels were built for (VKRT_INTEGRATE_*), and how the path tracer samples
 * direct light (VKRT_SAMPLING_*). */
layout(constant_id = VKRT_SPEC_INTEGRATOR) const uint INTEGRATOR = VKRT_INTEGRATE_WHITTED;
layout(constant_id = VKRT_SPEC_LIGHT_SAMPLING) const uint LIGHT_SAMPLING = VKRT_SAMPLING_MIS;

/* Set when a material of the scene is cut out by a texture (lib/cutout.glsl). */
layout(constant_id = VKRT_SPEC_HAS_CUTOUTS) const bool HAS_CUTOUTS = false;

/* Set for Whitted on a scene with emissive triangles: every hit sees a point drawn on them as one
 * more light (lib/emitters.glsl). */
layout(constant_id = VKRT_SPEC_EMITTER_LIGHT) const bool EMITTER_LIGHT = false;

/* The kinds of .mtl surface maps the scene's materials have: VKRT_MATERIAL_NORMAL_MAP,
 * _BUMP_MAP, _EMISSION_MAP (lib/surface_maps.glsl), and VKRT_MATERIAL_COAT where one has a clear
 * coat (lib/microfacet.glsl). */
layout(constant_id = VKRT_SPEC_SURFACE_MAPS) const uint SURFACE_MAPS = 0u;

/* `--clamp L`: no contribution added to a pixel has a channel above CLAMP (lib/pixel.glsl); 0 is
 * off (the default). */
layout(constant_id = VKRT_SPEC_CLAMP) const float CLAMP = 0.0;

/* `--target-error E` (adaptive sampling, glsl/adapt.comp): each pixel takes samples until its
 * estimated relative error (lib/adaptive.glsl) is at most TARGET_ERROR; 0 is off (the default,
 * and then none of the code below or in adapt.comp runs). Its buffers: per pixel its luminance
 * statistics; the pixels the next pass traces; and the luminance each sample of the pass adds
 * to its pixel (sample k of the pass at k * pixels + pixel), which adapt.comp folds into the
 * statistics and clears. */
layout(constant_id = VKRT_SPEC_TARGET_ERROR) const float TARGET_ERROR = 0.0;
layout(std430, set = 0, binding = VKRT_BINDING_PIXEL_STATS) buffer PixelStatsBuffer { PixelStats pixel_stats[]; };
layout(std430, set = 0, binding = VKRT_BINDING_ACTIVE_PIXELS) buffer ActivePixelBuffer {
    ActivePixels active_list;
    uint active_pixels[];
};
layout(std430, set = 0, binding = VKRT_BINDING_SAMPLE_LUMINANCE) buffer SampleLuminanceBuffer { float sample_luminance[]; };
layout(std430, set = 0, binding = VKRT_BINDING_SAMPLE_LUMINANCE) buffer SampleLuminanceWords { uint sample_luminance_words[]; };

/* Hits grouped by shader from depth VKRT_ORDER_FIRST_DEPTH on (glsl/order.comp; on GPUs, for
 * scenes of several shaders: src/render/tuning.c): the light, count and shade kernels read their
 * rays in that order. */
layout(constant_id = VKRT_SPEC_MATERIAL_ORDER) const bool MATERIAL_ORDER = false;
layout(std430, set = 0, binding = VKRT_BINDING_MATERIAL_ORDER) buffer MaterialOrderBuffer { uint material_order[]; };

/* Which structure trace_closest and trace_any walk (VKRT_TRAVERSE_*). */
layout(constant_id = VKRT_SPEC_ACCEL_KIND) const uint ACCEL_KIND = VKRT_TRAVERSE_BRUTE;

layout(push_constant) uniform FramePush { FrameParams frame; };

/* This invocation's item index; large dispatches fold into y (see gpu_dispatch). */
uint invocation_index()
{
    return gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
}

/* How many rays this dispatch covers: the host's count, or this depth's wave (clamped to the
 * buffers' capacity: rays past it were never stored). */
uint dispatch_ray_count()
{
    if (frame.counts.z != VKRT_RAYS_OF_WAVE)
        return frame.counts.z;
    return min(waves[frame.wave.y].ray_count, frame.wave.w);
}

/* Where depth's bin totals start in material_order (its cursors follow them), and where the
 * grouped order starts: after the bins of depths 0 to the max depth. */
uint order_bins_start(uint depth)
{
    return depth * 2u * VKRT_ORDER_BINS;
}
uint order_places_start()
{
    return order_bins_start(frame.wave.z + 1u);
}

/* The ray that invocation i of a light, count or shade dispatch handles (i below
 * dispatch_ray_count()): the i-th in the grouped order where there is one. */
uint ray_of_invocation(uint i)
{
    if (!MATERIAL_ORDER || frame.wave.y < VKRT_ORDER_FIRST_DEPTH)
        return i;
    return material_order[order_places_start() + i];
}

/* Ray i of this depth, from the buffer frame.wave.x names. */
Ray load_ray(uint i)
{
    /* Not a ?: expression: the two blocks' Ray are distinct SPIR-V types, and glslang would
     * select between them without converting (invalid SPIR-V). */
    if (frame.wave.x == 0u)
        return rays[i];
    return rays_b[i];
}

/* Stores a ray cast at this depth into slot i of the other buffer. */
void store_child_ray(uint i, Ray ray)
{
    if (frame.wave.x == 0u)
        rays_b[i] = ray;
    else
        rays[i] = ray;
}

/* Arrays larger than one buffer holds (glsl/shared.h VKRT_SPLIT_*, src/gpu/array.h): compiled
 * only for a scene that has one (the host defines VKRT_SPLIT_ARRAYS and turns on
 * GL_EXT_buffer_reference), so every other scene's kernels are what they were. Each split array
 * is read through the device addresses of its chunks; the rest through their bindings. */
#ifdef VKRT_SPLIT_ARRAYS
layout(constant_id = VKRT_SPEC_SPLIT_TRIANGLES) const uint SPLIT_TRIANGLES = 0u;
layout(constant_id = VKRT_SPEC_SPLIT_NORMALS) const uint SPLIT_NORMALS = 0u;
layout(constant_id = VKRT_SPEC_SPLIT_TEXCOORDS) const uint SPLIT_TEXCOORDS = 0u;
layout(constant_id = VKRT_SPEC_SPLIT_TRIANGLE_MATERIAL) const uint SPLIT_TRIANGLE_MATERIAL = 0u;
layout(constant_id = VKRT_SPEC_SPLIT_NODES) const uint SPLIT_NODES = 0u;
layout(constant_id = VKRT_SPEC_SPLIT_REFS) const uint SPLIT_REFS = 0u;
layout(constant_id = VKRT_SPEC_SPLIT_TEXELS) const uint SPLIT_TEXELS = 0u;
layout(std430, set = 0, binding = VKRT_BINDING_SPLIT_ADDRESSES) readonly buffer SplitAddressBuffer {
    uvec2 split_addresses[];
};
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer TriangleChunk { Triangle v[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer NormalChunk { TriangleNormals v[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer TexcoordChunk { TriangleTexcoords v[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer QuadChunk { BvhQuad v[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer PairChunk { BvhPair v[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer KdChunk { KdNode v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer WordChunk { uint v[]; };

/* The address of the chunk that holds element i of split array k, of chunks of 2^s elements. */
uvec2 split_chunk(uint k, uint i, uint s)
{
    return split_addresses[k * VKRT_MAX_CHUNKS + (i >> s)];
}

/* Element i's index within its chunk. */
uint split_index(uint i, uint s)
{
    return i & ((1u << s) - 1u);
}
#endif

/* The per-triangle arrays, the structure's and the textures' elements, wherever they are: at
 * their bindings, or in the chunks of a split array. Traversal reads triangles and nodes through
 * load_triangle and the node loads below, which add the texel path. Without a split array they
 * are the plain loads, as macros: the SPIR-V is then what it was before arrays could split. */
#ifdef VKRT_SPLIT_ARRAYS
/* The loader of one array: element i from the chunk of split array k (chunks of 2^s elements,
 * through Chunk's buffer reference) where the array is split, else from its binding. An if, not
 * a ?: expression: a chunk's element and a binding's are distinct SPIR-V types. */
#define SPLIT_LOADER(Type, name, Chunk, k, s, bound)                                           \
    Type name(uint i)                                                                          \
    {                                                                                          \
        if (s != 0u)                                                                           \
            return Chunk(split_chunk(k, i, s)).v[split_index(i, s)];                           \
        return bound[i];                                                                       \
    }
SPLIT_LOADER(Triangle, triangle_at, TriangleChunk, VKRT_SPLIT_TRIANGLES, SPLIT_TRIANGLES, triangles)
SPLIT_LOADER(TriangleNormals, normals_at, NormalChunk, VKRT_SPLIT_NORMALS, SPLIT_NORMALS,
             triangle_normals)
SPLIT_LOADER(TriangleTexcoords, texcoords_at, TexcoordChunk, VKRT_SPLIT_TEXCOORDS,
             SPLIT_TEXCOORDS, triangle_texcoords)
/* The material of triangle i. */
SPLIT_LOADER(uint, material_of, WordChunk, VKRT_SPLIT_TRIANGLE_MATERIAL, SPLIT_TRIANGLE_MATERIAL,
             triangle_material)
/* Entry i of the grid's or the kd-tree's triangle references. */
SPLIT_LOADER(uint, ref_at, WordChunk, VKRT_SPLIT_REFS, SPLIT_REFS, grid_refs)
/* Where grid cell i's references start (cell i + 1's start is where they end). */
SPLIT_LOADER(uint, cell_start_at, WordChunk, VKRT_SPLIT_NODES, SPLIT_NODES, grid_cell_start)
/* Word i of the texel buffer (lib/texture.glsl). */
SPLIT_LOADER(uint, texel_word, WordChunk, VKRT_SPLIT_TEXELS, SPLIT_TEXELS, texels)
#undef SPLIT_LOADER
#else
#define triangle_at(i) triangles[i]
#define normals_at(i) triangle_normals[i]
#define texcoords_at(i) triangle_texcoords[i]
#define material_of(i) triangle_material[i]
#define ref_at(i) grid_refs[i]
#define cell_start_at(i) grid_cell_start[i]
#define texel_word(i) texels[i]
#endif

/* Triangle i and BVH pair record i, through whichever of the two bindings TEXEL_LOADS chooses (a
 * specialization constant: the other load is dead code; the host never sets it for a split
 * array). The 4-wide walk loads its nodes itself (lib/traverse_bvh.glsl). */
Triangle load_triangle(uint i)
{
    if (TEXEL_LOADS) {
        int t = int(3u * i);
        return Triangle(uintBitsToFloat(texelFetch(triangle_texels, t)),
                        uintBitsToFloat(texelFetch(triangle_texels, t + 1)),
                        uintBitsToFloat(texelFetch(triangle_texels, t + 2)));
    }
    return triangle_at(i);
}

BvhPair load_pair(uint i)
{
    if (TEXEL_LOADS) {
        int t = int(4u * i);
        return BvhPair(uintBitsToFloat(texelFetch(node_texels, t)),
                       uintBitsToFloat(texelFetch(node_texels, t + 1)),
                       uintBitsToFloat(texelFetch(node_texels, t + 2)),
                       texelFetch(node_texels, t + 3));
    }
#ifdef VKRT_SPLIT_ARRAYS
    if (SPLIT_NODES != 0u)
        return PairChunk(split_chunk(VKRT_SPLIT_NODES, i, SPLIT_NODES)).v[split_index(i, SPLIT_NODES)];
#endif
    return bvh_pairs[i];
}

#endif
