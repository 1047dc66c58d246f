/*
 * test_tonemap.c: the tone curves of src/output/tonemap.c and their pass in src/output/finish.c.
 *
 * Neither source publishes a table of outputs, so each curve is held to its published code,
 * transcribed here a second time in the layout its source prints it (Hill's ACES fit as the HLSL
 * of Baking Lab's ACES.hlsl, row by row, applied as mul(M, v); Wrensch's minimal AgX as GLSL
 * mat3 constructors, which fill columns, applied as M * v) and evaluated in double: a row typed
 * as a column in glsl/tone_curves.h, a digit dropped or a step left out shows here. The
 * constants are also checked against what they are derived from (AgX's outset is its inset's
 * inverse; AgX's range is 10 stops below and 6.5 above middle grey; the ACES matrices keep grey
 * grey), and both curves against the properties a tone curve must have: black stays black,
 * output in [0, 1], never falling along grey, saturating, NaN black.
 */
#include <setjmp.h> /* cmocka needs these before its header */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../glsl/tone_curves.h"
#include "output/finish.h"
#include "output/srgb8.h"
#include "output/tonemap.h"

/* ---------------------------------------------------------------------------------------------
 * The published code, in double
 * ------------------------------------------------------------------------------------------- */

/* BakingLab/ACES.hlsl: static const float3x3 ACESInputMat = {{...}, {...}, {...}} (rows), used
 * as mul(ACESInputMat, color). */
static const double hill_input[3][3] = {{0.59719, 0.35458, 0.04823},
                                        {0.07600, 0.90834, 0.01566},
                                        {0.02840, 0.13383, 0.83777}};
static const double hill_output[3][3] = {{1.60475, -0.53108, -0.07367},
                                         {-0.10208, 1.10813, -0.00605},
                                         {-0.00327, -0.07276, 1.07602}};

static double clamp01(double x)
{
    return x < 0 ? 0 : x > 1 ? 1 : x;
}

static void hill_aces(const double in[3], double out[3])
{
    double v[3];
    for (int r = 0; r < 3; ++r)
        v[r] = hill_input[r][0] * in[0] + hill_input[r][1] * in[1] + hill_input[r][2] * in[2];
    for (int r = 0; r < 3; ++r) {
        double a = v[r] * (v[r] + 0.0245786) - 0.000090537;
        double b = v[r] * (0.983729 * v[r] + 0.4329510) + 0.238081;
        v[r] = a / b;
    }
    for (int r = 0; r < 3; ++r)
        out[r] = clamp01(hill_output[r][0] * v[0] + hill_output[r][1] * v[1] +
                         hill_output[r][2] * v[2]);
}

/* iolite-engine.com/blog_posts/minimal_agx_implementation: const mat3 agx_mat = mat3(...),
 * nine numbers that GLSL reads column after column; val = agx_mat * val. */
static const double wrensch_inset_columns[9] = {
    0.842479062253094,  0.0423282422610123, 0.0423756549057051,
    0.0784335999999992, 0.878468636469772,  0.0784336,
    0.0792237451477643, 0.0791661274605434, 0.879142973793104};
static const double wrensch_outset_columns[9] = {
    1.19687900512017,    -0.0528968517574562, -0.0529716355144438,
    -0.0980208811401368, 1.15190312990417,    -0.0980434501171241,
    -0.0990297440797205, -0.0989611768448433, 1.15107367264116};

static void glsl_mat3_times(const double columns[9], const double v[3], double out[3])
{
    for (int r = 0; r < 3; ++r)
        out[r] = columns[r] * v[0] + columns[3 + r] * v[1] + columns[6 + r] * v[2];
}

static void wrensch_agx(const double in[3], double out[3])
{
    const double min_ev = -12.47393, max_ev = 4.026069;
    double v[3];
    glsl_mat3_times(wrensch_inset_columns, in, v);
    for (int i = 0; i < 3; ++i) {
        /* clamp(log2(val), min_ev, max_ev), with log2(0) = -inf clamped to min_ev */
        double ev = v[i] > 0 ? log2(v[i]) : -INFINITY;
        double x = ((ev < min_ev ? min_ev : ev > max_ev ? max_ev : ev) - min_ev) / (max_ev - min_ev);
        double x2 = x * x, x4 = x2 * x2;
        v[i] = 15.5 * x4 * x2 - 40.14 * x4 * x + 31.96 * x4 - 6.868 * x2 * x + 0.4298 * x2 +
               0.1191 * x - 0.00232;
    }
    glsl_mat3_times(wrensch_outset_columns, v, out);
    for (int i = 0; i < 3; ++i) /* agxEotf's pow(val, 2.2), negatives at 0 */
        out[i] = clamp01(pow(out[i] > 0 ? out[i] : 0, 2.2));
}

typedef void (*reference_curve)(const double in[3], double out[3]);

/* A fixed, spread-out set of inputs: greys from 2^-14 to 2^17, every channel mix of a few
 * levels, and pseudo-random colours up to 64. Returns how many (at most max). */
