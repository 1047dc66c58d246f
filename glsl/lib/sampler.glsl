/*
 * sampler.glsl: the path tracer's stratified random numbers, a padded, hash-based Owen-scrambled
 * Sobol sampler (Burley, "Practical Hash-based Owen Scrambling", JCGT 9(4), 2020; pbrt-v4's
 * PaddedSobolSampler is the same idea with a permutation of the sample index instead).
 *
 * The numbers of a path come in pairs of dimensions (2k, 2k + 1). Pair k of sample i of a pixel
 * is the point of the first two Sobol dimensions (van der Corput and its Pascal-matrix partner,
 * a (0,2)-sequence) at index i shuffled by a nested-uniform scramble keyed by (pixel, frame, k),
 * each coordinate then Owen-scrambled with a key of its own. The top m bits of both Sobol
 * coordinates depend only on the low m bits of the index, and the shuffle permutes those among
 * themselves, so the first 2^m samples of a pixel are a (0,m,2)-net in every pair (one point in
 * every elementary interval of area 2^-m), and each coordinate has one point in each of the 2^m
 * strata; Owen scrambling keeps both properties. Different pairs get independent shuffles, so
 * pairs are not correlated with each other ("padding"), and nothing needs the number of samples.
 *
 * Stateless: a number is a function of (pixel, sample index, frame seed, dimension), so any
 * kernel can draw any dimension of a ray without a stored generator state.
 *
 * The scramble is Laine and Karras's bit-reversed formulation of Owen scrambling with Vegdahl's
 * better hash ("Building a Better LK Hash", 2021; pbrt-v4's FastOwenScrambler): in the reversed
 * domain, a digit may only be flipped by a function of the digits below it, and x ^= x * even,
 * x += c and x *= odd each do exactly that, so every step is a bijection and a nested scramble.
 *
 * Also compiled as C (tests/test_sampler.c checks stratification, the nets and the bijection):
 * everything outside the VKRT_GLSL block is plain C and GLSL at once.
 */
#ifndef VKRT_SAMPLER_GLSL
#define VKRT_SAMPLER_GLSL

#include "rng.glsl"

/* Where each depth's numbers go: depth d owns dimensions [d * SAMPLER_DEPTH_DIMS, + DEPTH_DIMS),
 * and within them every use has its own (pairs start at even dimensions, so that each 2D use is
 * one stratified pair). "Depth d" is the ray of depth d and the vertex its hit makes. */
#define SAMPLER_DIM_PIXEL 0u            /* 2D: the camera ray's jitter in its pixel (depth 0) */
#define SAMPLER_DIM_EMITTER_POINT 2u    /* 2D: the point on the emissive triangle, NEE */
#define SAMPLER_DIM_EMITTER_CHOICE 4u   /* 1D: which emissive triangle (the alias table), NEE */
#define SAMPLER_DIM_ROULETTE 5u         /* 1D: Russian roulette */
#define SAMPLER_DIM_ENVIRONMENT 6u      /* 2D: the environment's light sample, NEE */
#define SAMPLER_DIM_BSDF 8u             /* the material's random() calls, in order */
#define SAMPLER_BSDF_DIMS 8u            /* past these, random() falls back to the hash stream */
#define SAMPLER_DIM_LENS 16u            /* 2D: the point on the thin lens (depth 0) */
#define SAMPLER_DEPTH_DIMS 18u

/* x with its 32 bits in reverse order: GLSL's bitfieldReverse (one instruction on GPUs), written
 * out for C. */
uint sampler_reverse_bits(uint x)
{
#ifdef VKRT_GLSL
    return bitfieldReverse(x);
#else
    x = ((x >> 1u) & 0x55555555u) | ((x & 0x55555555u) << 1u);
    x = ((x >> 2u) & 0x33333333u) | ((x & 0x33333333u) << 2u);
    x = ((x >> 4u) & 0x0F0F0F0Fu) | ((x & 0x0F0F0F0Fu) << 4u);
    x = ((x >> 8u) & 0x00FF00FFu) | ((x & 0x00FF00FFu) << 8u);
    return (x >> 16u) | (x << 16u);
#endif
}

/* The nested-uniform (Owen) scramble of the 32-bit fraction x under key seed: bit b (counting
 * from the top) is flipped by a hash of seed and the bits above it. A bijection on 32-bit values
 * that maps every dyadic interval [j 2^-m, (j + 1) 2^-m) onto another. */
uint sampler_owen(uint x, uint seed)
{
    x = sampler_reverse_bits(x);
    x ^= x * 0x3D20ADEAu;
    x += seed;
    x *= (seed >> 16u) | 1u;
    x ^= x * 0x05526C56u;
    x ^= x * 0x53A22864u;
    return sampler_reverse_bits(x);
}

/* Sobol dimension 1 at index, a 32-bit fraction: direction numbers v_0 = 1/2,
 * v_{j+1} = v_j ^ (v_j >> 1) (the Pascal matrix mod 2). Dimension 0 is sampler_reverse_bits. */
uint sampler_sobol1(uint index)
{
    uint x = 0u, v = 0x80000000u;
    for (; index != 0u; index >>= 1u) {
        if ((index & 1u) != 0u)
            x ^= v;
        v ^= v >> 1u;
    }
    return x;
}

/* The key of dimension pair `pair` of a pixel in a frame: the index shuffle's; coordinate c of
 * the pair is scrambled with rng_child_seed(key, c). */
uint sampler_pair_key(uint pixel, uint frame_seed, uint pair)
{
    return pcg_hash(pair ^ pcg_hash(pixel ^ pcg_hash(frame_seed ^ 0x5B1D7A93u)));
}

/* Coordinate c (0 or 1) of the pair keyed by key, for sample `index`, as a 32-bit fraction. */
uint sampler_coordinate(uint key, uint index, uint c)
{
    uint shuffled = sampler_owen(index, key);
    uint x = c == 0u ? sampler_reverse_bits(shuffled) : sampler_sobol1(shuffled);
    return sampler_owen(x, rng_child_seed(key, c));
}

/* Dimension `dimension` of sample `index` of a pixel in a frame, as a 32-bit fraction (take
 * rng_float of it for a float in [0, 1)). */
uint sampler_bits(uint pixel, uint frame_seed, uint index, uint dimension)
{
    return sampler_coordinate(sampler_pair_key(pixel, frame_seed, dimension >> 1u), index,
                              dimension & 1u);
}

#ifdef VKRT_GLSL
#include "ray_record.glsl"

/* Dimension `dimension` of ray's depth block (its pixel, sample and depth), in [0, 1). */
float sampler_1d(Ray ray, uint frame_seed, uint dimension)
{
    return rng_float(sampler_bits(ray_pixel(ray), frame_seed, ray_sample(ray),
                                  ray_depth(ray) * SAMPLER_DEPTH_DIMS + dimension));
}

/* The pair at the even `dimension` of the ray's depth block: one stratified 2D point. */
vec2 sampler_2d(Ray ray, uint frame_seed, uint dimension)
{
    uint key = sampler_pair_key(ray_pixel(ray), frame_seed,
                                (ray_depth(ray) * SAMPLER_DEPTH_DIMS + dimension) >> 1u);
    uint index = ray_sample(ray);
    return vec2(rng_float(sampler_coordinate(key, index, 0u)),
                rng_float(sampler_coordinate(key, index, 1u)));
}
#endif

#endif
