/*
 * closest.rchit: the closest hit of a primary or diffuse ray, as a Hit (glsl/shared.h). The
 * built-in triangle barycentrics are the weights of vertices 1 and 2, vkrt's u and v; the
 * primitive index is the triangle's index in the OBJ's order, since the one geometry is the
 * mesh's triangles in that order, non-indexed.
 */
#extension GL_EXT_ray_tracing : require
#include "shared.h"

layout(location = 0) rayPayloadInEXT Hit payload;
hitAttributeEXT vec2 barycentrics;

void main()
{
    payload = Hit(gl_HitTEXT, barycentrics.x, barycentrics.y, uint(gl_PrimitiveID));
}
