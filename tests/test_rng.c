/*
 * test_rng.c: statistical tests of glsl/lib/rng.glsl, compiled here as C.
 *
 * The kernels' random numbers decide where camera rays are jittered and which way diffuse and
 * glass rays go, so a flaw shows as structure in the image: bands from a non-uniform stream,
 * or correlated noise where sibling rays (the reflection and refraction of one glass hit, say)
 * draw related numbers. These tests check, with fixed seeds so that they are deterministic:
 *   1. uniformity, chi-square over 64 bins: along one stream, and for the first draw of a
 *      million camera rays seeded from consecutive pixel indices as raygen.comp seeds them;
 *   2. independence of streams, Pearson correlation of their i-th draws: sibling children
 *      (k = 0 and 1 of one parent), parent and child, and the children of parent states s and
 *      s + 1 (states that differ in one bit are what a weak hash maps to related outputs);
 *   3. independence of successive draws, chi-square over an 8 x 8 grid of (draw 2j, draw 2j+1).
 * Thresholds: the 0.999 quantile of chi-square with 63 degrees of freedom (103.44; computed
 * below), and 4 / sqrt(n) for a correlation over n pairs (4 standard deviations of the sample
 * correlation of independent variables, which is about normal with variance 1/n).
 * A test that cannot fail proves nothing, so the same statistics run on two deliberately bad
 * generators and must exceed the thresholds there.
 */
#include <setjmp.h> /* cmocka needs these before its header */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <string.h>

/* rng.glsl is written to compile as C as well as GLSL; GLSL's uint is C's uint32_t. */
typedef uint32_t uint;
#include "../glsl/lib/rng.glsl"

enum {
    BINS = 64,            /* 1D: chi-square with 63 degrees of freedom */
    GRID = 8,             /* 2D: 8 x 8 cells, again 63 degrees of freedom */
    DRAWS = 1000000,      /* per uniformity test: 15625 expected per bin */
    PARENTS = 12500,      /* correlation tests: 12500 parents x 8 draws = 1e5 pairs */
    DRAWS_PER_STREAM = 8, /* a path rarely draws more per ray */
};

/* A generator as the renderer uses one: how a stream advances (the draw is rng_float of the new
 * state, as rng_next does), how a child stream is seeded, and how raygen seeds a camera ray. */
typedef struct generator {
    const char *name;
    uint (*advance)(uint state);
    uint (*child)(uint parent, uint k);
    uint (*camera)(uint pixel, uint sample, uint frame);
} generator;

static float draw(const generator *g, uint *state)
{
    *state = g->advance(*state);
    return rng_float(*state);
}

/* ---------------------------------------------------------------------------------------------
 * The generators
 * ------------------------------------------------------------------------------------------- */

/* raygen.comp's seed of sample `sample` of pixel `pixel` in frame `frame`. */
static uint pcg_camera(uint pixel, uint sample, uint frame)
{
    return pcg_hash(pixel ^ pcg_hash(sample ^ pcg_hash(frame)));
}

static const generator pcg = {"pcg", pcg_hash, rng_child_seed, pcg_camera};

/* Bad generator 1, a counter: uniform over its period but not at all random. Every statistic
 * must catch it. */
static uint counter_advance(uint state)
{
    return state + 1u;
}

static uint counter_child(uint parent, uint k)
{
    return parent + k + 1u;
}

static uint counter_camera(uint pixel, uint sample, uint frame)
{
    (void)sample;
    (void)frame;
    return pixel;
}

static const generator counter = {"counter", counter_advance, counter_child, counter_camera};

/* Bad generator 2, PCG's own LCG step without its output permutation, children seeded with
 * consecutive states. Its top bits are uniform, so the 1D tests pass it; but streams from nearby
 * seeds stay a constant distance apart, the mistake rng_child_seed's second hash avoids. The
 * correlation tests must catch it. */
static uint lcg_advance(uint state)
{
    return state * 747796405u + 2891336453u;
}

static const generator lcg = {"lcg", lcg_advance, counter_child, counter_camera};

/* ---------------------------------------------------------------------------------------------
 * Statistics
 * ------------------------------------------------------------------------------------------- */

/* The regularised lower incomplete gamma function P(a, x), by its power series (Numerical
 * Recipes, gser), which converges for every x but slowly far past a; here x is near a. */
