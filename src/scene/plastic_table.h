/*
 * plastic_table.h: the rough coat's numbers that Mitsuba 3's `roughplastic` (src/bsdfs/
 * roughplastic.cpp) tabulates, for vkrt's @roughplastic (glsl/lib/microfacet.glsl,
 * plastic_diffuse), which follows that model:
 * - T(cos): the GGX dielectric coat's transmittance into the plastic for light arriving at cos to
 *   the normal, the energy its visible microfacets refract and the refracted light's Smith
 *   masking lets through (Mitsuba's eval_transmittance, microfacet.h: single scattering, so it is
 *   below 1 - the coat's reflectance), at the VKRT_PLASTIC_COSINES cosines k / 63, k = 0..63 (the
 *   first at 1e-6), between which the shader interpolates linearly, as Mitsuba does;
 * - Ri: the coat's reflectance seen from inside (index 1 / eta, total internal reflection
 *   included) averaged over the same 64 cosines with the weight 2 cos: Mitsuba's
 *   `m_internal_reflectance`, a plain mean over those cosines (not the integral, which is about
 *   1.5% larger at a smooth coat, and Mitsuba's base is brighter for it).
 * The diffuse base of albedo kd is then kd / (pi eta^2 (1 - Ri)) T(cos_i) T(cos_o) cos_o.
 * The integrals over the visible normals are Gauss-Legendre rules in the two numbers that Heitz's
 * 2018 sampler (the shader's ggx_sample_visible) turns into a normal, as Mitsuba integrates them
 * in its own sampler's numbers; the two agree within 2e-4 (tests/test_microfacet.c holds the
 * picture to Mitsuba's albedo).
 * Pure CPU, no Vulkan.
 */
#ifndef VKRT_PLASTIC_TABLE_H
#define VKRT_PLASTIC_TABLE_H

#include "../../glsl/shared.h" /* VKRT_PLASTIC_COSINES, VKRT_PLASTIC_ROW_FLOATS: a row's layout */

/* Makes the quadrature rules the functions below use, once (later calls return at once; any
 * thread may call it); the functions below call it themselves. */
void vkrt_plastic_rules_init(void);

/* Fills row (VKRT_PLASTIC_ROW_FLOATS floats) for a GGX coat of alpha (roughness squared) and
 * relative index eta (not 1) over the base: Ri, then T(k / 63) for k = 0..63: 300 000
 * integrand evaluations, so callers with many rows spread them over threads. */
void vkrt_plastic_row(double alpha, double eta, float *row);

/* The row in pieces, for threads: vkrt_plastic_entry fills T at cosine k (row[1 + k]) and sets
 * *internal to cosine k's share of Ri; vkrt_plastic_finish, given all 64 shares, sets row[0]. */
void vkrt_plastic_entry(double alpha, double eta, int k, float *row, double *internal);
void vkrt_plastic_finish(float *row, const double *internal);

/* Cosine k of the table: k / 63, the first 1e-6. */
double vkrt_plastic_cosine(int k);

/* The coat's transmittance into the plastic at cos (above 0) and its reflectance for light
 * arriving at cos from the index-1 side, integrated as for the row (for the tests). */
double vkrt_plastic_transmittance(double cos_i, double alpha, double eta);
double vkrt_plastic_reflectance(double cos_i, double alpha, double eta);

#endif
