/*
 * test_envmap.c: unit tests for src/scene/envmap.c: the environment map's reading, its sampling
 * distribution, and the CPU mirror of glsl/lib/envmap.glsl.
 *
 * The sampler is held against its definitions: directions round-trip through uv and land where
 * Mitsuba's envmap puts them; the density integrates to 1 over the sphere; a histogram of sampled
 * directions matches the density integrated over each bin; the density a sample comes with is the
 * density of its direction; every direction whose bilinear lookup is non-zero has a positive
 * density, however dim it is beside the sun; and the estimator of the map's integral, L / pdf, is
 * unbiased against a quadrature of the same bilinear lookup the kernels do (texture_sample).
 */
#define _POSIX_C_SOURCE 200809L

#include <setjmp.h> /* cmocka needs these before its header */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <openexr.h>
#include <stb_image.h>
#include <stb_image_write.h>

#include "../glsl/shared.h"
#include "gpu/shader.h"
#include "output/image_write.h"
#include "render/kernel_sources.h"
#include "scene/envmap.h"
#include "temp_dir.h"

#define PI 3.14159265358979323846

/* ---------------------------------------------------------------------------------------------
 * Helpers
 * ------------------------------------------------------------------------------------------- */

/* xorshift64*, so every run draws the same numbers. */
static uint64_t rng_state = 0x2545F4914F6CDD1Dull;
static double uniform(void)
{
    rng_state ^= rng_state >> 12;
    rng_state ^= rng_state << 25;
    rng_state ^= rng_state >> 27;
    return (double)((rng_state * 0x2545F4914F6CDD1Dull) >> 11) * 0x1.0p-53;
}

static float uniform_f(void)
{
    return fminf((float)uniform(), 0x1.fffffep-1f);
}

/* A map with structure: a dim gradient sky, a black band, and a small bright sun. */
static float *make_sky(uint32_t w, uint32_t h)
{
    float *rgb = malloc((size_t)w * h * 3 * sizeof *rgb);
    assert_non_null(rgb);
    for (uint32_t y = 0; y < h; y++) {
        for (uint32_t x = 0; x < w; x++) {
            float *p = rgb + ((size_t)y * w + x) * 3;
            float t = (float)y / (float)h;
            p[0] = 0.2f + 0.5f * t;
            p[1] = 0.3f + 0.2f * t;
            p[2] = 0.9f - 0.4f * t;
            if (y > h / 2 && y < h / 2 + h / 8) /* a black band below the horizon */
                p[0] = p[1] = p[2] = 0.0f;
            if (x == w / 3 && y == h / 4) /* the sun */
                p[0] = 5000.0f, p[1] = 4500.0f, p[2] = 4000.0f;
        }
    }
    return rgb;
}

static void build(const float *rgb, uint32_t w, uint32_t h, vkrt_envmap_distribution *d)
{
    vkrt_error err = {{0}};
    bool ok = vkrt_envmap_distribution_build(rgb, w, h, d, &err);
    if (!ok)
        print_error("unexpected failure: %s\n", err.msg);
    assert_true(ok);
}

static uint32_t wrap(int i, uint32_t n)
{
    int r = i % (int)n;
    return (uint32_t)(r < 0 ? r + (int)n : r);
}

/* envmap_radiance of glsl/lib/environment.glsl on float RGB, luminance only: bilinear, texel
 * centres at half-integers, v = 0 the bottom row, wrapping across and clamped down. */
static double lookup(const float *rgb, uint32_t w, uint32_t h, double u, double v)
{
    double px = (u - floor(u)) * w - 0.5;
    double tv = 1.0 - v;
    double py = (tv - floor(tv)) * h - 0.5;
    double x0 = floor(px), y0 = floor(py);
    double fx = px - x0, fy = py - y0;
    double c[2][2];
    for (int j = 0; j < 2; j++) {
        for (int i = 0; i < 2; i++) {
            int y = (int)y0 + j < 0 ? 0 : (int)y0 + j >= (int)h ? (int)h - 1 : (int)y0 + j;
            const float *p = rgb + ((size_t)y * w + wrap((int)x0 + i, w)) * 3;
            c[j][i] = 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
        }
    }
    double top = c[0][0] + (c[0][1] - c[0][0]) * fx;
    double bottom = c[1][0] + (c[1][1] - c[1][0]) * fx;
    return top + (bottom - top) * fy;
}

/* The length of [a, b] inside [lo, hi]. */
static double overlap(double a, double b, double lo, double hi)
{
    return fmax(0.0, fmin(b, hi) - fmax(a, lo));
}

static void assert_dir(const float d[3], float x, float y, float z)
{
    assert_float_equal(d[0], x, 1e-6);
    assert_float_equal(d[1], y, 1e-6);
    assert_float_equal(d[2], z, 1e-6);
}

/* ---------------------------------------------------------------------------------------------
 * The mapping
 * ------------------------------------------------------------------------------------------- */

/* Mitsuba's envmap: u = 0 looks down -z, a quarter across down +x, half across down +z; the top
 * row (v = 1 in texture uv) is +y. rotate turns the map about +y as to_world's rotate does. */
