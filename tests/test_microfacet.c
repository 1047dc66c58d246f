/*
 * test_microfacet.c: the GGX built-ins (glsl/lib/microfacet.glsl: roughconductor, roughplastic,
 * roughdielectric) in a white furnace, against their albedo integrated numerically on the CPU.
 *
 * The furnace: flat tiles of the materials in one plane under a uniform environment of radiance
 * 1, seen from far away at one angle (cos 0.5 to the normal), so that every pixel of a tile
 * shows its BSDF's directional albedo at that angle: what it reflects (and, for glass, lets
 * through from the environment behind) of a uniform radiance. A plane never sees itself, so one
 * bounce is the whole answer.
 *
 * The reference: the same albedo as an integral over microfacet normals, by a midpoint rule on
 * a grid warped by GGX's own cumulative distribution (no sampling, no shader code): the test
 * writes the model's formulas again in C, from the papers (Walter et al. 2007, Heitz 2014 and
 * 2018), and checks the renderer against them. It prints the energy each BSDF loses: single
 * scattering drops the light that would bounce again between microfacets. The plastic is
 * Mitsuba 3's roughplastic (its base under the rough coat's tabulated transmittance, furnace.h),
 * and its integral is held to Mitsuba's own albedo as well; a row of more plastics checks a
 * roughness map (the table's rows of roughness), another index and a smooth coat.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "../glsl/shared.h"
#include "render/renderer.h"
#include "furnace.h"
#include "scene_dir.h"

/* ---- The model, written again from the papers (on purpose: not the shader's code) ----------- */

enum bsdf { CONDUCTOR, PLASTIC, DIELECTRIC };

/* What albedo integrates for one microfacet normal: the reflected energy, plus the glass's
 * transmitted energy in full, while *seen (ctx) gathers what the picture shows (transmission
 * carrying radiance, 1 / eta^2). */
typedef struct {
    enum bsdf kind;
    double eta, seen;
} albedo_term_ctx;

static double albedo_term(const furnace_facet *f, double alpha, void *ctx)
{
    albedo_term_ctx *c = ctx;
    double fr = c->kind == CONDUCTOR ? 1 : fresnel(f->om, c->eta);
    double reflected = f->r.z > 0 ? fr * smith_g1(f->r, f->m, alpha) * f->common : 0;
    double through = 0;
    if (c->kind == DIELECTRIC && fr < 1 && f->t.z < 0)
        through = (1 - fr) * smith_g1(f->t, f->m, alpha) * f->common;
    c->seen += reflected + through / (c->eta * c->eta);
    return reflected + through;
}

/* ---- Mitsuba's roughplastic ---------------------------------------------------------------- */

/* The base's albedo for Kd 1 seen at mu (furnace.h, furnace_plastic_coat): T(mu) / (eta^2
 * (1 - Ri)) times the integral of T(mu_i) 2 mu_i over the cosines of the light, by a 4000-point
 * midpoint rule. */
static double plastic_base_albedo(double mu, double alpha, double eta)
{
    const int n = 4000;
    double t[FURNACE_PLASTIC_COSINES], ri, sum = 0;
    furnace_plastic_coat(alpha, eta, t, &ri);
    for (int k = 0; k < n; ++k) {
        double mu_i = (k + 0.5) / n;
        sum += furnace_plastic_lerp(t, mu_i) * mu_i;
    }
    return furnace_plastic_lerp(t, mu) / (eta * eta * (1 - ri)) * 2 * sum / n;
}

/* Mitsuba 3.9.1's roughplastic albedo at cos 0.5 (Kd 1, Ni 1.5, GGX alpha = roughness^2), by
 * 2^24 of its own BSDF samples (standard error 3e-5): tools/rough_spheres.py --plastic-albedo
 * prints them from 2^20. */
static const double mitsuba_plastic_albedo[4] = {0.98194, 0.96544, 0.72467, 0.25984};

/* The directional albedo at o (o.z = mu) of the white BSDF: F0 = 1 conductor, plastic of Kd 1
 * and a plain coat (Mitsuba's roughplastic), glass of eta; for glass, *seen is what the picture
 * shows: reflection plus transmission carrying radiance (1 / eta^2), and the return value counts
 * the transmitted energy in full. Integrated over microfacet normals (furnace_integrate,
 * 600 x 600). */
