/*
 * environment.glsl: the light of rays that leave the scene: the environment map's radiance
 * (scene.cfg `environment-map`, bilinear over its float pixels, which follow its sampling
 * distribution in the environment buffer: lib/envmap.glsl) or, without a map, the environment
 * shader's (the built-in constant of `environment R G B`, or a user's sky). Both integrators.
 * Included after the generated material module.
 */
#ifndef VKRT_ENVIRONMENT_GLSL
#define VKRT_ENVIRONMENT_GLSL

#include "envmap.glsl"

/* Pixel (x, y) of the map, x from the left and wrapped (the map goes round), y from the top row
 * and clamped: above the top row is the zenith, not the bottom row (src/scene/envmap.h). */
vec3 envmap_pixel(int x, int y)
{
    uint w = light_info.environment_width, h = light_info.environment_height;
    uint row = uint(clamp(y, 0, int(h) - 1));
    uint at = light_info.environment_pixels + 3u * (row * w + texture_wrap(x, w));
    return vec3(environment_distribution[at], environment_distribution[at + 1u],
                environment_distribution[at + 2u]);
}

/* The map's radiance along unit direction d: bilinear at its uv, as texture_sample filters. */
vec3 envmap_radiance(vec3 d)
{
    vec2 uv = envmap_uv(d, light_info.environment_rotate);
    vec2 p = fract(vec2(uv.x, 1.0 - uv.y)) *
                 vec2(light_info.environment_width, light_info.environment_height) - 0.5;
    vec2 p0 = floor(p);
    vec2 f = p - p0;
    int x = int(p0.x), y = int(p0.y);
    vec3 top = mix(envmap_pixel(x, y), envmap_pixel(x + 1, y), f.x);
    vec3 bottom = mix(envmap_pixel(x, y + 1), envmap_pixel(x + 1, y + 1), f.x);
    return light_info.environment_scale * mix(top, bottom, f.y);
}

/* The radiance arriving along a ray of direction d (unit) and payload that left the scene. */
vec3 environment_radiance(vec3 d, vec4 payload)
{
    if (light_info.environment_width > 0u)
        return envmap_radiance(d);
    /* The environment shader reads its own parameters (param reads vkrt_material's), also when
     * a surface asks, as next-event estimation does: else a light sample of `environment 1 1 1`
     * came back as the surface's Kd (invisible on a white furnace, black on a metal). */
    uint asking = vkrt_material;
    vkrt_material = VKRT_ENVIRONMENT_MATERIAL;
    vec3 radiance = material_environment(d, payload);
    vkrt_material = asking;
    return radiance;
}

#endif