static void test_convention(void **state)
{
    (void)state;
    float d[3];
    vkrt_envmap_direction(0.0f, 0.5f, 0.0f, d);
    assert_dir(d, 0, 0, -1);
    vkrt_envmap_direction(0.25f, 0.5f, 0.0f, d);
    assert_dir(d, 1, 0, 0);
    vkrt_envmap_direction(0.5f, 0.5f, 0.0f, d);
    assert_dir(d, 0, 0, 1);
    vkrt_envmap_direction(0.75f, 0.5f, 0.0f, d);
    assert_dir(d, -1, 0, 0);
    vkrt_envmap_direction(0.3f, 1.0f, 0.0f, d);
    assert_dir(d, 0, 1, 0);
    vkrt_envmap_direction(0.3f, 0.0f, 0.0f, d);
    assert_dir(d, 0, -1, 0);
    /* Rotated by +90 degrees about +y: -z goes to -x, as R_y(90) does to the vector (0, 0, -1). */
    vkrt_envmap_direction(0.0f, 0.5f, (float)(PI / 2), d);
    assert_dir(d, -1, 0, 0);
    float uv[2];
    const float up[3] = {0, 1, 0};
    vkrt_envmap_uv(up, 0.0f, uv);
    assert_float_equal(uv[1], 1.0f, 0);
    const float minus_z[3] = {0, 0, -1};
    vkrt_envmap_uv(minus_z, 0.0f, uv);
    assert_float_equal(uv[0], 0.0f, 1e-7);
    assert_float_equal(uv[1], 0.5f, 1e-7);
}

static void test_round_trip(void **state)
{
    (void)state;
    const float rotations[] = {0.0f, 1.0f, -2.5f, (float)PI};
    for (int r = 0; r < 4; r++) {
        float rot = rotations[r];
        double worst_uv = 0, worst_dir = 0;
        for (int i = 0; i < 20000; i++) {
            float u = uniform_f(), v = 0.001f + 0.998f * uniform_f();
            float d[3], uv[2];
            vkrt_envmap_direction(u, v, rot, d);
            assert_float_equal(d[0] * d[0] + d[1] * d[1] + d[2] * d[2], 1.0f, 1e-5);
            vkrt_envmap_uv(d, rot, uv);
            double du = fabs(uv[0] - u);
            du = fmin(du, 1.0 - du); /* u wraps */
            worst_uv = fmax(worst_uv, fmax(du, fabs(uv[1] - v)));

            /* And from a direction: uniform on the sphere. */
            double z = 2 * uniform() - 1, a = 2 * PI * uniform(), s = sqrt(1 - z * z);
            float dir[3] = {(float)(s * cos(a)), (float)z, (float)(s * sin(a))}, back[3];
            vkrt_envmap_uv(dir, rot, uv);
            assert_true(uv[0] >= 0.0f && uv[0] <= 1.0f && uv[1] >= 0.0f && uv[1] <= 1.0f);
            vkrt_envmap_direction(uv[0], uv[1], rot, back);
            for (int k = 0; k < 3; k++)
                worst_dir = fmax(worst_dir, fabs(back[k] - dir[k]));
        }
        /* float trigonometry near the poles: a few ulps of theta */
        assert_true(worst_uv < 2e-4);
        assert_true(worst_dir < 2e-3);
    }
}

/* ---------------------------------------------------------------------------------------------
 * The distribution
 * ------------------------------------------------------------------------------------------- */

static void test_layout_and_cdfs(void **state)
{
    (void)state;
    uint32_t w = 37, h = 19;
    float *rgb = make_sky(w, h);
    vkrt_envmap_distribution d;
    build(rgb, w, h, &d);
    assert_int_equal(d.float_count, (h + 1) + (size_t)h * (w + 1));
    assert_int_equal(vkrt_envmap_distribution_floats(w, h), d.float_count);
    assert_true(d.weight_sum > 0);
    const float *cdfs[2] = {d.data, NULL};
    for (uint32_t y = 0; y <= h; y++) {
        const float *cdf = y == 0 ? cdfs[0] : d.data + (h + 1) + (size_t)(y - 1) * (w + 1);
        uint32_t n = y == 0 ? h : w;
        assert_float_equal(cdf[0], 0.0f, 0);
        assert_float_equal(cdf[n], 1.0f, 0);
        for (uint32_t i = 0; i < n; i++)
            assert_true(cdf[i] <= cdf[i + 1]);
    }

    LightInfo info;
    memset(&info, 0xAB, sizeof info);
    info.environment_pixels = 7;
    info.emitter_count = 3;
    vkrt_envmap_light_info(&d, 2.0f, 450.0f, &info);
    assert_int_equal(info.environment_width, w);
    assert_int_equal(info.environment_height, h);
    assert_float_equal(info.environment_scale, 2.0f, 0);
    assert_float_equal(info.environment_rotate, (float)(PI / 2), 1e-6);
    assert_float_equal(info.environment_integral, (float)d.weight_sum, 0);
    assert_int_equal(info.environment_sampled, 1);
    assert_int_equal(info.environment_pixels, 7); /* the caller's */
    assert_int_equal(info.emitter_count, 3);
    vkrt_envmap_light_info(&d, 0.0f, 0.0f, &info);
    assert_int_equal(info.environment_sampled, 0);
    vkrt_envmap_distribution_free(&d);
    vkrt_envmap_distribution_free(&d);
    vkrt_envmap_distribution_free(NULL);

    /* A black map: nothing to sample, and no NaN in the tables. */
    memset(rgb, 0, (size_t)w * h * 3 * sizeof *rgb);
    build(rgb, w, h, &d);
    assert_true(d.weight_sum == 0.0);
    for (size_t i = 0; i < d.float_count; i++)
        assert_true(isfinite(d.data[i]));
    vkrt_envmap_light_info(&d, 1.0f, 0.0f, &info);
    assert_int_equal(info.environment_sampled, 0);
    vkrt_envmap_distribution_free(&d);

    /* Sizes it refuses. */
    vkrt_error err = {{0}};
    memset(&d, 0xAB, sizeof d);
    assert_false(vkrt_envmap_distribution_build(rgb, 0, h, &d, &err));
    assert_non_null(strstr(err.msg, "a 0x19 map cannot be sampled"));
    assert_null(d.data);
    assert_false(vkrt_envmap_distribution_build(rgb, 16385, 1, &d, &err));
    free(rgb);
}

