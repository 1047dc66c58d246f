/*
 * rng.glsl: random numbers for the kernels.
 *
 * PCG hash (Jarzynski and Olano, "Hash Functions for GPU Rendering", JCGT 2020): a stateless
 * hash of good quality, so a ray carries only a 32-bit state and any (pixel, sample) pair can
 * start its own stream without a table of generators.
 *
 * Streams: a ray's seed is the state of its stream; rng_next advances it. A child ray (secondary
 * ray k of a hit) starts a new stream with rng_child_seed, which hashes the parent's state with k
 * through a second, differently keyed hash, so that siblings and parent do not walk the same
 * sequence shifted by one step (the seed used two generators for the same reason).
 *
 * This file is also compiled as C (tests/test_rng.c checks uniformity and the independence of
 * sibling streams): everything outside the VKRT_GLSL block is plain C and GLSL at once.
 */
#ifndef VKRT_RNG_GLSL
#define VKRT_RNG_GLSL

uint pcg_hash(uint v)
{
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

/* The seed of child k of a ray whose stream is at parent: an xorshift-multiply finaliser
 * (Wellons' "lowbias32") keyed by k, then PCG, so it shares no structure with rng_next's chain. */
uint rng_child_seed(uint parent, uint k)
{
    uint x = parent ^ ((k + 1u) * 0x9E3779B9u);
    x ^= x >> 16u;
    x *= 0x7FEB352Du;
    x ^= x >> 15u;
    x *= 0x846CA68Bu;
    x ^= x >> 16u;
    return pcg_hash(x);
}

/* A float in [0, 1) from a 32-bit state: the top 24 bits, so 1.0 never occurs. */
float rng_float(uint state)
{
    /* uint to float is implicit in GLSL and C alike, and exact for 24 bits. */
    return (state >> 8u) * (1.0 / 16777216.0);
}

#ifdef VKRT_GLSL
/* Advances state and returns a float uniform in [0, 1). */
float rng_next(inout uint state)
{
    state = pcg_hash(state);
    return rng_float(state);
}
#endif

#endif
