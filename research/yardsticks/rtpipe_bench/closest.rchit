/*
 * closest.rchit: the closest hit of a primary or diffuse ray, as a Hit (glsl/shared.h). The
 * built-in triangle barycentrics are the weights of vertices 1 and 2, vkrt's u and v (in the
 * mesh's own space, which an affine instance transform does not change); gl_HitTEXT is the
 * world ray's parameter. The triangle is numbered as vkrt bench numbers it (vkrt_model_world's
 * order), by specialization constant HIT_NUMBERING (rtpipe_accel.h, rtpipe_hit_numbering):
 *   0  flat: the one geometry is the scene's triangles in that order, non-indexed, so the
 *      primitive index is the number;
 *   1  two-level: each BLAS is its mesh's triangles in the mesh's order, and the instance's
 *      custom index is its first triangle: custom index + primitive index;
 *   2  two-level with first triangles past the custom index's 24 bits: instance_first[the
 *      instance's index in the TLAS] + primitive index.
 */
#extension GL_EXT_ray_tracing : require
#include "shared.h"

layout(constant_id = 0) const uint HIT_NUMBERING = 0u;

layout(set = 0, binding = 3, std430) readonly buffer InstanceFirst { uint instance_first[]; };

layout(location = 0) rayPayloadInEXT Hit payload;
hitAttributeEXT vec2 barycentrics;

void main()
{
    uint first = 0u;
    if (HIT_NUMBERING == 1u)
        first = uint(gl_InstanceCustomIndexEXT);
    else if (HIT_NUMBERING == 2u)
        first = instance_first[gl_InstanceID];
    payload = Hit(gl_HitTEXT, barycentrics.x, barycentrics.y, first + uint(gl_PrimitiveID));
}