static double albedo(enum bsdf kind, double mu, double alpha, double eta, double *seen)
{
    const int n = 600;
    v3 o = {sqrt(1 - mu * mu), 0, mu};
    albedo_term_ctx ctx = {kind, eta, 0};
    double sum = furnace_integrate(o, alpha, eta, n, albedo_term, &ctx);
    double sum_seen = ctx.seen / ((double)n * n);
    if (kind == PLASTIC) {
        double base = plastic_base_albedo(mu, alpha, eta);
        sum += base;
        sum_seen += base;
    }
    if (seen)
        *seen = sum_seen;
    return sum;
}

/* The smooth-Fresnel plastic of @pbr's non-metal share: its base returns all the coat lets in,
 * 1 - F(mu) (the shader's normalisation by the average Fresnel reflectance is exactly that). */
static double pbr_plastic_albedo(double mu, double alpha, double eta)
{
    albedo_term_ctx ctx = {PLASTIC, eta, 0};
    const int n = 600;
    v3 o = {sqrt(1 - mu * mu), 0, mu};
    furnace_integrate(o, alpha, eta, n, albedo_term, &ctx);
    return ctx.seen / ((double)n * n) + 1 - fresnel(mu, eta);
}

/* ---- The furnace ---------------------------------------------------------------------------- */

enum { COLUMNS = 3, ROWS = 7, TILE = 16, MARGIN = 2, SPP = 64 };
static const double view_cos = 0.5, eta = 1.5;
static const double roughness[4] = {0.05, 0.2, 0.5, 1.0};
/* Row 4: smooth glass, rough glass of roughness 0 (the smooth one by another name) and of 0.03
 * (GGX, just above the delta lobe's limit of 0.02). */
static const char *const last_row[COLUMNS] = {
    "@glass 0 0 0 0  0 0 0 0  0 0 0  1.5",
    "@roughdielectric 0 0 0 0  0 0 0 0  0 0 0  1.5  0 0 0  0  0",
    "@roughdielectric 0 0 0 0  0 0 0 0  0 0 0  1.5  0 0 0  0  0.03",
};

/* Row 5: the .mtl's PBR extension through the pbr built-in: a metal of Pr 0.5; a plastic whose
 * roughness is a map of 128/255 (data, not sRGB-decoded); a metal without Pr whose Ns 30 makes
 * roughness (2 / 32)^(1/4) = 0.5 (materials.h, vkrt_ns_roughness). */
static const char *const mtl_row[COLUMNS] = {
    "Kd 1 1 1\nPr 0.5\nPm 1\n",
    "Kd 1 1 1\nNi 1.5\nPm 0\nPr 0.9\nmap_Pr grey.tga\n",
    "Kd 1 1 1\nKs 0.5 0.5 0.5\nNs 30\nPm 1\n",
};
static const double mtl_row_roughness[COLUMNS] = {0.5, 128.0 / 255.0, 0.5};

/* Row 6: more @roughplastic, tabulated otherwise: a roughness map (grey.tga, read as a colour:
 * the sRGB curve makes 128 a roughness of 0.2158; the shader interpolates between the rows of
 * roughness 6/32 and 7/32 of a table of 33), an index of 1.3 at roughness 0.35, and a smooth
 * coat (roughness 0.01, below the delta limit of 0.02: Mitsuba's smooth `plastic`, which for
 * Kd 1 returns everything, F + (1 - F)). */
static const char *const plastic_row[COLUMNS] = {
    "3 white.tga white.tga grey.tga @roughplastic 1 1 1 0  1 1 1 0  0 0 0  1.5  0 0 0  0  1",
    "0 @roughplastic 1 1 1 0  1 1 1 0  0 0 0  1.3  0 0 0  0  0.35",
    "0 @roughplastic 1 1 1 0  1 1 1 0  0 0 0  1.5  0 0 0  0  0.01",
};
static const double plastic_row_eta[COLUMNS] = {1.5, 1.3, 1.5};

/* The roughness of row 6's tiles: the sRGB curve (IEC 61966-2-1) at 128 / 255, 0.35, 0.01. */
static double plastic_row_roughness(int column)
{
    double c = 128.0 / 255.0;
    return column == 0 ? pow((c + 0.055) / 1.055, 2.4) : column == 1 ? 0.35 : 0.01;
}