static double gamma_p(double a, double x)
{
    double term = 1.0 / a, sum = term;
    for (int n = 1; n < 10000 && term > sum * 1e-16; n++) {
        term *= x / (a + n);
        sum += term;
    }
    return sum * exp(-x + a * log(x) - lgamma(a));
}

/* The p-quantile of chi-square with dof degrees of freedom, by bisection on its CDF
 * P(dof / 2, x / 2). */
static double chi2_quantile(int dof, double p)
{
    double lo = 0.0, hi = 10.0 * dof + 100.0;
    for (int i = 0; i < 100; i++) {
        double mid = 0.5 * (lo + hi);
        if (gamma_p(0.5 * dof, 0.5 * mid) < p)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

static double chi_square(const uint32_t *counts, int cells, double total)
{
    double expected = total / cells, sum = 0.0;
    for (int i = 0; i < cells; i++) {
        double d = counts[i] - expected;
        sum += d * d / expected;
    }
    return sum;
}

static int bin(float x, int bins)
{
    int b = (int)(x * (float)bins);
    return b < bins ? b : bins - 1; /* x < 1 always; this only guards the test itself */
}

/* 1D chi-square of DRAWS draws along one stream. */
static double chi2_stream(const generator *g, uint seed)
{
    uint32_t counts[BINS] = {0};
    uint state = seed;
    for (int i = 0; i < DRAWS; i++)
        counts[bin(draw(g, &state), BINS)]++;
    return chi_square(counts, BINS, DRAWS);
}

/* 1D chi-square of the first draw of DRAWS camera rays of consecutive pixels. */
static double chi2_camera_rays(const generator *g, uint sample, uint frame)
{
    uint32_t counts[BINS] = {0};
    for (uint pixel = 0; pixel < DRAWS; pixel++) {
        uint state = g->camera(pixel, sample, frame);
        counts[bin(draw(g, &state), BINS)]++;
    }
    return chi_square(counts, BINS, DRAWS);
}

/* 2D chi-square of DRAWS / 2 non-overlapping pairs (draw 2j, draw 2j+1) of one stream on a
 * GRID x GRID grid. Overlapping pairs would not be independent, and their statistic would not
 * follow chi-square with 63 degrees of freedom. */
static double chi2_pairs(const generator *g, uint seed)
{
    uint32_t counts[GRID * GRID] = {0};
    uint state = seed;
    for (int i = 0; i < DRAWS / 2; i++) {
        int x = bin(draw(g, &state), GRID);
        int y = bin(draw(g, &state), GRID);
        counts[y * GRID + x]++;
    }
    return chi_square(counts, GRID * GRID, DRAWS / 2);
}

typedef struct pearson {
    double n, sx, sy, sxx, syy, sxy;
} pearson;

static void pearson_add(pearson *p, double x, double y)
{
    p->n += 1.0;
    p->sx += x;
    p->sy += y;
    p->sxx += x * x;
    p->syy += y * y;
    p->sxy += x * y;
}

static double pearson_r(const pearson *p)
{
    double cov = p->sxy - p->sx * p->sy / p->n;
    double vx = p->sxx - p->sx * p->sx / p->n, vy = p->syy - p->sy * p->sy / p->n;
    return cov / sqrt(vx * vy);
}

typedef enum pairing {
    SIBLINGS,        /* child 0 and child 1 of parent s */
    PARENT_CHILD,    /* parent s itself and its child 0 */
    NEIGHBOUR_CHILD, /* child 0 of parent s and child 0 of parent s + 1 */
} pairing;

/* Correlation of the i-th draws of two streams, over PARENTS parents (the camera rays of
 * consecutive pixels) and DRAWS_PER_STREAM draws each. */
static double correlation(const generator *g, pairing how)
{
    pearson p;
    memset(&p, 0, sizeof p);
    for (uint pixel = 0; pixel < PARENTS; pixel++) {
        uint parent = g->camera(pixel, 0u, 0u);
        uint a = 0, b = 0;
        switch (how) {
        case SIBLINGS:
            a = g->child(parent, 0u);
            b = g->child(parent, 1u);
            break;
        case PARENT_CHILD:
            a = parent;
            b = g->child(parent, 0u);
            break;
        case NEIGHBOUR_CHILD:
            a = g->child(parent, 0u);
            b = g->child(parent + 1u, 0u);
            break;
        }
        for (int i = 0; i < DRAWS_PER_STREAM; i++) {
            float x = draw(g, &a);
            float y = draw(g, &b);
            pearson_add(&p, x, y);
        }
    }
    return pearson_r(&p);
}

static const double pairs_n = (double)PARENTS * DRAWS_PER_STREAM;

/* ---------------------------------------------------------------------------------------------
 * Tests
 * ------------------------------------------------------------------------------------------- */

static double chi2_limit(void)
{
    return chi2_quantile(BINS - 1, 0.999);
}

static void test_chi2_quantile(void **state)
{
    (void)state;
    /* Tabulated values (e.g. NIST/SEMATECH e-Handbook, table 1.3.6.7.4; scipy chi2.ppf). */
    assert_float_equal(chi2_quantile(63, 0.999), 103.442, 0.001);
    assert_float_equal(chi2_quantile(10, 0.999), 29.588, 0.001);
    assert_float_equal(chi2_quantile(1, 0.95), 3.841, 0.001);
}

static void test_uniform_along_a_stream(void **state)
{
    (void)state;
    static const uint seeds[] = {0u, 1u, 0x12345678u, 0xFFFFFFFFu};
    for (size_t i = 0; i < sizeof seeds / sizeof seeds[0]; i++) {
        double chi2 = chi2_stream(&pcg, seeds[i]);
        print_message("stream from seed 0x%08X: chi-square %.1f (limit %.1f)\n", seeds[i], chi2,
                      chi2_limit());
        assert_true(chi2 < chi2_limit());
    }
}

static void test_uniform_across_camera_rays(void **state)
{
    (void)state;
    /* The first draw of each ray, as raygen's jitter takes it; then another sample and frame. */
    static const uint runs[][2] = {{0u, 0u}, {1u, 0u}, {0u, 1u}, {7u, 1234u}};
    for (size_t i = 0; i < sizeof runs / sizeof runs[0]; i++) {
        double chi2 = chi2_camera_rays(&pcg, runs[i][0], runs[i][1]);
        print_message("first draws of 1e6 pixels, sample %u frame %u: chi-square %.1f\n",
                      runs[i][0], runs[i][1], chi2);
        assert_true(chi2 < chi2_limit());
    }
}

static void test_streams_uncorrelated(void **state)
{
    (void)state;
    static const char *const names[] = {"siblings", "parent and child", "children of s, s+1"};
    double limit = 4.0 / sqrt(pairs_n);
    for (int how = SIBLINGS; how <= NEIGHBOUR_CHILD; how++) {
        double r = correlation(&pcg, (pairing)how);
        print_message("%s: correlation %+.5f over %.0f pairs (limit %.5f)\n", names[how], r,
                      pairs_n, limit);
        assert_true(fabs(r) < limit);
    }
}

static void test_successive_draws_independent(void **state)
{
    (void)state;
    static const uint seeds[] = {0u, 42u, 0xDEADBEEFu};
    for (size_t i = 0; i < sizeof seeds / sizeof seeds[0]; i++) {
        double chi2 = chi2_pairs(&pcg, seeds[i]);
        print_message("pairs from seed 0x%08X: 8x8 chi-square %.1f\n", seeds[i], chi2);
        assert_true(chi2 < chi2_limit());
    }
}

/* The statistics above, run on the bad generators: each must exceed its threshold. */
static void test_bad_generators_fail(void **state)
{
    (void)state;
    double chi2_max = chi2_limit(), r_max = 4.0 / sqrt(pairs_n);

    double stream = chi2_stream(&counter, 0x12345678u);
    double camera = chi2_camera_rays(&counter, 0u, 0u);
    double grid = chi2_pairs(&counter, 0x12345678u);
    print_message("counter: stream %.3g, camera rays %.3g, pairs %.3g\n", stream, camera, grid);
    assert_true(stream > chi2_max);
    assert_true(camera > chi2_max);
    assert_true(grid > chi2_max);
    for (int how = SIBLINGS; how <= NEIGHBOUR_CHILD; how++) {
        double r_counter = correlation(&counter, (pairing)how);
        double r_lcg = correlation(&lcg, (pairing)how);
        print_message("correlation %d: counter %+.3f, lcg %+.3f\n", how, r_counter, r_lcg);
        assert_true(fabs(r_counter) > r_max);
        assert_true(fabs(r_lcg) > r_max);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_chi2_quantile),
        cmocka_unit_test(test_uniform_along_a_stream),
        cmocka_unit_test(test_uniform_across_camera_rays),
        cmocka_unit_test(test_streams_uncorrelated),
        cmocka_unit_test(test_successive_draws_independent),
        cmocka_unit_test(test_bad_generators_fail),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
