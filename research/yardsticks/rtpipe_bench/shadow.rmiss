/*
 * shadow.rmiss: miss index 1, for shadow rays: nothing blocks the ray, so it is "not blocked"
 * (VKRT_NO_HIT, what vkrt's occlusion kernel writes); raygen.rgen starts it as blocked.
 */
#extension GL_EXT_ray_tracing : require
#include "shared.h"

layout(location = 0) rayPayloadInEXT Hit payload;

void main()
{
    payload.triangle = VKRT_NO_HIT;
}
