/*
 * adaptive.glsl: what `--target-error E` measures (docs/scene-format.md, "Sampling to a target
 * error"), written once for the kernels (glsl/adapt.comp decides which pixels take more samples)
 * and for the host (src/render/renderer_adaptive.c reports the error reached, and tests hold it
 * against the true error): compiled as C too, like sampler.glsl.
 *
 * The estimate of a pixel is the relative standard error of the mean of its samples' luminance:
 *
 *     e = sqrt(s^2 / n) / max(mean, VKRT_ADAPTIVE_FLOOR),   s^2 = m2 / (n - 1),
 *
 * with n the pixel's samples (at least VKRT_ADAPTIVE_MIN_SAMPLES before it may stop),
 * VKRT_ADAPTIVE_FLOOR the floor for dark pixels (both in glsl/shared.h, which says why), mean
 * and m2 their luminance's mean and sum of squared deviations from it (Welford's update,
 * adaptive_add; stable in float where a sum and a sum of squares would cancel), luminance the
 * Rec. 709 weights of lib/colour.glsl. It is the error a pixel's average has, as a
 * share of the pixel, for independent samples: vkrt's stratified samples (lib/sampler.glsl) do
 * at least as well, so the estimate errs on the safe side.
 */
#ifndef VKRT_ADAPTIVE_GLSL
#define VKRT_ADAPTIVE_GLSL

/* The pixel's estimated relative error (above); 1e30 before two samples. */
float adaptive_relative_error(float mean, float m2, uint n)
{
    if (n < 2u)
        return 1e30f;
    /* uint to float is implicit in GLSL and C alike. */
    float samples = n, degrees = n - 1u;
    float variance = (m2 > 0.0f ? m2 : 0.0f) / degrees;
    return sqrt(variance / samples) / (mean > VKRT_ADAPTIVE_FLOOR ? mean : VKRT_ADAPTIVE_FLOOR);
}

#ifdef VKRT_GLSL
/* Adds sample luminance x to a pixel's (mean, m2) after n - 1 samples, making n. */
void adaptive_add(inout float mean, inout float m2, uint n, float x)
{
    float delta = x - mean;
    mean += delta / float(n);
    m2 += delta * (x - mean);
}
#endif

#endif
