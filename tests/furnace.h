/*
 * furnace.h: what the white-furnace tests of the GGX built-ins share (test_microfacet.c,
 * test_coat.c): the microfacet model's Fresnel and Smith masking written again from the papers
 * (on purpose: not the shader's code), and the mean of a tile of their rendered pictures.
 */
#ifndef VKRT_TEST_FURNACE_H
#define VKRT_TEST_FURNACE_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "render/renderer.h"

typedef struct {
    double x, y, z;
} v3;

double dot3(v3 a, v3 b);

/* Fresnel reflectance of an unpolarised ray meeting a dielectric of relative index eta at
 * cos_i; 1 under total internal reflection. */
double fresnel(double cos_i, double eta);

/* Smith's G1 for GGX (Heitz 2014, "Understanding the Masking-Shadowing Function", eq. 72 with
 * 86): 2 / (1 + sqrt(1 + alpha^2 tan^2)); 0 where w sees the back of m. */
double smith_g1(v3 w, v3 m, double alpha);

/* A microfacet normal m of the integration grid, seen from o: o.m, the mirror direction r and
 * the direction t refracted into index eta (t.z = 0 under total internal reflection), and
 * `common` = G1(o) (o.m) / (o.z m.z). Times G1 of the outgoing direction and the Fresnel share,
 * common is f cos of a GGX lobe, with the Jacobian from m to that direction (Walter et al. 2007,
 * eq. 14 and 17: the (o.m) and eta terms cancel), over the grid's density D(m) cos(theta_m). */
typedef struct {
    v3 m, r, t;
    double om, common;
} furnace_facet;

/* The mean of term(facet, ctx) over an n x n midpoint grid of microfacet normals warped by GGX's
 * distribution of alpha (density D(m) cos(theta_m), so that the grid follows the lobe at any
 * roughness), the normals facing away from o left out: the integral of what term returns. */
double furnace_integrate(v3 o, double alpha, double eta, int n,
                         double (*term)(const furnace_facet *f, double alpha, void *ctx),
                         void *ctx);

/* The same integral on a grid denser towards grazing normals (u = 1 - s^2, s on the midpoint
 * grid): where the term does not vanish at grazing normals (light refracted by them, whose
 * `common` grows as 1 / cos(theta_m)), furnace_integrate's error falls as 1 / sqrt(n) only; here
 * as 1 / n. */
double furnace_integrate_tails(v3 o, double alpha, double eta, int n,
                               double (*term)(const furnace_facet *f, double alpha, void *ctx),
                               void *ctx);

/* Mitsuba 3's roughplastic (src/bsdfs/roughplastic.cpp, nonlinear false), written again from
 * its source: its base of albedo kd is kd / (pi eta^2 (1 - Ri)) T(cos_i) T(cos_o) cos_o, T the
 * rough coat's transmittance at 64 cosines k / 63 (the first 1e-6), interpolated linearly between
 * them, and Ri the coat's internal reflectance, a plain mean over the same cosines of 2 R(mu) mu.
 * furnace_plastic_coat integrates both over microfacet normals (furnace_integrate_tails, 100 x
 * 100, within 1e-5 of 160 x 160; not the renderer's Gauss-Legendre rule over visible normals): T
 * the refracted energy that the refracted light's masking lets through, R the reflected energy from
 * inside (index 1 / eta, total internal reflection included). 0.15 s a call. */
enum { FURNACE_PLASTIC_COSINES = 64 };
void furnace_plastic_coat(double alpha, double eta, double t[FURNACE_PLASTIC_COSINES], double *ri);

/* T at mu, linear between the cosines (Mitsuba's lerp_gather). */
double furnace_plastic_lerp(const double t[FURNACE_PLASTIC_COSINES], double mu);

/* Writes to obj the quad of tile (row, column) of a columns x rows layout, 1 wide (x) and 2 deep
 * (z) in the plane y = 0, facing +y (counter-clockwise seen from there), row 0 the farthest, with
 * `usemtl t<row><column>`. */
void furnace_write_tile(FILE *obj, int columns, int rows, int row, int column);

/* The same with tiles `depth` deep (z) instead of 2: 1 / cos of the furnace's viewing angle
 * makes them square in the picture at any angle (2 at cos 0.5). */
void furnace_write_tile_deep(FILE *obj, int columns, int rows, int row, int column, double depth);

/* Writes the scene folder's scene.cfg: tiles.obj with tiles.mat, path traced to depth 8 under an
 * environment of radiance 1, the camera 500 away at cos view_cos to the tiles' normal, its field
 * of view just the rows' depth, so that each tile is a square of pixels. */
void furnace_write_cfg(int rows, double view_cos);

/* The same with other lighting: `lighting` is scene.cfg lines (environment, lights) in place of
 * the environment of radiance 1. */
void furnace_write_cfg_lit(int rows, double view_cos, const char *lighting);

/* Renders the scene folder's scene.cfg (scene_dir.h) at columns x rows tiles of tile pixels,
 * spp samples per pixel, with the integrator and light sampling mode given; fails the test where
 * it cannot, or where a pixel is not finite. The RGB floats, malloc'd. */
float *furnace_render(int columns, int rows, int tile, uint32_t spp, vkrt_integrator integrator,
                      uint32_t mode);

/* Mean and standard error of the channel average of tile (row, column), tile pixels square, of
 * an RGB image `columns` tiles wide, leaving out `margin` pixels at each edge. */
void furnace_tile_mean(const float *rgb, int columns, int tile, int margin, int row, int column,
                       double *mean, double *se);

/* Whether tile (row, column)'s picture mean agrees with what the integral expects: within 4
 * standard errors of its pixels and 0.003 (the perspective's spread of the viewing angle over a
 * tile, which the integral at the tile's centre does not see). Prints how far off it is where
 * it is not. */
bool furnace_tile_agrees(double mean, double se, double expected, int row, int column);

#endif
