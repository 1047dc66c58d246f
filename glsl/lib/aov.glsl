/*
 * aov.glsl: the AOVs of `--aov` (glsl/shared.h VKRT_AOV_*), what each sample adds to its pixel's
 * planes. AOVS is a specialization constant: 0 (the default) leaves every call below dead code,
 * so the kernels of a render without --aov are what they were, and the AOV buffer is a minimal
 * one that nothing reads.
 *
 * Depth and position are the camera ray's first hit. Albedo and normal are those of the first
 * surface the path meets that is not a perfect mirror or glass (OpenImageDenoise's advice for
 * its auxiliary images: follow delta bounces and store the features of the first diffuse or
 * glossy hit), which the integrators find by carrying VKRT_RAY_AOV_PENDING along delta bounces
 * (shade.comp). Every sample adds its share, so the planes are filtered as the beauty image is:
 * the host divides by the pixel's samples (renderer_aov.c).
 */
#ifndef VKRT_AOV_GLSL
#define VKRT_AOV_GLSL

#include "bindings.glsl"

/* The AOVs the kernels record (VKRT_AOV_* bits); 0: none. */
layout(constant_id = VKRT_SPEC_AOVS) const uint AOVS = 0u;
layout(std430, set = 0, binding = VKRT_BINDING_AOVS) buffer AovBuffer { vec4 aov_planes[]; };
/* The same words as floats and as bits, for the atomic adds. */
layout(std430, set = 0, binding = VKRT_BINDING_AOVS) buffer AovFloats { float aov_floats[]; };
layout(std430, set = 0, binding = VKRT_BINDING_AOVS) buffer AovWords { uint aov_words[]; };

/* Where pixel p's vec4 of AOV a (one VKRT_AOV_* bit) is: its plane is the count of the AOVs
 * asked for below it. */
uint aov_slot(uint a, uint p)
{
    return uint(bitCount(AOVS & (a - 1u))) * frame.image.x * frame.image.y + p;
}

/* Adds v to word `word` of the planes: a float atomic where the device has them (the generated
 * material module's VKRT_FLOAT_ATOMICS), else a compare-and-swap loop on the float's bits.
 * Several samples of a pixel may add at once (a pass holds several where the image is small). */
void aov_add_word(uint word, float v)
{
    if (v == 0.0)
        return;
#ifdef VKRT_FLOAT_ATOMICS
    atomicAdd(aov_floats[word], v);
#else
    uint seen = aov_words[word];
    for (;;) {
        uint before = atomicCompSwap(aov_words[word], seen, floatBitsToUint(uintBitsToFloat(seen) + v));
        if (before == seen)
            break;
        seen = before;
    }
#endif
}

/* Adds the first `lanes` components of v to pixel p's vec4 of AOV a. */
void aov_add(uint a, uint p, vec4 v, uint lanes)
{
    uint word = 4u * aov_slot(a, p);
    for (uint k = 0u; k < lanes; ++k)
        aov_add_word(word + k, v[k]);
}

/* Clears pixel p's planes: raygen, at the frame's first sample of the pixel. */
void aov_clear(uint p)
{
    for (uint a = 1u; a <= VKRT_AOV_POSITION; a <<= 1u)
        if ((AOVS & a) != 0u)
            aov_planes[aov_slot(a, p)] = vec4(0.0);
}

/* Where ray's path ends its search for a surface: albedo (clamped to [0, 1], the range
 * OpenImageDenoise takes; NaN counts as 0) and the shading normal there. A path that escaped
 * gives the environment's radiance as its albedo and a zero normal. */
void aov_record_surface(Ray ray, vec3 albedo, vec3 normal)
{
    uint p = ray_pixel(ray);
    if ((AOVS & VKRT_AOV_ALBEDO) != 0u) {
        vec3 a = any(isnan(albedo)) ? vec3(0.0) : clamp(albedo, 0.0, 1.0);
        aov_add(VKRT_AOV_ALBEDO, p, vec4(a, 0.0), 3u);
    }
    if ((AOVS & VKRT_AOV_NORMAL) != 0u)
        aov_add(VKRT_AOV_NORMAL, p, vec4(normal, 0.0), 3u);
}

/* A camera ray's hit: its distance t along the ray (the camera-space distance from the ray's
 * origin: the eye, a point of the lens, or of the orthographic image plane) and the world-space
 * point; each with a count of 1, the host's divisor. Rays past the camera's do nothing. */
void aov_record_first_hit(Ray ray, float t, vec3 position)
{
    if (ray_depth(ray) != 0u)
        return;
    uint p = ray_pixel(ray);
    if ((AOVS & VKRT_AOV_DEPTH) != 0u)
        aov_add(VKRT_AOV_DEPTH, p, vec4(t, 1.0, 0.0, 0.0), 2u);
    if ((AOVS & VKRT_AOV_POSITION) != 0u)
        aov_add(VKRT_AOV_POSITION, p, vec4(position, 1.0), 4u);
}

/* Ray i of the next depth, which a hit of this one cast (the other buffer than load_ray's). */
Ray aov_load_child_ray(uint i)
{
    if (frame.wave.x == 0u)
        return rays_b[i];
    return rays[i];
}

#endif
