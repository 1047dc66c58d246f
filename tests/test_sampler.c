/*
 * test_sampler.c: the path tracer's sampler, glsl/lib/sampler.glsl, compiled here as C.
 *
 * What the sampler promises (its header comment says why it holds), checked exactly for
 * N = 2^m samples, m = 0..12, and several (pixel, frame, dimension) keys, on the floats the
 * kernels see (rng_float of the bits):
 *   1. stratified: each coordinate has exactly one sample in each of the N strata of [0, 1);
 *   2. a (0,m,2)-net in each pair of dimensions (2k, 2k + 1): exactly one sample in every
 *      elementary interval [a 2^-i, (a + 1) 2^-i) x [b 2^-(m-i), (b + 1) 2^-(m-i)), every i;
 *   3. the scramble is a bijection on 2^m points: it permutes the dyadic points j 2^-m among
 *      the strata, and it shuffles sample indices 0 .. 2^m - 1 onto one aligned block of 2^m
 *      indices (which is why 1 and 2 hold for the first N samples of a pixel);
 *   4. different keys give different points: two pixels, two frames, two pairs of dimensions
 *      share no point, and dimensions of different pairs are independent (chi-square of their
 *      joint 8 x 8 histogram under 103.44, the 0.999 quantile with 63 degrees of freedom, which
 *      tests/test_rng.c computes).
 * Each check runs on the sampler and must pass, and on a deliberately broken variant (no
 * scrambling, a hash that is not nested, Sobol's dimension 0 used twice) and must fail there.
 */
#include <setjmp.h> /* cmocka needs these before its header */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

/* sampler.glsl is written to compile as C as well as GLSL; GLSL's uint is C's uint32_t. */
typedef uint32_t uint;
#include <math.h>

#include "../glsl/lib/sampler.glsl"
#include "../glsl/lib/mis.glsl"

enum {
    MAX_M = 12,      /* up to 4096 samples a pixel */
    KEYS = 6,        /* (pixel, frame, dimension) triples per check */
    JOINT_M = 12,    /* the independence check: 4096 samples, 64 expected per cell */
    JOINT_GRID = 8,
};

static const double chi2_0999_dof63 = 103.44;

/* A sampler under test: dimension `dimension` of sample `index` of a pixel in a frame. */
typedef uint (*sampler_fn)(uint pixel, uint frame, uint index, uint dimension);

/* Keys spread over pixels, frames and pairs of the sampler's depth blocks (even dimensions: the
 * first of a pair). */
static const uint keys[KEYS][3] = {
    {0, 0, 0}, {1, 0, 0}, {12345, 7, SAMPLER_DIM_BSDF}, {511 * 512 + 3, 0, SAMPLER_DIM_EMITTER_POINT},
    {77, 3, SAMPLER_DEPTH_DIMS + SAMPLER_DIM_ENVIRONMENT}, {9, 1, 15 * SAMPLER_DEPTH_DIMS + 4},
};

/* The stratum of [0, 1) in 2^bits equal parts that a kernel's float of x falls in. */
static uint stratum(uint x, int bits)
{
    return bits == 0 ? 0 : (uint)(rng_float(x) * (float)(1u << bits));
}

static int compare_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

/* ---- The broken variants ---------------------------------------------------------------- */

/* No scrambling at all: plain Sobol, the same points in every pixel and every pair. */
static uint unscrambled(uint pixel, uint frame, uint index, uint dimension)
{
    (void)pixel, (void)frame;
    return (dimension & 1u) == 0u ? sampler_reverse_bits(index) : sampler_sobol1(index);
}

/* A hash in place of the nested scramble: random, but it forgets the strata. */
static uint hashed(uint pixel, uint frame, uint index, uint dimension)
{
    uint key = sampler_pair_key(pixel, frame, dimension >> 1u);
    uint x = (dimension & 1u) == 0u ? sampler_reverse_bits(index) : sampler_sobol1(index);
    return pcg_hash(x ^ rng_child_seed(key, dimension & 1u));
}

/* Sobol's dimension 0 for both coordinates, each Owen-scrambled: stratified along each axis, but
 * the second coordinate is a function of the first, so the pair is no net. */
static uint same_dimension(uint pixel, uint frame, uint index, uint dimension)
{
    uint key = sampler_pair_key(pixel, frame, dimension >> 1u);
    uint shuffled = sampler_owen(index, key);
    return sampler_owen(sampler_reverse_bits(shuffled), rng_child_seed(key, dimension & 1u));
}

/* ---- The checks -------------------------------------------------------------------------- */

/* Whether every coordinate of the first 2^m samples, for every key and m <= MAX_M, has exactly
 * one sample in each of the 2^m strata. */
