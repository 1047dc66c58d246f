/*
 * tonemap.c: the tone curves (tonemap.h), in float as glsl/display.comp computes them, with the
 * constants of glsl/tone_curves.h.
 */
#include "tonemap.h"

#include <math.h>

#include "../../glsl/tone_curves.h"

_Static_assert(VKRT_TONEMAP_NONE == VKRT_TONE_CURVE_NONE &&
                   VKRT_TONEMAP_ACES == VKRT_TONE_CURVE_ACES &&
                   VKRT_TONEMAP_AGX == VKRT_TONE_CURVE_AGX,
               "the window's curve numbers are scene.cfg's");

typedef float matrix3[3][3];

/* Both curves have one shape: a matrix, a function per channel, a matrix, a function per
 * channel. */
typedef struct curve_steps {
    matrix3 before;
    float (*channel)(float v);
    matrix3 after;
    float (*display)(float v);
} curve_steps;

static inline void apply_matrix(const matrix3 m, float rgb[3])
{
    float v[3] = {rgb[0], rgb[1], rgb[2]};
    for (int i = 0; i < 3; ++i)
        rgb[i] = m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2];
}

static inline __attribute__((always_inline)) void run_steps(const curve_steps *c, float rgb[3])
{
    apply_matrix(c->before, rgb);
    for (int i = 0; i < 3; ++i)
        rgb[i] = c->channel(rgb[i]);
    apply_matrix(c->after, rgb);
    for (int i = 0; i < 3; ++i)
        rgb[i] = c->display(rgb[i]);
}

/* x clamped to [lo, hi] (x is never NaN here: map_pixel turns NaN pixels black first).
 * Comparisons rather than fminf and fmaxf, which are calls into libm. */
static inline float clamp_to(float x, float lo, float hi)
{
    return x < lo ? lo : x > hi ? hi : x;
}

static float clamp01(float x)
{
    return clamp_to(x, 0.0f, 1.0f);
}

static float aces_fit(float v)
{
    float a = v * (v + VKRT_ACES_FIT_A) - VKRT_ACES_FIT_B;
    float b = v * (VKRT_ACES_FIT_C * v + VKRT_ACES_FIT_D) + VKRT_ACES_FIT_E;
    return a / b;
}

static const curve_steps aces = {
    .before = {{VKRT_ACES_INPUT_ROW0}, {VKRT_ACES_INPUT_ROW1}, {VKRT_ACES_INPUT_ROW2}},
    .channel = aces_fit,
    .after = {{VKRT_ACES_OUTPUT_ROW0}, {VKRT_ACES_OUTPUT_ROW1}, {VKRT_ACES_OUTPUT_ROW2}},
    .display = clamp01,
};

/* log2 clamped to AgX's range, scaled to [0, 1], through the sigmoid polynomial: a
 * display-encoded value. */
static float agx_sigmoid(float v)
{
    float ev = clamp_to(log2f(v > VKRT_AGX_LOG_FLOOR ? v : VKRT_AGX_LOG_FLOOR), VKRT_AGX_MIN_EV,
                        VKRT_AGX_MAX_EV);
    float x = (ev - VKRT_AGX_MIN_EV) / (VKRT_AGX_MAX_EV - VKRT_AGX_MIN_EV);
    float p = VKRT_AGX_POLY6;
    p = p * x + VKRT_AGX_POLY5;
    p = p * x + VKRT_AGX_POLY4;
    p = p * x + VKRT_AGX_POLY3;
    p = p * x + VKRT_AGX_POLY2;
    p = p * x + VKRT_AGX_POLY1;
    return p * x + VKRT_AGX_POLY0;
}

/* The published display EOTF back to linear. */
static float agx_linear(float encoded)
{
    return encoded > 0.0f ? clamp01(powf(encoded, VKRT_AGX_DISPLAY_GAMMA)) : 0.0f;
}

static const curve_steps agx = {
    .before = {{VKRT_AGX_INSET_ROW0}, {VKRT_AGX_INSET_ROW1}, {VKRT_AGX_INSET_ROW2}},
    .channel = agx_sigmoid,
    .after = {{VKRT_AGX_OUTSET_ROW0}, {VKRT_AGX_OUTSET_ROW1}, {VKRT_AGX_OUTSET_ROW2}},
    .display = agx_linear,
};

/* One pixel through c, in place. Always inlined: with c constant in each curve's loop, the steps
 * are inlined too instead of called through pointers (a 1080p frame through AgX took twice as
 * long without). */
static inline __attribute__((always_inline)) void map_pixel(const curve_steps *c, float rgb[3])
{
    for (int i = 0; i < 3; ++i) {
        /* A NaN channel would reach every channel through the matrices: the pixel is black. */
        if (isnan(rgb[i])) {
            rgb[0] = rgb[1] = rgb[2] = 0.0f;
            return;
        }
        rgb[i] = clamp_to(rgb[i], 0.0f, VKRT_TONE_INPUT_MAX);
    }
    run_steps(c, rgb);
}

void tonemap_image(vkrt_tonemap curve, float *rgb, size_t pixels)
{
    if (curve == VKRT_TONEMAP_ACES)
        for (size_t i = 0; i < pixels; ++i)
            map_pixel(&aces, rgb + 3 * i);
    else if (curve == VKRT_TONEMAP_AGX)
        for (size_t i = 0; i < pixels; ++i)
            map_pixel(&agx, rgb + 3 * i);
}

void tonemap_pixel(vkrt_tonemap curve, const float in[3], float out[3])
{
    for (int i = 0; i < 3; ++i)
        out[i] = in[i];
    tonemap_image(curve, out, 1);
}
