/*
 * bindings.glsl: the one descriptor set every wavefront kernel sees (set 0), and the frame's push
 * constants. The host binds the same set to every pipeline (src/render/renderer.c keeps the
 * binding numbers in the same order); a kernel simply ignores the buffers it does not read.
 */
#ifndef VKRT_BINDINGS_GLSL
#define VKRT_BINDINGS_GLSL

#include "../shared.h"

layout(local_size_x_id = 0) in;

/* Set when the OBJ had normals and the TriangleNormals buffer is real. */
layout(constant_id = 1) const bool HAS_NORMALS = false;
/* Set when a material reads textures and the TriangleTexcoords buffer is real. */
layout(constant_id = 3) const bool HAS_TEXCOORDS = false;
/* The workgroup size of the wave kernels, for the kernel that writes their indirect dispatches. */
layout(constant_id = 4) const uint WAVE_WORKGROUP_SIZE = 64u;

/* Rays live in two buffers, A and B: one depth's rays in one, the rays they cast in the other
 * (frame.wave.x says which is which). Two bindings rather than two halves of one buffer, so each
 * can be as large as maxStorageBufferRange (128 MiB on lavapipe). */
layout(std430, set = 0, binding = 0) buffer RayBuffer { Ray rays[]; };
layout(std430, set = 0, binding = 12) buffer RayBufferB { Ray rays_b[]; };
layout(std430, set = 0, binding = 1) buffer HitBuffer { Hit hits[]; };
layout(std430, set = 0, binding = 2) readonly buffer TriangleBuffer { Triangle triangles[]; };
layout(std430, set = 0, binding = 3) readonly buffer NormalBuffer { TriangleNormals triangle_normals[]; };
layout(std430, set = 0, binding = 4) readonly buffer TriangleMaterialBuffer { uint triangle_material[]; };
layout(std430, set = 0, binding = 5) readonly buffer MaterialBuffer { Material materials[]; };
layout(std430, set = 0, binding = 6) readonly buffer LightBuffer { Light lights[]; };
layout(std430, set = 0, binding = 7) buffer ImageBuffer { vec4 image[]; };
layout(std430, set = 0, binding = 7) buffer ImageWords { uint image_words[]; };
layout(std430, set = 0, binding = 8) buffer CounterBuffer { Counters counters; };

/* The acceleration structure: binding 9 is the grid's frame, binding 10 the BVH's nodes (4-wide
 * or pairs) or the grid's cell starts (one binding, three views: only the chosen one is read), binding 11 the
 * grid's triangle references. */
layout(std430, set = 0, binding = 9) readonly buffer GridInfoBuffer { GridInfo grid; };
layout(std430, set = 0, binding = 10) readonly buffer BvhNodeBuffer { BvhQuad bvh_nodes[]; };
layout(std430, set = 0, binding = 10) readonly buffer BvhPairBuffer { BvhPair bvh_pairs[]; };
layout(std430, set = 0, binding = 10) readonly buffer GridCellBuffer { uint grid_cell_start[]; };
layout(std430, set = 0, binding = 11) readonly buffer GridRefBuffer { uint grid_refs[]; };

/* The triangles and the structure's nodes once more, as uniform texel buffers of 16-byte texels:
 * views of bindings 2 and 10 (src/render/renderer.c, create_texel_views). Traversal reads them
 * when TEXEL_LOADS is set (on CPU devices, by default): Mesa's llvmpipe loads from a storage
 * buffer one lane and one word at a time, each behind a bounds check and a branch, and fetches
 * from a texel buffer with vector gathers (docs/performance.md). */
layout(set = 0, binding = 20) uniform usamplerBuffer triangle_texels;
layout(set = 0, binding = 21) uniform usamplerBuffer node_texels;
layout(constant_id = 9) const bool TEXEL_LOADS = false;

/* Set when the BVH's walk runs inner nodes and leaves in two loops of their own
 * (lib/traverse_bvh.glsl, bvh_traverse_nested): on CPU devices, by default. */
layout(constant_id = 10) const bool NESTED_WALK = false;

/* The wave machinery: one WaveState per depth, light visibility bits (frame.range.w words per
 * ray, bit k of word k / 32 set when light k reaches the hit), and for each ray the first slot and
 * number of the rays its material casts. */
layout(std430, set = 0, binding = 13) buffer WaveBuffer { WaveState waves[]; };
layout(std430, set = 0, binding = 14) buffer VisibilityBuffer { uint light_visibility[]; };
layout(std430, set = 0, binding = 15) buffer SlotBuffer { uvec2 ray_slots[]; };
layout(std430, set = 0, binding = 16) readonly buffer TexcoordBuffer { TriangleTexcoords triangle_texcoords[]; };
layout(std430, set = 0, binding = 17) readonly buffer TextureInfoBuffer { TextureInfo texture_infos[]; };
layout(std430, set = 0, binding = 18) readonly buffer TexelBuffer { uint texels[]; };
/* Per depth, how many of that depth's rays the trace kernels have taken (dynamic ray fetch,
 * lib/trace_wave.glsl); zeroed before each trace. */
layout(std430, set = 0, binding = 19) buffer TraceCursorBuffer { uint trace_cursor[]; };

/* Set for `vkrt bench --stats`: the traversal counts its work into counters.trace_* (slower;
 * never set for timed runs or renders). */
layout(constant_id = 5) const bool TRAVERSAL_STATS = false;

/* Children per node of the BVH's GPU layout: 2 (BvhPair) or 4 (BvhQuad). */
layout(constant_id = 6) const uint BVH_WIDTH = 2u;

/* Set when the trace kernels walk the (2-wide) BVH with dynamic ray fetch (lib/trace_wave.glsl)
 * rather than one ray per invocation. */
layout(constant_id = 7) const bool DYNAMIC_FETCH = false;

/* Which structure trace_closest and trace_any walk (VKRT_TRAVERSE_*). */
layout(constant_id = 2) const uint ACCEL_KIND = VKRT_TRAVERSE_BRUTE;

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

/* Triangle i and BVH pair record i, through whichever of the two bindings TEXEL_LOADS chooses (a
 * specialization constant: the other load is dead code). The 4-wide walk loads its nodes itself
 * (lib/traverse_bvh.glsl). */
Triangle load_triangle(uint i)
{
    if (TEXEL_LOADS) {
        int t = int(3u * i);
        return Triangle(uintBitsToFloat(texelFetch(triangle_texels, t)),
                        uintBitsToFloat(texelFetch(triangle_texels, t + 1)),
                        uintBitsToFloat(texelFetch(triangle_texels, t + 2)));
    }
    return triangles[i];
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
    return bvh_pairs[i];
}

#endif