/* The material file line of tile (row, column). */
static void tile_material(int row, int column, char *line, size_t size)
{
    static const char *const shaders[COLUMNS] = {
        "@roughconductor 0 0 0 0  1 1 1 0  0 0 0  0  0 0 0  0",
        "@roughplastic 1 1 1 0  1 1 1 0  0 0 0  1.5  0 0 0  0",
        "@roughdielectric 0 0 0 0  0 0 0 0  0 0 0  1.5  0 0 0  0",
    };
    if (row < 4)
        snprintf(line, size, "t%d%d 0 %s  %g\n", row, column, shaders[column], roughness[row]);
    else if (row == 4)
        snprintf(line, size, "t%d%d 0 %s\n", row, column, last_row[column]);
    else if (row == 6)
        snprintf(line, size, "t%d%d %s\n", row, column, plastic_row[column]);
    else
        line[0] = '\0'; /* the .mtl's */
}

/* Writes the tiles' scene: tile (row, column) is 1 wide (x) and 2 deep (z) in the plane y = 0,
 * facing +y, row 0 the farthest; the camera 500 away at cos 0.5 to the normal sees each as a
 * square of TILE pixels. */
static void write_tiles(void)
{
    FILE *obj = scene_dir_open("tiles.obj");
    FILE *mtl = scene_dir_open("tiles.mtl");
    FILE *mat = scene_dir_open("tiles.mat");
    fprintf(obj, "mtllib tiles.mtl\n");
    for (int row = 0; row < ROWS; ++row)
        for (int column = 0; column < COLUMNS; ++column) {
            furnace_write_tile(obj, COLUMNS, ROWS, row, column);
            fprintf(mtl, "newmtl t%d%d\n%s", row, column, row == 5 ? mtl_row[column] : "");
            char line[256];
            tile_material(row, column, line, sizeof line);
            fputs(line, mat);
        }
    fclose(obj);
    fclose(mtl);
    fclose(mat);
    /* A 1 x 1 8-bit grey TGA of 128: the roughness map. */
    FILE *tga = scene_dir_open("grey.tga");
    const unsigned char grey[19] = {0, 0, 3, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 1, 0, 8, 0x20, 128};
    fwrite(grey, 1, sizeof grey, tga);
    fclose(tga);
    /* And one of 255: row 6's map_Kd and map_d, which leave Kd and the coverage as they are. */
    tga = scene_dir_open("white.tga");
    const unsigned char white[19] = {0, 0, 3, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 1, 0, 8, 0x20, 255};
    fwrite(white, 1, sizeof white, tga);
    fclose(tga);
    furnace_write_cfg(ROWS, view_cos);
}

/* The albedo (returned: the energy, the transmitted counted in full) and what the picture shows
 * (*seen) of tile (row, column) of the first four rows, integrated once and kept (a plastic's
 * takes 0.3 s; the run with light samples alone needs it again). */
static double tile_albedo(int row, int column, double *seen)
{
    static double energy[4][COLUMNS], shown[4][COLUMNS];
    static bool done[4][COLUMNS];
    if (!done[row][column]) {
        double alpha = roughness[row] * roughness[row];
        energy[row][column] = albedo((enum bsdf)column, view_cos, alpha, eta, &shown[row][column]);
        done[row][column] = true;
    }
    *seen = shown[row][column];
    return energy[row][column];
}

/* What row 6's rough tiles show, integrated once. */
static double plastic_row_albedo(int column)
{
    static double shown[COLUMNS];
    static bool done[COLUMNS];
    if (!done[column]) {
        double r = plastic_row_roughness(column);
        albedo(PLASTIC, view_cos, r * r, plastic_row_eta[column], &shown[column]);
        done[column] = true;
    }
    return shown[column];
}

/* Every tile's picture, rendered with the sampling `mode`, against the albedo the CPU
 * integrates, within 4 standard errors of its pixels and 0.003 (the perspective's spread of the
 * viewing angle over a tile, which the integral at the tile's centre does not see); rows of
 * roughness below min_roughness are not checked. Prints the energy each BSDF loses. */