static size_t sample_inputs(float (*in)[3], size_t max)
{
    size_t n = 0;
    for (double stops = -14; stops <= 17 && n < max; stops += 0.125, ++n)
        in[n][0] = in[n][1] = in[n][2] = (float)exp2(stops);
    static const float levels[] = {0.0f, 0.01f, 0.18f, 1.0f, 4.0f, 100.0f};
    for (int r = 0; r < 6; ++r)
        for (int g = 0; g < 6; ++g)
            for (int b = 0; b < 6 && n < max; ++b, ++n) {
                in[n][0] = levels[r];
                in[n][1] = levels[g];
                in[n][2] = levels[b];
            }
    uint32_t state = 12345u;
    while (n < max) {
        for (int i = 0; i < 3; ++i) {
            state = state * 1664525u + 1013904223u; /* Numerical Recipes' LCG */
            in[n][i] = 64.0f * (float)(state >> 8) / (float)(1u << 24);
        }
        ++n;
    }
    return n;
}

enum { SAMPLES = 1000 };

/* The float curve within tolerance of the published one, on every sample. */
static void check_against_reference(vkrt_tonemap curve, reference_curve reference,
                                    double tolerance)
{
    static float in[SAMPLES][3];
    size_t n = sample_inputs(in, SAMPLES);
    double worst = 0;
    for (size_t i = 0; i < n; ++i) {
        float got[3];
        tonemap_pixel(curve, in[i], got);
        double in_d[3] = {in[i][0], in[i][1], in[i][2]}, want[3];
        reference(in_d, want);
        for (int c = 0; c < 3; ++c) {
            double d = fabs(got[c] - want[c]);
            if (d > worst)
                worst = d;
            if (!(d <= tolerance))
                fail_msg("%s (%g, %g, %g) channel %d: %.9g, published code gives %.9g",
                         vkrt_tonemap_name(curve), in[i][0], in[i][1], in[i][2], c, got[c],
                         want[c]);
        }
    }
    print_message("%s: largest difference from the published code in double: %.2g\n",
                  vkrt_tonemap_name(curve), worst);
}

/* Float arithmetic against double: AgX's polynomial sums terms up to 40 that cancel to a value
 * near 1, so float rounding moves it by up to a few 1e-6; both stay far under a code value's
 * 1/255. */
static const double float_tolerance = 2e-5;

static void test_aces_against_hill(void **state)
{
    (void)state;
    check_against_reference(VKRT_TONEMAP_ACES, hill_aces, float_tolerance);
}

static void test_agx_against_wrensch(void **state)
{
    (void)state;
    check_against_reference(VKRT_TONEMAP_AGX, wrensch_agx, float_tolerance);
}

/* ---------------------------------------------------------------------------------------------
 * The constants against what they are derived from
 * ------------------------------------------------------------------------------------------- */

static void test_agx_constants(void **state)
{
    (void)state;
    /* The outset is the inset's inverse (agx_mat_inv): their product is the identity. */
    static const float inset[3][3] = {
        {VKRT_AGX_INSET_ROW0}, {VKRT_AGX_INSET_ROW1}, {VKRT_AGX_INSET_ROW2}};
    static const float outset[3][3] = {
        {VKRT_AGX_OUTSET_ROW0}, {VKRT_AGX_OUTSET_ROW1}, {VKRT_AGX_OUTSET_ROW2}};
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
            double sum = 0;
            for (int k = 0; k < 3; ++k)
                sum += (double)inset[r][k] * outset[k][c];
            assert_float_equal(sum, r == c ? 1.0 : 0.0, 1e-6);
        }
    /* Troy Sobotka's AgX: middle grey 0.18 with 10 stops below it and 6.5 above. */
    assert_float_equal(VKRT_AGX_MIN_EV, log2(0.18) - 10.0, 1e-5);
    assert_float_equal(VKRT_AGX_MAX_EV, log2(0.18) + 6.5, 1e-5);
}

static void test_aces_constants(void **state)
{
    (void)state;
    /* Both matrices keep grey grey: each row sums to 1 (to the published 5 decimals). */
    static const float rows[6][3] = {{VKRT_ACES_INPUT_ROW0},  {VKRT_ACES_INPUT_ROW1},
                                     {VKRT_ACES_INPUT_ROW2},  {VKRT_ACES_OUTPUT_ROW0},
                                     {VKRT_ACES_OUTPUT_ROW1}, {VKRT_ACES_OUTPUT_ROW2}};
    for (int r = 0; r < 6; ++r)
        assert_float_equal((double)rows[r][0] + rows[r][1] + rows[r][2], 1.0, 2e-5);
}

/* ---------------------------------------------------------------------------------------------
 * Properties
 * ------------------------------------------------------------------------------------------- */

static float grey(vkrt_tonemap curve, float v)
{
    float in[3] = {v, v, v}, out[3];
    tonemap_pixel(curve, in, out);
    /* Grey in, nearly grey out (AgX's published inset rows sum to 1 within 1.4e-4, which tints
     * grey by less than 1e-3). */
    assert_float_equal(out[1], out[0], 1e-3);
    return out[1];
}