/* The density integrates to 1 over the sphere: a midpoint rule in (theta, phi) on a grid four
 * times finer than the texels (and so exact for a piecewise-constant density, up to float). */
static void test_pdf_integrates_to_one(void **state)
{
    (void)state;
    uint32_t w = 64, h = 32;
    float *rgb = make_sky(w, h);
    vkrt_envmap_distribution d;
    build(rgb, w, h, &d);
    const float rot = 0.7f;
    uint32_t nu = 4 * w, nv = 4 * h;
    double sum = 0.0;
    for (uint32_t j = 0; j < nv; j++) {
        double theta = PI * (j + 0.5) / nv;
        for (uint32_t i = 0; i < nu; i++) {
            double phi = 2 * PI * (i + 0.5) / nu;
            float dir[3] = {(float)(sin(phi) * sin(theta)), (float)cos(theta),
                            (float)(-cos(phi) * sin(theta))};
            sum += vkrt_envmap_pdf(d.data, w, h, rot, dir) * sin(theta) * (2 * PI / nu) * (PI / nv);
        }
    }
    assert_float_equal(sum, 1.0, 1e-4);

    vkrt_envmap_distribution_free(&d);
    free(rgb);
}

/* Sampled directions, binned in world (theta, phi) cells that do not line up with the texels,
 * against the density integrated over each cell; and each sample's density against the density
 * of its direction. */
static void test_histogram_and_sample_pdf(void **state)
{
    (void)state;
    uint32_t w = 48, h = 24;
    float *rgb = make_sky(w, h);
    vkrt_envmap_distribution d;
    build(rgb, w, h, &d);
    const float rot = -1.3f;
    enum { BT = 10, BP = 14, N = 2000000 };
    static double expected[BT][BP];
    static uint32_t count[BT][BP];
    memset(count, 0, sizeof count);
    /* The density is constant over each texel in uv, and a cell is a rectangle in uv too (world
     * phi = 2 pi u - rotate): the cell's probability is the texels' densities times their
     * overlaps with it, exactly. */
    for (int bt = 0; bt < BT; bt++) {
        for (int bp = 0; bp < BP; bp++) {
            double a = (double)bp / BP + rot / (2 * PI);
            a -= floor(a);
            double b = a + 1.0 / BP;
            double t0 = (double)bt / BT, t1 = (bt + 1.0) / BT;
            double sum = 0;
            for (uint32_t y = 0; y < h; y++) {
                double ot = overlap(t0, t1, (double)y / h, (y + 1.0) / h);
                if (ot <= 0)
                    continue;
                for (uint32_t x = 0; x < w; x++) {
                    double lo = (double)x / w, hi = (x + 1.0) / w;
                    double ou = overlap(a, b, lo, hi) + overlap(a - 1, b - 1, lo, hi);
                    if (ou <= 0)
                        continue;
                    sum += vkrt_envmap_pdf_uv(d.data, w, h, (float)((x + 0.5) / w),
                                              (float)(1.0 - (y + 0.5) / h)) *
                           ot * ou;
                }
            }
            expected[bt][bp] = sum * N;
        }
    }

    uint32_t uv_mismatch = 0, dir_mismatch = 0;
    for (int s = 0; s < N; s++) {
        float uv[2], pdf_uv, dir[3];
        vkrt_envmap_sample(d.data, w, h, uniform_f(), uniform_f(), uv, &pdf_uv);
        assert_true(pdf_uv > 0.0f);
        assert_true(uv[0] >= 0.0f && uv[0] < 1.0f && uv[1] > 0.0f && uv[1] <= 1.0f);
        /* The density the sampler returns is that of the texel it chose, to the bit, except
         * where float rounding of (x + fx) / W puts uv on the next texel's edge. */
        if (vkrt_envmap_pdf_uv(d.data, w, h, uv[0], uv[1]) != pdf_uv)
            uv_mismatch++;
        vkrt_envmap_direction(uv[0], uv[1], rot, dir);
        double sin_theta = sqrt((double)dir[0] * dir[0] + (double)dir[2] * dir[2]);
        double want = pdf_uv / (2 * PI * PI * sin_theta);
        double got = vkrt_envmap_pdf(d.data, w, h, rot, dir);
        if (fabs(got - want) > 1e-3 * want)
            dir_mismatch++;

        double theta = acos(fmin(fmax(dir[1], -1.0), 1.0));
        double phi = atan2(dir[0], -dir[2]);
        if (phi < 0)
            phi += 2 * PI;
        int bt = (int)(theta / PI * BT), bp = (int)(phi / (2 * PI) * BP);
        count[bt < BT ? bt : BT - 1][bp < BP ? bp : BP - 1]++;
    }
    assert_true(uv_mismatch <= N / 100000);
    /* Through trigonometry a sample near a texel edge may cross it. */
    assert_true(dir_mismatch <= N / 1000);

    double chi2 = 0;
    int cells = 0;
    for (int bt = 0; bt < BT; bt++) {
        for (int bp = 0; bp < BP; bp++) {
            double e = expected[bt][bp], c = count[bt][bp];
            if (e < 20) {
                assert_true(c <= 20 + 10 * e);
                continue;
            }
            chi2 += (c - e) * (c - e) / e;
            cells++;
            if (!(fabs(c - e) < 6 * sqrt(e)))
                print_error("cell %d %d: %g samples, %g expected\n", bt, bp, c, e);
            assert_true(fabs(c - e) < 6 * sqrt(e));
        }
    }
    /* Mean cells - 1, standard deviation sqrt(2 cells). */
    assert_true(cells > 100);
    assert_true(chi2 < cells + 6 * sqrt(2.0 * cells));
    vkrt_envmap_distribution_free(&d);
    free(rgb);
}

