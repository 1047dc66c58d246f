/*
 * tone_curves.h: the published constants of the tone curves that 8-bit output may pass through,
 * defined once for the host (src/output/tonemap.c, which makes PNGs) and the viewer's display
 * pass (glsl/display.comp), so that the window shows what a PNG holds. Compiled as C and as GLSL:
 * a matrix row is a macro of three numbers, read as `vec3(ROW)` in GLSL and `{ROW}` in C, and a
 * row is applied as a dot product on both sides (no row/column-major question arises).
 *
 * Both curves take linear Rec.709/sRGB radiance (after exposure) and give linear display values
 * in [0, 1], which the sRGB encode then turns into code values, as it does without a curve.
 */
#ifndef VKRT_TONE_CURVES_H
#define VKRT_TONE_CURVES_H

/* The curve a frame goes through (the push constants' value; src/scene/config.h's vkrt_tonemap
 * has the same numbers). */
#define VKRT_TONE_CURVE_NONE 0u
#define VKRT_TONE_CURVE_ACES 1u
#define VKRT_TONE_CURVE_AGX 2u

/* Inputs are clamped to [0, this] first: the largest half float, which keeps v * v finite in
 * float arithmetic (the ACES fit) and lies far past where both curves reach white (grey about
 * 26 for ACES, 16 for AgX). A pixel with a NaN channel is black. */
#define VKRT_TONE_INPUT_MAX 65504.0f

/* ACES: Stephen Hill's fit of the ACES 1.0 reference rendering transform and sRGB output
 * transform (RRT + ODT), as published in MJP's and David Neubelt's Baking Lab,
 * BakingLab/ACES.hlsl (github.com/TheRealMJP/BakingLab, MIT licence): "ACES fitted" in Unity,
 * Godot and three.js (three.js adds an exposure of 1/0.6 in front; Hill's fit, used here as
 * published, does not). The input matrix is sRGB => XYZ => D65_2_D60 => AP1 => RRT_SAT, the
 * output matrix ODT_SAT => XYZ => D60_2_D65 => sRGB; between them each channel goes through
 *     fit(v) = (v (v + A) - B) / (v (C v + D) + E)
 * and the result is clamped to [0, 1]. */
#define VKRT_ACES_INPUT_ROW0 0.59719f, 0.35458f, 0.04823f
#define VKRT_ACES_INPUT_ROW1 0.07600f, 0.90834f, 0.01566f
#define VKRT_ACES_INPUT_ROW2 0.02840f, 0.13383f, 0.83777f
#define VKRT_ACES_OUTPUT_ROW0 1.60475f, -0.53108f, -0.07367f
#define VKRT_ACES_OUTPUT_ROW1 -0.10208f, 1.10813f, -0.00605f
#define VKRT_ACES_OUTPUT_ROW2 -0.00327f, -0.07276f, 1.07602f
#define VKRT_ACES_FIT_A 0.0245786f
#define VKRT_ACES_FIT_B 0.000090537f
#define VKRT_ACES_FIT_C 0.983729f
#define VKRT_ACES_FIT_D 0.4329510f
#define VKRT_ACES_FIT_E 0.238081f

/* AgX: Benjamin Wrensch's "Minimal AgX implementation" (iolite-engine.com/blog_posts/
 * minimal_agx_implementation, MIT licence), derived from Troy Sobotka's AgX OCIO configuration
 * (github.com/sobotka/AgX), with its default look (no look transform) and its 6th-order
 * polynomial sigmoid (mean squared error 3.67e-6 against Troy's curve). Per pixel:
 *   inset matrix; per channel log2, clamped to [MIN_EV, MAX_EV] (middle grey 0.18 at log2 0.18,
 *   10 stops below it and 6.5 above) and scaled to [0, 1]; the polynomial, whose result is
 *   display-encoded; the outset matrix (the inset's inverse); and the published display EOTF,
 *   x^2.2, back to linear display values for the sRGB encode. Negative values before the power
 *   are 0 (the published code leaves them to pow(), undefined there). The rows below are the
 *   rows of the published GLSL mat3s, which GLSL fills column by column. */
#define VKRT_AGX_INSET_ROW0 0.842479062253094f, 0.0784335999999992f, 0.0792237451477643f
#define VKRT_AGX_INSET_ROW1 0.0423282422610123f, 0.878468636469772f, 0.0791661274605434f
#define VKRT_AGX_INSET_ROW2 0.0423756549057051f, 0.0784336f, 0.879142973793104f
#define VKRT_AGX_OUTSET_ROW0 1.19687900512017f, -0.0980208811401368f, -0.0990297440797205f
#define VKRT_AGX_OUTSET_ROW1 -0.0528968517574562f, 1.15190312990417f, -0.0989611768448433f
#define VKRT_AGX_OUTSET_ROW2 -0.0529716355144438f, -0.0980434501171241f, 1.15107367264116f
#define VKRT_AGX_MIN_EV -12.47393f
#define VKRT_AGX_MAX_EV 4.026069f
/* log2's argument is at least this, so that a black channel has a logarithm (below MIN_EV: the
 * clamp makes it MIN_EV, as the published clamp of log2(0) = -inf does). */
#define VKRT_AGX_LOG_FLOOR 1e-10f
/* The sigmoid polynomial's coefficients, from x^6 down to x^0. */
#define VKRT_AGX_POLY6 15.5f
#define VKRT_AGX_POLY5 -40.14f
#define VKRT_AGX_POLY4 31.96f
#define VKRT_AGX_POLY3 -6.868f
#define VKRT_AGX_POLY2 0.4298f
#define VKRT_AGX_POLY1 0.1191f
#define VKRT_AGX_POLY0 -0.00232f
#define VKRT_AGX_DISPLAY_GAMMA 2.2f

#endif
