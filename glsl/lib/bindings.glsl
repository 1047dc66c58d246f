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

layout(std430, set = 0, binding = 0) buffer RayBuffer { Ray rays[]; };
layout(std430, set = 0, binding = 1) buffer HitBuffer { Hit hits[]; };
layout(std430, set = 0, binding = 2) readonly buffer TriangleBuffer { Triangle triangles[]; };
layout(std430, set = 0, binding = 3) readonly buffer NormalBuffer { TriangleNormals triangle_normals[]; };
layout(std430, set = 0, binding = 4) readonly buffer TriangleMaterialBuffer { uint triangle_material[]; };
layout(std430, set = 0, binding = 5) readonly buffer MaterialBuffer { Material materials[]; };
layout(std430, set = 0, binding = 6) readonly buffer LightBuffer { Light lights[]; };
layout(std430, set = 0, binding = 7) buffer ImageBuffer { vec4 image[]; };
layout(std430, set = 0, binding = 8) buffer CounterBuffer { Counters counters; };

/* The acceleration structure: binding 9 is the grid's frame, binding 10 the BVH's nodes or the
 * grid's cell starts (one binding, two views: only the chosen structure's is read), binding 11 the
 * grid's triangle references. */
layout(std430, set = 0, binding = 9) readonly buffer GridInfoBuffer { GridInfo grid; };
layout(std430, set = 0, binding = 10) readonly buffer BvhNodeBuffer { BvhNode bvh_nodes[]; };
layout(std430, set = 0, binding = 10) readonly buffer GridCellBuffer { uint grid_cell_start[]; };
layout(std430, set = 0, binding = 11) readonly buffer GridRefBuffer { uint grid_refs[]; };

/* Which structure trace_closest and trace_any walk (VKRT_TRAVERSE_*). */
layout(constant_id = 2) const uint ACCEL_KIND = VKRT_TRAVERSE_BRUTE;

layout(push_constant) uniform FramePush { FrameParams frame; };

/* This invocation's item index; large dispatches fold into y (see gpu_dispatch). */
uint invocation_index()
{
    return gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
}

#endif
