/*
 * envmap.glsl: the environment map as a light: directions to and from the map's uv, and
 * importance sampling by its piecewise-constant 2D distribution (pbrt's Distribution2D).
 *
 * src/scene/envmap.h defines the convention and the buffer, and src/scene/envmap.c mirrors every
 * function here step by step in C for the tests (tests/test_envmap.c): a change here belongs
 * there too. In short: +y is up; uv is the texture's uv (lib/texture.glsl: v = 0 is the bottom
 * row), so the map's bilinear lookup at envmap_uv(d, info.environment_rotate) (envmap_radiance in
 * lib/environment.glsl, filtered as texture_sample filters) is its radiance along d (times
 * info.environment_scale); u = 0 looks down -z, u = 0.25 down +x,
 * as Mitsuba's envmap does. The buffer holds, for a W x H map, the marginal CDF over rows (H + 1
 * floats, top row first) and then each row's conditional CDF (W + 1 floats each).
 *
 * Include after lib/bindings.glsl. LightInfo comes as a parameter: the caller reads it once.
 */
#ifndef VKRT_ENVMAP_GLSL
#define VKRT_ENVMAP_GLSL

#include "../shared.h"

layout(std430, set = 0, binding = VKRT_BINDING_ENVIRONMENT) readonly buffer EnvironmentBuffer {
    float environment_distribution[];
};

const float ENVMAP_PI = 3.14159265358979323846;
/* The largest float below 1: uniform numbers are clamped to it so that a CDF walk never runs off
 * the end of a table (whose last value is exactly 1). */
const float ENVMAP_ONE_MINUS_EPSILON = 0.99999994; /* 1 - 2^-24 */

/* The unit direction in which the map's texture uv is seen. rotate: radians about +y. */
vec3 envmap_direction(vec2 uv, float rotate)
{
    float phi = 2.0 * ENVMAP_PI * uv.x - rotate;
    float theta = ENVMAP_PI * (1.0 - uv.y);
    float sin_theta = sin(theta);
    return vec3(sin(phi) * sin_theta, cos(theta), -cos(phi) * sin_theta);
}

/* The map's texture uv seen along unit direction dir; u in [0, 1]. */
vec2 envmap_uv(vec3 dir, float rotate)
{
    /* Straight up or down every u is the same direction; atan(0, 0) is undefined. */
    float phi = (dir.x == 0.0 && dir.z == 0.0) ? 0.0 : atan(dir.x, -dir.z);
    float u = (phi + rotate) * (1.0 / (2.0 * ENVMAP_PI));
    float y = clamp(dir.y, -1.0, 1.0);
    return vec2(u - floor(u), 1.0 - acos(y) * (1.0 / ENVMAP_PI));
}

/* The largest i in [0, n) with cdf[i] <= x, the CDF being environment_distribution[base ...
 * base + n] with cdf[0] = 0 <= x < 1 = cdf[n]: the segment holding x, never one of zero width. */
uint envmap_cdf_find(uint base, uint n, float x)
{
    uint lo = 0u, hi = n - 1u;
    while (lo < hi) {
        uint mid = (lo + hi + 1u) / 2u;
        if (environment_distribution[base + mid] <= x)
            lo = mid;
        else
            hi = mid - 1u;
    }
    return lo;
}

/* Maps two uniform numbers in [0, 1) to the map's texture uv, distributed as the map's luminance
 * (times sin(theta)); *pdf_uv is the density in uv. The direction is envmap_direction(uv,
 * info.environment_rotate); its solid-angle density is pdf_uv / (2 pi^2 sin(theta)). */
vec2 envmap_sample(LightInfo info, vec2 u, out float pdf_uv)
{
    uint width = info.environment_width, height = info.environment_height;
    u = clamp(u, vec2(0.0), vec2(ENVMAP_ONE_MINUS_EPSILON));
    uint y = envmap_cdf_find(0u, height, u.x);
    float row_start = environment_distribution[y];
    float row_p = environment_distribution[y + 1u] - row_start;
    float fy = min((u.x - row_start) / row_p, ENVMAP_ONE_MINUS_EPSILON);

    uint base = (height + 1u) + y * (width + 1u);
    uint x = envmap_cdf_find(base, width, u.y);
    float texel_start = environment_distribution[base + x];
    float texel_p = environment_distribution[base + x + 1u] - texel_start;
    float fx = min((u.y - texel_start) / texel_p, ENVMAP_ONE_MINUS_EPSILON);

    pdf_uv = row_p * float(height) * texel_p * float(width);
    return vec2((float(x) + fx) / float(width), 1.0 - (float(y) + fy) / float(height));
}

/* The density in uv of the texel holding texture uv (u wrapped, v clamped). */
float envmap_pdf_uv(LightInfo info, vec2 uv)
{
    uint width = info.environment_width, height = info.environment_height;
    float u = uv.x - floor(uv.x);
    float t = clamp(1.0 - uv.y, 0.0, 1.0); /* theta / pi: rows are stored from the top */
    uint x = uint(min(u * float(width), float(width - 1u)));
    uint y = uint(min(t * float(height), float(height - 1u)));
    uint base = (height + 1u) + y * (width + 1u);
    return (environment_distribution[y + 1u] - environment_distribution[y]) * float(height) *
           (environment_distribution[base + x + 1u] - environment_distribution[base + x]) *
           float(width);
}

/* The solid-angle density with which envmap_sample yields unit direction dir (world space):
 * pdf_uv / (2 pi^2 sin(theta)); 0 straight up or down. For the MIS weight of a BSDF ray that
 * escapes. */
float envmap_pdf(LightInfo info, vec3 dir)
{
    float sin_theta = sqrt(dir.x * dir.x + dir.z * dir.z);
    if (!(sin_theta > 0.0))
        return 0.0;
    vec2 uv = envmap_uv(dir, info.environment_rotate);
    return envmap_pdf_uv(info, uv) / (2.0 * ENVMAP_PI * ENVMAP_PI * sin_theta);
}

#endif
