/*
 * rng.glsl: random numbers for the kernels.
 *
 * PCG hash (Jarzynski and Olano, "Hash Functions for GPU Rendering", JCGT 2020): a stateless
 * hash of good quality, so a ray carries only a 32-bit state and any (pixel, sample) pair can
 * start its own stream without a table of generators.
 */
#ifndef VKRT_RNG_GLSL
#define VKRT_RNG_GLSL

uint pcg_hash(uint v)
{
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

/* Advances state and returns a float uniform in [0, 1): the top 24 bits, so 1.0 never occurs. */
float rng_next(inout uint state)
{
    state = pcg_hash(state);
    return float(state >> 8) * (1.0 / 16777216.0);
}

#endif