static bool stratified(sampler_fn f)
{
    static uint8_t seen[1u << MAX_M];
    for (int k = 0; k < KEYS; ++k)
        for (uint c = 0; c < 2; ++c)
            for (int m = 0; m <= MAX_M; ++m) {
                uint n = 1u << m;
                memset(seen, 0, n);
                for (uint i = 0; i < n; ++i) {
                    uint s = stratum(f(keys[k][0], keys[k][1], i, keys[k][2] + c), m);
                    if (seen[s]++)
                        return false;
                }
            }
    return true;
}

/* Whether the first 2^m samples of every key's pair are a (0,m,2)-net, for m <= MAX_M. */
static bool nets(sampler_fn f)
{
    static uint8_t seen[1u << MAX_M];
    static uint x[1u << MAX_M], y[1u << MAX_M];
    for (int k = 0; k < KEYS; ++k)
        for (int m = 0; m <= MAX_M; ++m) {
            uint n = 1u << m;
            for (uint i = 0; i < n; ++i) {
                x[i] = f(keys[k][0], keys[k][1], i, keys[k][2]);
                y[i] = f(keys[k][0], keys[k][1], i, keys[k][2] + 1u);
            }
            for (int a = 0; a <= m; ++a) {
                memset(seen, 0, n);
                for (uint i = 0; i < n; ++i) {
                    uint cell = (stratum(x[i], a) << (m - a)) | stratum(y[i], m - a);
                    if (seen[cell]++)
                        return false;
                }
            }
        }
    return true;
}

/* The first 2^MAX_M points of a key's pair, each as the kernels' two 24-bit floats in one word,
 * sorted. */
static void sorted_points(sampler_fn f, const uint key[3], uint64_t *points)
{
    for (uint i = 0; i < (1u << MAX_M); ++i)
        points[i] = (uint64_t)(f(key[0], key[1], i, key[2]) >> 8) << 24 |
                    f(key[0], key[1], i, key[2] + 1u) >> 8;
    qsort(points, 1u << MAX_M, sizeof *points, compare_u64);
}

/* Whether the first 2^MAX_M samples of two keys share no 2D point: unrelated sequences share one
 * by chance with odds of about 2^24 * 2^-48 in all. */
static bool keys_differ(sampler_fn f, const uint a[3], const uint b[3])
{
    static uint64_t pa[1u << MAX_M], pb[1u << MAX_M];
    sorted_points(f, a, pa);
    sorted_points(f, b, pb);
    for (uint i = 0, j = 0; i < (1u << MAX_M) && j < (1u << MAX_M);) {
        if (pa[i] == pb[j])
            return false;
        if (pa[i] < pb[j])
            ++i;
        else
            ++j;
    }
    return true;
}

/* Chi-square of the joint histogram of dimension d0 against dimension d1 of one pixel, over the
 * first 2^JOINT_M samples, in JOINT_GRID x JOINT_GRID cells. */
static double joint_chi2(sampler_fn f, uint pixel, uint d0, uint d1)
{
    uint32_t counts[JOINT_GRID * JOINT_GRID] = {0};
    uint n = 1u << JOINT_M;
    for (uint i = 0; i < n; ++i) {
        uint cx = (uint)(rng_float(f(pixel, 0, i, d0)) * JOINT_GRID);
        uint cy = (uint)(rng_float(f(pixel, 0, i, d1)) * JOINT_GRID);
        ++counts[cy * JOINT_GRID + cx];
    }
    double expected = (double)n / (JOINT_GRID * JOINT_GRID), chi2 = 0;
    for (int c = 0; c < JOINT_GRID * JOINT_GRID; ++c)
        chi2 += (counts[c] - expected) * (counts[c] - expected) / expected;
    return chi2;
}

/* ---- The tests ----------------------------------------------------------------------------- */

static void test_coordinates_stratified(void **state)
{
    (void)state;
    assert_true(stratified(sampler_bits));
    assert_false(stratified(hashed));
}

static void test_pairs_are_nets(void **state)
{
    (void)state;
    assert_true(nets(sampler_bits));
    assert_true(nets(unscrambled)); /* what the scrambles must keep */
    assert_false(nets(same_dimension));
    assert_false(nets(hashed));
}

/* The scramble of the 2^m dyadic points j 2^-m permutes them among the 2^m strata; the shuffle of
 * indices 0 .. 2^m - 1 is a permutation of one aligned block of 2^m indices. */
