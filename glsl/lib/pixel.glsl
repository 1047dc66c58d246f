/*
 * pixel.glsl: adding radiance to the image. Several rays of one pass may add to one pixel at once
 * (a material's several rays, the path tracer's light samples and its hits), so additions are
 * atomic. Needs the generated material module's VKRT_FLOAT_ATOMICS (from the device).
 */
#ifndef VKRT_PIXEL_GLSL
#define VKRT_PIXEL_GLSL

#include "bindings.glsl"
#include "colour.glsl"

/* Adds c to pixel p. Float atomics where the device has them (VK_EXT_shader_atomic_float), else a
 * compare-and-swap loop on the float's bits. */
void add_to_pixel(uint p, vec3 c)
{
#ifdef VKRT_FLOAT_ATOMICS
    atomicAdd(image[p].x, c.x);
    atomicAdd(image[p].y, c.y);
    atomicAdd(image[p].z, c.z);
#else
    for (uint k = 0u; k < 3u; ++k) {
        uint word = 4u * p + k;
        uint seen = image_words[word];
        for (;;) {
            uint wanted = floatBitsToUint(uintBitsToFloat(seen) + c[k]);
            uint before = atomicCompSwap(image_words[word], seen, wanted);
            if (before == seen)
                break;
            seen = before;
        }
    }
#endif
}

/* Adaptive sampling: adds luminance x to the slot of sample `sample_index` of pixel p in this pass
 * (lib/bindings.glsl), which adapt.comp reads after the pass. Float atomics where the device has
 * them, else a compare-and-swap loop, as add_to_pixel. */
void add_to_sample_luminance(uint p, uint sample_index, float x)
{
    uint slot = (sample_index - frame.image.z) * frame.image.x * frame.image.y + p;
#ifdef VKRT_FLOAT_ATOMICS
    atomicAdd(sample_luminance[slot], x);
#else
    uint seen = sample_luminance_words[slot];
    for (;;) {
        uint wanted = floatBitsToUint(uintBitsToFloat(seen) + x);
        uint before = atomicCompSwap(sample_luminance_words[slot], seen, wanted);
        if (before == seen)
            break;
        seen = before;
    }
#endif
}

/* Adds c to the pixel of ray (ray_pixel; with --target-error, also to its sample's luminance,
 * ray_sample) unless it is zero, or NaN or infinite: one of those would spread through every
 * sample of its pixel, so it is dropped and counted (the host warns). With `--clamp L`
 * (CLAMP > 0) c is first scaled so that its largest channel is at most L: each call adds one
 * path's contribution (a light sample, or the light a ray found), so this is Cycles' sample
 * clamp, hue kept. Biased: the light of rare bright paths is lost, and fireflies with it. */
void add_finite_to_pixel(Ray ray, vec3 c)
{
    uint p = ray_pixel(ray);
    if (any(isnan(c)) || any(isinf(c))) {
        atomicAdd(counters.nonfinite, 1u);
        return;
    }
    if (CLAMP > 0.0) {
        float largest = max(c.r, max(c.g, c.b));
        if (largest > CLAMP)
            c *= CLAMP / largest;
    }
    if (any(notEqual(c, vec3(0.0)))) {
        add_to_pixel(p, c);
        /* With --target-error, the sample's luminance too, for its pixel's error estimate. */
        if (TARGET_ERROR > 0.0)
            add_to_sample_luminance(p, ray_sample(ray), luminance(c));
    }
}

#endif
