/*
 * miss.rmiss: a closest-hit ray that hits nothing: no triangle, t the ray's tmax (what vkrt's
 * trace kernel leaves in a missing ray's Hit).
 */
#extension GL_EXT_ray_tracing : require
#include "shared.h"

layout(location = 0) rayPayloadInEXT Hit payload;

void main()
{
    payload = Hit(gl_RayTmaxEXT, 0.0, 0.0, VKRT_NO_HIT);
}