/* Wherever the bilinear lookup is non-zero, the density is positive: around a lone texel, across
 * the left/right seam and at the poles, and for a texel far dimmer than the sun beside
 * it, whose CDF step would round to zero in float. */
static void test_positive_where_lit(void **state)
{
    (void)state;
    uint32_t w = 16, h = 8;
    float *rgb = calloc((size_t)w * h * 3, sizeof *rgb);
    assert_non_null(rgb);
    rgb[(0 * w + 0) * 3 + 1] = 1.0f;     /* top-left corner: wraps across, clamps up */
    rgb[(5 * w + 9) * 3 + 0] = 65504.0f; /* the sun */
    rgb[(5 * w + 12) * 3 + 2] = 1e-30f;  /* a faint texel in the sun's row */
    rgb[(2 * w + 6) * 3 + 2] = 1e-35f;   /* a faint texel in a row of its own */
    vkrt_envmap_distribution d;
    build(rgb, w, h, &d);
    uint32_t lit = 0;
    for (uint32_t j = 0; j < 8 * h; j++) {
        for (uint32_t i = 0; i < 8 * w; i++) {
            double u = (i + 0.5) / (8 * w), v = (j + 0.5) / (8 * h);
            double l = lookup(rgb, w, h, u, v);
            float pdf = vkrt_envmap_pdf_uv(d.data, w, h, (float)u, (float)v);
            if (l > 0) {
                lit++;
                if (!(pdf > 0.0f))
                    print_error("uv %g %g: radiance %g, density 0\n", u, v, l);
                assert_true(pdf > 0.0f);
            }
        }
    }
    assert_true(lit > 4 * 64);
    /* Texels two away from every lit one have no weight, so nothing is wasted on them. */
    assert_true(vkrt_envmap_pdf_uv(d.data, w, h, 3.5f / w, 1.0f - 4.5f / h) == 0.0f);
    vkrt_envmap_distribution_free(&d);
    free(rgb);
}

/* The estimator of the map's integral over the sphere, mean of L / pdf over samples, against a
 * quadrature of the same bilinear lookup: the whole chain (weights, CDFs, sampling, uv, pdf) is
 * unbiased. */
static void test_estimator_unbiased(void **state)
{
    (void)state;
    uint32_t w = 40, h = 20;
    float *rgb = make_sky(w, h);
    vkrt_envmap_distribution d;
    build(rgb, w, h, &d);
    const float rot = 2.0f;

    /* Reference: integral of L sin(theta) dtheta dphi, fine midpoint rule. */
    double exact = 0;
    uint32_t nu = 16 * w, nv = 16 * h;
    for (uint32_t j = 0; j < nv; j++) {
        double theta = PI * (j + 0.5) / nv;
        for (uint32_t i = 0; i < nu; i++)
            exact += lookup(rgb, w, h, (i + 0.5) / nu, 1.0 - theta / PI) * sin(theta);
    }
    exact *= (2 * PI / nu) * (PI / nv);

    int n = 1000000;
    double sum = 0, sum2 = 0, uni = 0, uni2 = 0;
    for (int s = 0; s < n; s++) {
        float uv[2], pdf_uv, dir[3];
        vkrt_envmap_sample(d.data, w, h, uniform_f(), uniform_f(), uv, &pdf_uv);
        vkrt_envmap_direction(uv[0], uv[1], rot, dir);
        float pdf = vkrt_envmap_pdf(d.data, w, h, rot, dir);
        float back[2];
        vkrt_envmap_uv(dir, rot, back);
        double f = pdf > 0 ? lookup(rgb, w, h, back[0], back[1]) / pdf : 0.0;
        sum += f;
        sum2 += f * f;

        /* The same integral by uniform directions, for scale. */
        double z = 2 * uniform() - 1, a = 2 * PI * uniform(), r = sqrt(1 - z * z);
        float udir[3] = {(float)(r * cos(a)), (float)z, (float)(r * sin(a))};
        vkrt_envmap_uv(udir, rot, back);
        double g = lookup(rgb, w, h, back[0], back[1]) * 4 * PI;
        uni += g;
        uni2 += g * g;
    }
    double mean = sum / n;
    double sigma = sqrt((sum2 / n - mean * mean) / n);
    if (fabs(mean - exact) > 5 * sigma + 1e-4 * exact)
        print_error("estimate %g +- %g, quadrature %g\n", mean, sigma, exact);
    assert_true(fabs(mean - exact) <= 5 * sigma + 1e-4 * exact);
    /* Importance sampling pays: against uniform directions, the sun makes the difference. */
    double uni_mean = uni / n;
    double uni_sigma = sqrt((uni2 / n - uni_mean * uni_mean) / n);
    assert_true(fabs(uni_mean - exact) <= 5 * uni_sigma);
    assert_true(sigma < uni_sigma / 10);
    vkrt_envmap_distribution_free(&d);
    free(rgb);
}

/* ---------------------------------------------------------------------------------------------
 * Reading
 * ------------------------------------------------------------------------------------------- */