static void check_properties(vkrt_tonemap curve, reference_curve reference)
{
    assert_true(grey(curve, 0.0f) == 0.0f);
    assert_true(grey(curve, -5.0f) == 0.0f);
    /* Middle grey where the published formula puts it (double precision, this file). */
    double mid[3] = {0.18, 0.18, 0.18}, want[3];
    reference(mid, want);
    assert_float_equal(grey(curve, 0.18f), want[1], float_tolerance);
    /* Never falling along grey, from 2^-20 to 2^20, in steps of 1/64 stop. */
    float last = 0.0f;
    for (double stops = -20; stops <= 20; stops += 1.0 / 64) {
        float y = grey(curve, (float)exp2(stops));
        if (y < last)
            fail_msg("%s falls at grey 2^%g: %.9g after %.9g", vkrt_tonemap_name(curve), stops, y,
                     last);
        assert_true(y >= 0.0f && y <= 1.0f);
        last = y;
    }
    /* Saturates: past the top of its range the output no longer changes, and stays at most 1;
     * infinity is that value too. */
    float top = grey(curve, 1000.0f);
    assert_true(top > 0.99f && top <= 1.0f);
    assert_true(grey(curve, 1e6f) == top);
    assert_true(grey(curve, INFINITY) == top);
    /* NaN in any channel: black, all three. */
    float in[3] = {0.5f, NAN, 2.0f}, out[3] = {1, 1, 1};
    tonemap_pixel(curve, in, out);
    assert_true(out[0] == 0.0f && out[1] == 0.0f && out[2] == 0.0f);
}

static void test_aces_properties(void **state)
{
    (void)state;
    check_properties(VKRT_TONEMAP_ACES, hill_aces);
    /* Hill's fit tends to 1 / 0.983729 > 1, clamped: grey reaches white (near 26). */
    assert_true(grey(VKRT_TONEMAP_ACES, 30.0f) == 1.0f);
    assert_true(grey(VKRT_TONEMAP_ACES, 20.0f) < 1.0f);
}

static void test_agx_properties(void **state)
{
    (void)state;
    check_properties(VKRT_TONEMAP_AGX, wrensch_agx);
    /* AgX's sigmoid ends just short of white: its top is below 1. */
    assert_true(grey(VKRT_TONEMAP_AGX, 1000.0f) < 1.0f);
}

static void test_none_copies(void **state)
{
    (void)state;
    float in[3] = {-1.0f, 0.5f, 7.0f}, out[3];
    tonemap_pixel(VKRT_TONEMAP_NONE, in, out);
    assert_memory_equal(in, out, sizeof in);
}

/* ---------------------------------------------------------------------------------------------
 * The finish stage
 * ------------------------------------------------------------------------------------------- */

/* 8-bit output: exposure, then the curve, then the sRGB encode; none gives the codes it gave
 * before curves existed (srgb8_encode of the exposed value, channel by channel); float output
 * keeps the radiance whatever the curve. */
static void test_finish(void **state)
{
    (void)state;
    static float in[SAMPLES][3];
    size_t n = sample_inputs(in, SAMPLES);
    in[0][1] = NAN;
    const float *rgb = &in[0][0];
    size_t count = 3 * n;
    uint8_t *codes = malloc(count);
    assert_non_null(codes);
    vkrt_error err = {{0}};
    for (vkrt_tonemap curve = VKRT_TONEMAP_NONE; curve <= VKRT_TONEMAP_AGX; ++curve) {
        vkrt_finish_desc desc = {.exposure = 1.5f, .tonemap = curve};
        const vkrt_finish_frame frame = {.width = (uint32_t)n, .height = 1, .rgb = rgb};
        assert_true(vkrt_finish_srgb8(&desc, &frame, codes, &err));
        float scale = exp2f(desc.exposure);
        for (size_t i = 0; i < n; ++i) {
            float exposed[3] = {in[i][0] * scale, in[i][1] * scale, in[i][2] * scale}, shown[3];
            tonemap_pixel(curve, exposed, shown);
            for (int c = 0; c < 3; ++c)
                assert_int_equal(codes[3 * i + c],
                                 srgb8_encode(curve == VKRT_TONEMAP_NONE ? exposed[c] : shown[c]));
        }
        float *scratch;
        assert_ptr_equal(vkrt_finish_linear(&desc, &frame, &scratch, &err), rgb);
        assert_null(scratch);
        vkrt_finish_display shown = vkrt_finish_display_params(&desc);
        assert_int_equal(shown.tonemap, curve);
        assert_float_equal(shown.scale, scale, 0);
    }
    free(codes);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_aces_against_hill), cmocka_unit_test(test_agx_against_wrensch),
        cmocka_unit_test(test_agx_constants),     cmocka_unit_test(test_aces_constants),
        cmocka_unit_test(test_aces_properties),   cmocka_unit_test(test_agx_properties),
        cmocka_unit_test(test_none_copies),       cmocka_unit_test(test_finish),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