static bool furnace_agrees(vkrt_integrator integrator, uint32_t mode, double min_roughness)
{
    bool whitted = integrator == VKRT_INTEGRATOR_WHITTED;
    float *rgb = furnace_render(COLUMNS, ROWS, TILE, SPP, integrator, mode);
    static const char *const names[COLUMNS] = {"conductor F0=1", "plastic Kd=1", "dielectric 1.5"};
    bool all = true;
    for (int row = 0; row < ROWS; ++row) {
        if (row < 4 ? roughness[row] < min_roughness : (row == 4 || row == 6) && min_roughness > 0)
            continue; /* light samples alone cannot find a narrow lobe, nor a delta one */
        if (row == 6 && whitted)
            continue; /* the plastics (below) */
        for (int column = 0; column < COLUMNS; ++column) {
            /* Whitted's diffuse surfaces see lights, not the environment: not the plastics. */
            if (whitted && column == 1)
                continue;
            double mean, se, seen, energy;
            furnace_tile_mean(rgb, COLUMNS, TILE, MARGIN, row, column, &mean, &se);
            if (row < 4) {
                energy = tile_albedo(row, column, &seen);
                print_message("%-15s roughness %.2f: picture %.5f, integral %.5f (+- %.5f); "
                              "energy lost at cos 0.5: %.2f%%\n",
                              names[column], roughness[row], mean, seen, 4 * se,
                              100 * (1 - energy));
                if (column == 1) {
                    /* The integral is Mitsuba's model: it must give Mitsuba's numbers. */
                    double mitsuba = mitsuba_plastic_albedo[row];
                    print_message("%-15s roughness %.2f: Mitsuba's roughplastic %.5f\n", "",
                                  roughness[row], mitsuba);
                    all &= fabs(seen - mitsuba) < 0.002;
                }
            } else if (row == 6) {
                double r = plastic_row_roughness(column);
                seen = column == 2 ? 1 : plastic_row_albedo(column);
                print_message("plastic Kd=1 Ni %.1f roughness %.4f%s: picture %.5f, integral %.5f "
                              "(+- %.5f)\n",
                              plastic_row_eta[column], r, column == 0 ? " (map)" : "", mean, seen,
                              4 * se);
            } else if (row == 5) {
                double r = mtl_row_roughness[column];
                if (column == 1)
                    seen = pbr_plastic_albedo(view_cos, r * r, eta);
                else
                    albedo(CONDUCTOR, view_cos, r * r, eta, &seen);
                print_message(".mtl pbr %s, roughness %.3f: picture %.5f, expected %.5f "
                              "(+- %.5f)\n",
                              column == 1 ? "plastic (map_Pr)" : "metal", r, mean, seen, 4 * se);
            } else {
                double f = fresnel(view_cos, eta);
                seen = f + (1 - f) / (eta * eta); /* the smooth interface, in closed form */
                /* Whitted's @glass weighs its refracted ray by 1 - F alone, without the radiance's
                 * 1 / eta^2 (on the way out of a closed solid the two conventions meet again). */
                if (whitted && column == 0)
                    seen = 1;
                if (column == 2)
                    albedo(DIELECTRIC, view_cos, 0.03 * 0.03, eta, &seen);
                print_message("%-36s: picture %.5f, expected %.5f (+- %.5f)\n", last_row[column],
                              mean, seen, 4 * se);
            }
            all &= furnace_tile_agrees(mean, se, seen, row, column);
        }
    }
    free(rgb);
    return all;
}

/* The furnace with MIS (light samples of the environment and BSDF samples: a sampler that does
 * not draw by bsdf_eval's pdf, or a wrong value, moves a tile), then with light samples alone on
 * the rough rows (0.5 and 1, where uniform directions find the lobe often enough): that one
 * sees bsdf_eval's value without its pdf, so an error common to both, which the weight f / pdf
 * of a BSDF sample cancels, shows there. Then Whitted's: its one glossy ray per hit, sampled
 * from the BSDF, must bring the conductors and glasses the same energy. */
static void white_furnace_tiles(void **state)
{
    (void)state;
    write_tiles();
    print_message("MIS:\n");
    bool mis = furnace_agrees(VKRT_INTEGRATOR_PATH, VKRT_SAMPLING_MIS, 0);
    print_message("light samples alone:\n");
    bool lights = furnace_agrees(VKRT_INTEGRATOR_PATH, VKRT_SAMPLING_LIGHTS, 0.5);
    print_message("whitted:\n");
    bool whitted = furnace_agrees(VKRT_INTEGRATOR_WHITTED, VKRT_SAMPLING_MIS, 0);
    assert_true(mis && lights && whitted);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(white_furnace_tiles),
    };
    return cmocka_run_group_tests(tests, scene_dir_make, scene_dir_remove);
}