static void fill_pattern(float *rgb, uint32_t w, uint32_t h)
{
    for (uint32_t i = 0; i < w * h; i++) {
        rgb[3 * i + 0] = (float)(i % 7) * 0.25f;
        rgb[3 * i + 1] = (float)(i % 5) * 100.0f;
        rgb[3 * i + 2] = (float)(i / 3) * 0.5f;
    }
}

static void test_load_exr_scanline(void **state)
{
    temp_dir *fx = *state;
    uint32_t w = 23, h = 41; /* more than one chunk of 16 lines */
    float *rgb = malloc((size_t)w * h * 3 * sizeof *rgb);
    assert_non_null(rgb);
    fill_pattern(rgb, w, h);
    rgb[0] = -1.0f; /* read as 0 */
    rgb[1] = 1e6f;  /* past half floats: clamped */
    rgb[2] = NAN;   /* read as 0 */
    vkrt_error err = {{0}};
    const char *path = temp_dir_path(fx, "sky.EXR");
    assert_true(vkrt_image_write(path, w, h, rgb, 0.0f, &err));
    vkrt_envmap_image img;
    bool ok = vkrt_envmap_load(path, "s.cfg:3", &img, &err);
    if (!ok)
        print_error("%s\n", err.msg);
    assert_true(ok);
    assert_int_equal(img.width, w);
    assert_int_equal(img.height, h);
    assert_float_equal(img.rgb[0], 0.0f, 0);
    assert_float_equal(img.rgb[1], 65504.0f, 0);
    assert_float_equal(img.rgb[2], 0.0f, 0);
    for (size_t i = 3; i < (size_t)w * h * 3; i++)
        assert_float_equal(img.rgb[i], rgb[i], 0);
    vkrt_envmap_image_free(&img);
    vkrt_envmap_image_free(&img);
    free(rgb);
}

/* Writes a tiled (or scanline) EXR of half-float channels through OpenEXRCore, with its data
 * window starting at (ox, oy): names are "R", "G", "B" (rgb interleaved) or "Y" (grey). */
static void write_exr(const char *path, exr_storage_t storage, int ox, int oy, uint32_t w,
                      uint32_t h, bool grey, const float *px)
{
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    exr_context_t ctxt = NULL;
    assert_int_equal(exr_start_write(&ctxt, path, EXR_WRITE_FILE_DIRECTLY, &init), 0);
    int part = 0;
    assert_int_equal(exr_add_part(ctxt, "sky", storage, &part), 0);
    exr_attr_box2i_t window;
    window.min.x = ox, window.min.y = oy;
    window.max.x = ox + (int)w - 1, window.max.y = oy + (int)h - 1;
    exr_attr_v2f_t centre;
    centre.x = 0.0f, centre.y = 0.0f;
    assert_int_equal(exr_initialize_required_attr(ctxt, part, &window, &window, 1.0f, &centre, 1.0f,
                                                  EXR_LINEORDER_INCREASING_Y, EXR_COMPRESSION_ZIP),
                     0);
    if (storage == EXR_STORAGE_TILED)
        assert_int_equal(
            exr_set_tile_descriptor(ctxt, part, 8, 4, EXR_TILE_ONE_LEVEL, EXR_TILE_ROUND_DOWN), 0);
    static const char *const rgb_names[] = {"B", "G", "R"};
    int channels = grey ? 1 : 3;
    for (int c = 0; c < channels; c++)
        assert_int_equal(exr_add_channel(ctxt, part, grey ? "Y" : rgb_names[c], EXR_PIXEL_HALF,
                                         EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1),
                         0);
    assert_int_equal(exr_write_header(ctxt), 0);
    int32_t lines = 1;
    if (storage == EXR_STORAGE_SCANLINE)
        assert_int_equal(exr_get_scanlines_per_chunk(ctxt, part, &lines), 0);
    int tiles_x = storage == EXR_STORAGE_TILED ? (int)(w + 7) / 8 : 1;
    int tiles_y = storage == EXR_STORAGE_TILED ? (int)(h + 3) / 4 : ((int)h + lines - 1) / lines;
    for (int ty = 0; ty < tiles_y; ty++) {
        for (int tx = 0; tx < tiles_x; tx++) {
            exr_chunk_info_t chunk;
            int x0 = 0, y0 = ty * lines;
            if (storage == EXR_STORAGE_TILED) {
                assert_int_equal(exr_write_tile_chunk_info(ctxt, part, tx, ty, 0, 0, &chunk), 0);
                x0 = tx * 8, y0 = ty * 4;
            } else {
                assert_int_equal(exr_write_scanline_chunk_info(ctxt, part, oy + y0, &chunk), 0);
            }
            exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
            assert_int_equal(exr_encoding_initialize(ctxt, part, &chunk, &enc), 0);
            for (int16_t c = 0; c < enc.channel_count; c++) {
                exr_coding_channel_info_t *ch = &enc.channels[c];
                int k = grey ? 0
                             : (ch->channel_name[0] == 'R'   ? 0
                                : ch->channel_name[0] == 'G' ? 1
                                                             : 2);
                ch->encode_from_ptr = (const uint8_t *)(px + ((size_t)y0 * w + x0) * channels + k);
                ch->user_data_type = EXR_PIXEL_FLOAT;
                ch->user_bytes_per_element = sizeof(float);
                ch->user_pixel_stride = channels * (int32_t)sizeof(float);
                ch->user_line_stride = (int32_t)(w * channels * sizeof(float));
            }
            assert_int_equal(exr_encoding_choose_default_routines(ctxt, part, &enc), 0);
            assert_int_equal(exr_encoding_run(ctxt, part, &enc), 0);
            assert_int_equal(exr_encoding_destroy(ctxt, &enc), 0);
        }
    }
    assert_int_equal(exr_finish(&ctxt), 0);
}

