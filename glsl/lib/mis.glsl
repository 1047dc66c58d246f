/*
 * mis.glsl: weights of multiple importance sampling (Veach 1997, ch. 9), written to compile as C
 * as well as GLSL (scalars only, no built-ins) so that tests/test_sampler.c can hold them to
 * their limits.
 */
#ifndef VKRT_MIS_GLSL
#define VKRT_MIS_GLSL

/* Veach's power heuristic (exponent 2) for a sample of pdf a against the other strategy's b:
 * a^2 / (a^2 + b^2), written as 1 / (1 + (b/a)^2) so that it stays in [0, 1] where a pdf is huge:
 * a light sample towards an emitter seen edge-on (its solid-angle pdf has cos ~ 0 below it,
 * 1e20 and more) squared to infinity, and inf / inf made the contribution NaN. 0 for a pdf of 0
 * or NaN. */
float power_heuristic(float a, float b)
{
    if (!(a > 0.0))
        return 0.0;
    if (!(b > 0.0))
        return 1.0;
    float r = b / a;
    if (!(r == r)) /* both infinite */
        return 0.5;
    return 1.0 / (1.0 + r * r);
}

#endif