static void test_scramble_is_a_bijection(void **state)
{
    (void)state;
    static uint8_t seen[1u << MAX_M];
    const uint seeds[] = {0u, 1u, 0x9E3779B9u, 0xFFFFFFFFu, sampler_pair_key(5, 2, 9)};
    for (size_t k = 0; k < sizeof seeds / sizeof *seeds; ++k)
        for (int m = 1; m <= MAX_M; ++m) {
            uint n = 1u << m;
            memset(seen, 0, n);
            for (uint j = 0; j < n; ++j) {
                uint s = sampler_owen(j << (32 - m), seeds[k]) >> (32 - m);
                assert_int_equal(seen[s]++, 0);
            }
            memset(seen, 0, n);
            uint block = sampler_owen(0, seeds[k]) >> m;
            for (uint i = 0; i < n; ++i) {
                uint shuffled = sampler_owen(i, seeds[k]);
                assert_int_equal(shuffled >> m, block);
                assert_int_equal(seen[shuffled & (n - 1u)]++, 0);
            }
        }
    /* A hash in its place is no bijection on the strata. */
    bool collided = false;
    memset(seen, 0, 1u << MAX_M);
    for (uint j = 0; j < (1u << MAX_M); ++j)
        collided |= seen[pcg_hash(j << (32 - MAX_M)) >> (32 - MAX_M)]++ != 0;
    assert_true(collided);
}

static void test_keys_give_different_points(void **state)
{
    (void)state;
    const uint base[3] = {1000, 0, 0};
    const uint other_pixel[3] = {1001, 0, 0};
    const uint other_frame[3] = {1000, 1, 0};
    const uint other_pair[3] = {1000, 0, 2};
    const uint other_depth[3] = {1000, 0, SAMPLER_DEPTH_DIMS};
    assert_true(keys_differ(sampler_bits, base, other_pixel));
    assert_true(keys_differ(sampler_bits, base, other_frame));
    assert_true(keys_differ(sampler_bits, base, other_pair));
    assert_true(keys_differ(sampler_bits, base, other_depth));
    assert_false(keys_differ(unscrambled, base, other_pixel));
}

/* Dimensions of different pairs come from independent shuffles: no joint structure, while the
 * two of one pair are a net (far too even for chi-square to call them independent draws). */
static void test_pairs_independent(void **state)
{
    (void)state;
    for (uint pixel = 0; pixel < 4; ++pixel) {
        assert_true(joint_chi2(sampler_bits, pixel, 0, 2) < chi2_0999_dof63);
        assert_true(joint_chi2(sampler_bits, pixel, 1, SAMPLER_DIM_BSDF) < chi2_0999_dof63);
        assert_true(joint_chi2(sampler_bits, pixel, SAMPLER_DIM_ROULETTE,
                               SAMPLER_DEPTH_DIMS + SAMPLER_DIM_ROULETTE) < chi2_0999_dof63);
    }
    /* The joint histogram of a pair is exactly flat: chi-square 0. */
    assert_true(joint_chi2(sampler_bits, 0, 0, 1) == 0.0);
    /* Unscrambled, every pair is the same sequence: dimension 0 against 2 is a diagonal. */
    assert_false(joint_chi2(unscrambled, 0, 0, 2) < chi2_0999_dof63);
}

/* The power heuristic of lib/mis.glsl, at its limits: always in [0, 1], never NaN, 1 against a
 * pdf of 0 and 0 for one; a pdf so large that its square is infinite (an emitter seen edge-on)
 * takes all the weight, as a^2 / (a^2 + b^2) tends to, instead of inf / inf. */
static void test_power_heuristic_limits(void **state)
{
    (void)state;
    const struct {
        float a, b, want;
    } cases[] = {
        {1, 1, 0.5f},         {2, 1, 0.8f},         {1, 2, 0.2f},         {1e20f, 1, 1},
        {1, 1e20f, 0},        {INFINITY, 1, 1},     {1, INFINITY, 0},     {INFINITY, INFINITY, 0.5f},
        {0, 1, 0},            {1, 0, 1},            {NAN, 1, 0},          {1e-30f, 1e-30f, 0.5f},
        {3e38f, 3e38f, 0.5f},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        float w = power_heuristic(cases[i].a, cases[i].b);
        if (!(fabsf(w - cases[i].want) < 1e-6f))
            fail_msg("power_heuristic(%g, %g) = %g, not %g", cases[i].a, cases[i].b, w,
                     cases[i].want);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_coordinates_stratified),
        cmocka_unit_test(test_pairs_are_nets),
        cmocka_unit_test(test_scramble_is_a_bijection),
        cmocka_unit_test(test_keys_give_different_points),
        cmocka_unit_test(test_pairs_independent),
        cmocka_unit_test(test_power_heuristic_limits),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