static void test_load_exr_tiled_and_grey(void **state)
{
    temp_dir *fx = *state;
    uint32_t w = 19, h = 10; /* edge tiles narrower and shorter than 8 x 4 */
    float *rgb = malloc((size_t)w * h * 3 * sizeof *rgb);
    assert_non_null(rgb);
    fill_pattern(rgb, w, h); /* every value is exact in half */
    const char *path = temp_dir_path(fx, "tiled.exr");
    write_exr(path, EXR_STORAGE_TILED, -3, 5, w, h, false, rgb);
    vkrt_envmap_image img;
    vkrt_error err = {{0}};
    bool ok = vkrt_envmap_load(path, NULL, &img, &err);
    if (!ok)
        print_error("%s\n", err.msg);
    assert_true(ok);
    assert_int_equal(img.width, w);
    assert_int_equal(img.height, h);
    for (size_t i = 0; i < (size_t)w * h * 3; i++)
        assert_float_equal(img.rgb[i], rgb[i], 0);
    vkrt_envmap_image_free(&img);

    float *grey = malloc((size_t)w * h * sizeof *grey);
    assert_non_null(grey);
    for (size_t i = 0; i < (size_t)w * h; i++)
        grey[i] = (float)(i % 11) * 0.5f;
    path = temp_dir_path(fx, "grey.exr");
    write_exr(path, EXR_STORAGE_SCANLINE, 2, -7, w, h, true, grey);
    ok = vkrt_envmap_load(path, NULL, &img, &err);
    if (!ok)
        print_error("%s\n", err.msg);
    assert_true(ok);
    for (size_t i = 0; i < (size_t)w * h; i++)
        for (int k = 0; k < 3; k++)
            assert_float_equal(img.rgb[3 * i + k], grey[i], 0);
    vkrt_envmap_image_free(&img);
    free(grey);
    free(rgb);
}

static void test_load_hdr_and_png(void **state)
{
    temp_dir *fx = *state;
    uint32_t w = 9, h = 5;
    float *rgb = malloc((size_t)w * h * 3 * sizeof *rgb);
    assert_non_null(rgb);
    fill_pattern(rgb, w, h);
    const char *path = temp_dir_path(fx, "sky.hdr");
    assert_true(stbi_write_hdr(path, (int)w, (int)h, 3, rgb) != 0);
    vkrt_envmap_image img;
    vkrt_error err = {{0}};
    assert_true(vkrt_envmap_load(path, NULL, &img, &err));
    assert_int_equal(img.width, w);
    assert_int_equal(img.height, h);
    /* RGBE keeps 8 bits of mantissa per pixel, shared by the channels. */
    for (size_t i = 0; i < (size_t)w * h * 3; i += 3) {
        float big = fmaxf(rgb[i], fmaxf(rgb[i + 1], rgb[i + 2]));
        for (int k = 0; k < 3; k++)
            assert_float_equal(img.rgb[i + k], rgb[i + k], big / 128 + 1e-6);
    }
    vkrt_envmap_image_free(&img);

    /* An 8-bit PNG is sRGB-encoded: read back linear, as a colour texture is. */
    for (size_t i = 0; i < (size_t)w * h * 3; i++)
        rgb[i] = (float)(i % 10) / 9.0f;
    path = temp_dir_path(fx, "sky.png");
    assert_true(vkrt_image_write(path, w, h, rgb, 0.0f, &err));
    assert_true(vkrt_envmap_load(path, NULL, &img, &err));
    for (size_t i = 0; i < (size_t)w * h * 3; i++)
        assert_float_equal(img.rgb[i], rgb[i], 0.01);
    vkrt_envmap_image_free(&img);
    free(rgb);
}

static void test_load_errors(void **state)
{
    temp_dir *fx = *state;
    vkrt_envmap_image img;
    vkrt_error err = {{0}};
    memset(&img, 0xAB, sizeof img);
    assert_false(vkrt_envmap_load("/nonexistent/sky.hdr", "s.cfg:4", &img, &err));
    assert_string_equal(err.msg, "s.cfg:4: environment-map '/nonexistent/sky.hdr': cannot open: "
                                 "No such file or directory");
    assert_null(img.rgb);
    assert_false(vkrt_envmap_load("/nonexistent/sky.exr", NULL, &img, &err));
    assert_string_equal(err.msg, "environment-map '/nonexistent/sky.exr': cannot open: No such "
                                 "file or directory");

    const char *path = temp_dir_write_text(fx, "notes.hdr", "this is not an image\n");
    assert_false(vkrt_envmap_load(path, "s.cfg:4", &img, &err));
    assert_non_null(strstr(err.msg, "not an image vkrt can read"));
    path = temp_dir_write_text(fx, "broken.exr", "this is not an EXR either\n");
    memset(&img, 0xAB, sizeof img);
    assert_false(vkrt_envmap_load(path, "s.cfg:4", &img, &err));
    assert_non_null(strstr(err.msg, "broken.exr': cannot read it as OpenEXR"));
    assert_null(img.rgb);

    /* An EXR with no colour channel. */
    float a[6] = {1, 2, 3, 4, 5, 6};
    path = temp_dir_path(fx, "alpha.exr");
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    exr_context_t ctxt = NULL;
    assert_int_equal(exr_start_write(&ctxt, path, EXR_WRITE_FILE_DIRECTLY, &init), 0);
    int part = 0;
    assert_int_equal(exr_add_part(ctxt, "a", EXR_STORAGE_SCANLINE, &part), 0);
    assert_int_equal(exr_initialize_required_attr_simple(ctxt, part, 3, 2, EXR_COMPRESSION_NONE),
                     0);
    assert_int_equal(
        exr_add_channel(ctxt, part, "A", EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LINEAR, 1, 1), 0);
    assert_int_equal(exr_write_header(ctxt), 0);
    for (int y = 0; y < 2; y++) {
        exr_chunk_info_t chunk;
        assert_int_equal(exr_write_scanline_chunk_info(ctxt, part, y, &chunk), 0);
        exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
        assert_int_equal(exr_encoding_initialize(ctxt, part, &chunk, &enc), 0);
        enc.channels[0].encode_from_ptr = (const uint8_t *)(a + 3 * y);
        enc.channels[0].user_data_type = EXR_PIXEL_FLOAT;
        enc.channels[0].user_bytes_per_element = 4;
        enc.channels[0].user_pixel_stride = 4;
        enc.channels[0].user_line_stride = 12;
        assert_int_equal(exr_encoding_choose_default_routines(ctxt, part, &enc), 0);
        assert_int_equal(exr_encoding_run(ctxt, part, &enc), 0);
        assert_int_equal(exr_encoding_destroy(ctxt, &enc), 0);
    }
    assert_int_equal(exr_finish(&ctxt), 0);
    assert_false(vkrt_envmap_load(path, NULL, &img, &err));
    assert_non_null(strstr(err.msg, "alpha.exr': no R, G and B channels (nor Y)"));
}

