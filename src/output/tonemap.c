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

static void apply_matrix(const matrix3 m, const float in[3], float out[3])
{
    float v[3] = {in[0], in[1], in[2]};
    for (int i = 0; i < 3; ++i)
        out[i] = m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2];
}

static float clamp01(float x)
{
    return x < 0.0f ? 0.0f : x > 1.0f ? 1.0f : x;
}

static float aces_fit(float v)
{
    float a = v * (v + VKRT_ACES_FIT_A) - VKRT_ACES_FIT_B;
    float b = v * (VKRT_ACES_FIT_C * v + VKRT_ACES_FIT_D) + VKRT_ACES_FIT_E;
    return a / b;
}

static void aces(float rgb[3])
{
    static const matrix3 input = {
        {VKRT_ACES_INPUT_ROW0}, {VKRT_ACES_INPUT_ROW1}, {VKRT_ACES_INPUT_ROW2}};
    static const matrix3 output = {
        {VKRT_ACES_OUTPUT_ROW0}, {VKRT_ACES_OUTPUT_ROW1}, {VKRT_ACES_OUTPUT_ROW2}};
    apply_matrix(input, rgb, rgb);
    for (int i = 0; i < 3; ++i)
        rgb[i] = aces_fit(rgb[i]);
    apply_matrix(output, rgb, rgb);
    for (int i = 0; i < 3; ++i)
        rgb[i] = clamp01(rgb[i]);
}

static float agx_sigmoid(float x)
{
    float p = VKRT_AGX_POLY6;
    p = p * x + VKRT_AGX_POLY5;
    p = p * x + VKRT_AGX_POLY4;
    p = p * x + VKRT_AGX_POLY3;
    p = p * x + VKRT_AGX_POLY2;
    p = p * x + VKRT_AGX_POLY1;
    return p * x + VKRT_AGX_POLY0;
}

static void agx(float rgb[3])
{
    static const matrix3 inset = {
        {VKRT_AGX_INSET_ROW0}, {VKRT_AGX_INSET_ROW1}, {VKRT_AGX_INSET_ROW2}};
    static const matrix3 outset = {
        {VKRT_AGX_OUTSET_ROW0}, {VKRT_AGX_OUTSET_ROW1}, {VKRT_AGX_OUTSET_ROW2}};
    apply_matrix(inset, rgb, rgb);
    for (int i = 0; i < 3; ++i) {
        float ev = log2f(fmaxf(rgb[i], VKRT_AGX_LOG_FLOOR));
        ev = fminf(fmaxf(ev, VKRT_AGX_MIN_EV), VKRT_AGX_MAX_EV);
        rgb[i] = agx_sigmoid((ev - VKRT_AGX_MIN_EV) / (VKRT_AGX_MAX_EV - VKRT_AGX_MIN_EV));
    }
    apply_matrix(outset, rgb, rgb);
    for (int i = 0; i < 3; ++i)
        rgb[i] = clamp01(powf(fmaxf(rgb[i], 0.0f), VKRT_AGX_DISPLAY_GAMMA));
}

void tonemap_pixel(vkrt_tonemap curve, const float in[3], float out[3])
{
    if (curve == VKRT_TONEMAP_NONE) {
        for (int i = 0; i < 3; ++i)
            out[i] = in[i];
        return;
    }
    float rgb[3];
    for (int i = 0; i < 3; ++i) {
        /* A NaN channel would reach every channel through the matrices: the pixel is black. */
        if (isnan(in[i])) {
            out[0] = out[1] = out[2] = 0.0f;
            return;
        }
        rgb[i] = fminf(fmaxf(in[i], 0.0f), VKRT_TONE_INPUT_MAX);
    }
    if (curve == VKRT_TONEMAP_ACES)
        aces(rgb);
    else
        agx(rgb);
    for (int i = 0; i < 3; ++i)
        out[i] = rgb[i];
}

void tonemap_image(vkrt_tonemap curve, float *rgb, size_t pixels)
{
    for (size_t i = 0; i < pixels; ++i)
        tonemap_pixel(curve, rgb + 3 * i, rgb + 3 * i);
}