/* The bytes of the file at path, malloc'd, in *size. */
static unsigned char *file_bytes(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    assert_int_equal(fseek(f, 0, SEEK_END), 0);
    long n = ftell(f);
    assert_true(n > 0);
    rewind(f);
    unsigned char *bytes = malloc((size_t)n);
    assert_non_null(bytes);
    assert_int_equal(fread(bytes, 1, (size_t)n, f), (size_t)n);
    fclose(f);
    *size = (size_t)n;
    return bytes;
}

/* A Radiance map decodes to exactly the floats stb_image gives (the reader before ours), run-length
 * encoded (width 8 to 32767, as stbi_write_hdr writes them) or flat (narrower), and with a
 * file name that does not end in .hdr. */
static void test_hdr_as_stb_image_decodes(void **state)
{
    temp_dir *fx = *state;
    static const uint32_t widths[] = {5, 8, 37, 300};
    for (size_t t = 0; t < sizeof widths / sizeof widths[0]; t++) {
        uint32_t w = widths[t], h = 7;
        float *rgb = make_sky(w, h);
        rgb[3 * (w + 1)] = 1e-30f; /* an exponent of 0 */
        const char *path = temp_dir_path(fx, "sky.pic");
        assert_true(stbi_write_hdr(path, (int)w, (int)h, 3, rgb) != 0);
        int sw, sh, sc;
        float *want = stbi_loadf(path, &sw, &sh, &sc, 3);
        assert_non_null(want);
        vkrt_envmap_image img;
        vkrt_error err = {{0}};
        assert_true(vkrt_envmap_load(path, NULL, &img, &err));
        assert_int_equal(img.width, w);
        assert_int_equal(img.height, h);
        assert_memory_equal(img.rgb, want, (size_t)w * h * 3 * sizeof(float));
        stbi_image_free(want);
        vkrt_envmap_image_free(&img);
        free(rgb);
    }
}

/* A Radiance file cut short is an error with its byte counts, whatever the encoding and wherever
 * the cut (stb_image read the missing pixels as zeros: flat colour); a header declaring the
 * largest size the docs allow is read as such, and its missing pixels reported, not "too large". */
static void test_hdr_cut_short(void **state)
{
    temp_dir *fx = *state;
    static const uint32_t widths[] = {5, 64};
    for (size_t t = 0; t < sizeof widths / sizeof widths[0]; t++) {
        uint32_t w = widths[t], h = 16;
        float *rgb = make_sky(w, h);
        const char *path = temp_dir_path(fx, "whole.hdr");
        assert_true(stbi_write_hdr(path, (int)w, (int)h, 3, rgb) != 0);
        free(rgb);
        size_t size;
        unsigned char *bytes = file_bytes(path, &size);
        size_t cuts[] = {size - 1, size / 2, size - 200};
        for (size_t c = 0; c < sizeof cuts / sizeof cuts[0]; c++) {
            path = temp_dir_write(fx, "cut.hdr", bytes, cuts[c]);
            vkrt_envmap_image img;
            vkrt_error err = {{0}};
            assert_false(vkrt_envmap_load(path, "s.cfg:2", &img, &err));
            char want[200];
            snprintf(want, sizeof want, "cut.hdr': the Radiance HDR file is cut short: it has %zu bytes, but its pixels end in scanline ", cuts[c]);
            if (!strstr(err.msg, want))
                print_error("%s\n", err.msg);
            assert_non_null(strstr(err.msg, want));
            assert_null(img.rgb);
        }
        free(bytes);
    }

    static const char header[] = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 16384 +X 16384\n";
    const char *path = temp_dir_write(fx, "big.hdr", header, strlen(header));
    vkrt_envmap_image img;
    vkrt_error err = {{0}};
    assert_false(vkrt_envmap_load(path, NULL, &img, &err));
    assert_non_null(strstr(err.msg, "big.hdr': the Radiance HDR file is cut short: it has 53 "
                                    "bytes, but its pixels end in scanline 1 of 16384 (a "
                                    "16384x16384 image needs at least "));
    assert_null(strstr(err.msg, "too large"));

    /* One past the limit is refused as such; the limit itself, in one direction, loads. */
    static const char over[] = "#?RADIANCE\n\n-Y 1 +X 16385\n";
    path = temp_dir_write(fx, "over.hdr", over, strlen(over));
    assert_false(vkrt_envmap_load(path, NULL, &img, &err));
    assert_non_null(strstr(err.msg, "image is 16385x1; maps must be 1 to 16384 pixels"));
    size_t w = 16384, h = 2;
    float *rgb = malloc(w * h * 3 * sizeof *rgb);
    assert_non_null(rgb);
    for (size_t i = 0; i < w * h * 3; i++)
        rgb[i] = (float)(i % 7);
    path = temp_dir_path(fx, "wide.hdr");
    assert_true(stbi_write_hdr(path, (int)w, (int)h, 3, rgb) != 0);
    assert_true(vkrt_envmap_load(path, NULL, &img, &err));
    assert_int_equal(img.width, w);
    assert_memory_equal(img.rgb, rgb, w * h * 3 * sizeof *rgb); /* small integers are exact */
    vkrt_envmap_image_free(&img);
    free(rgb);

    /* Damaged rather than short: a run longer than its scanline. */
    static const char damaged[] = "#?RADIANCE\n\n-Y 1 +X 8\n\x02\x02\x00\x08\x8a\x01";
    path = temp_dir_write(fx, "damaged.hdr", damaged, sizeof damaged - 1);
    assert_false(vkrt_envmap_load(path, NULL, &img, &err));
    assert_non_null(strstr(err.msg, "a run in scanline 1 of 1 goes past the scanline's 8 pixels"));
    static const char xyze[] = "#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 1 +X 1\nabcd";
    path = temp_dir_write(fx, "xyze.hdr", xyze, sizeof xyze - 1);
    assert_false(vkrt_envmap_load(path, NULL, &img, &err));
    assert_non_null(strstr(err.msg, "format is 32-bit_rle_xyze; only 32-bit_rle_rgbe is read"));
}

/* A PNG map cut short says so with its byte counts, not stb_image's "outofdata". */
static void test_png_cut_short(void **state)
{
    temp_dir *fx = *state;
    uint32_t w = 32, h = 16;
    float *rgb = make_sky(w, h);
    const char *path = temp_dir_path(fx, "sky.png");
    vkrt_error err = {{0}};
    assert_true(vkrt_image_write(path, w, h, rgb, 0.0f, &err));
    free(rgb);
    size_t size;
    unsigned char *bytes = file_bytes(path, &size);
    path = temp_dir_write(fx, "cut.png", bytes, size - 20);
    free(bytes);
    vkrt_envmap_image img;
    assert_false(vkrt_envmap_load(path, NULL, &img, &err));
    if (!strstr(err.msg, "cut.png': cannot decode the image: the PNG file is cut short: it has "))
        print_error("%s\n", err.msg);
    assert_non_null(strstr(err.msg, "cut.png': cannot decode the image: the PNG file is cut short: it has "));
    assert_null(strstr(err.msg, "stb_image"));
}

/* ---------------------------------------------------------------------------------------------
 * glsl/lib/envmap.glsl compiles where the kernels include it: after lib/bindings.glsl. glslang
 * runs on the CPU, so no device is needed.
 * ------------------------------------------------------------------------------------------- */

static const char check_kernel[] =
    "#include \"lib/bindings.glsl\"\n"
    "#include \"lib/envmap.glsl\"\n"
    "layout(std430, set = 1, binding = 0) buffer CheckOut { vec4 check_out[]; };\n"
    "void main()\n"
    "{\n"
    "    LightInfo info = light_info;\n"
    "    float pdf_uv;\n"
    "    vec2 uv = envmap_sample(info, vec2(0.25, 0.75), pdf_uv);\n"
    "    vec3 d = envmap_direction(uv, info.environment_rotate);\n"
    "    check_out[gl_GlobalInvocationID.x] =\n"
    "        vec4(envmap_uv(d, info.environment_rotate), pdf_uv, envmap_pdf(info, d));\n"
    "}\n";

static char *check_lookup(void *user, const char *path)
{
    (void)user;
    if (strcmp(path, "envmap_check.comp") == 0)
        return strdup(check_kernel);
    return vkrt_kernel_source_lookup(NULL, path);
}

static void test_glsl_compiles(void **state)
{
    (void)state;
    gpu_shader_sources sources = {.lookup = check_lookup, .display_prefix = "glsl/"};
    uint32_t *spirv = NULL;
    size_t words = 0;
    vkrt_error err = {{0}};
    bool ok = gpu_shader_compile(&sources, "envmap_check.comp", &spirv, &words, &err);
    if (!ok)
        print_error("%s\n", err.msg);
    assert_true(ok);
    assert_true(words > 0);
    free(spirv);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_convention),
        cmocka_unit_test(test_round_trip),
        cmocka_unit_test(test_layout_and_cdfs),
        cmocka_unit_test(test_pdf_integrates_to_one),
        cmocka_unit_test(test_histogram_and_sample_pdf),
        cmocka_unit_test(test_positive_where_lit),
        cmocka_unit_test(test_estimator_unbiased),
        temp_dir_test(test_load_exr_scanline),
        temp_dir_test(test_load_exr_tiled_and_grey),
        temp_dir_test(test_load_hdr_and_png),
        temp_dir_test(test_load_errors),
        temp_dir_test(test_hdr_as_stb_image_decodes),
        temp_dir_test(test_hdr_cut_short),
        temp_dir_test(test_png_cut_short),
        cmocka_unit_test(test_glsl_compiles),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
