/*
 * test_sheen.c: the sheen of the rough built-ins (glsl/lib/microfacet.glsl, "The sheen": the
 * .mtl's Ps, Disney's sheen as Mitsuba 3's principled has it) in a white furnace, against its
 * albedo integrated numerically on the CPU.
 *
 * The furnace is tests/test_coat.c's: flat tiles under a uniform environment of radiance 1, seen
 * at one grazing angle (cos 0.2, where the sheen is strong), so that each tile shows its BSDF's
 * directional albedo there. The tiles: the sheen alone (a black @roughplastic of index 1, which
 * has no lobe of its own) of weight 0.5 and 1, beside a white Lambertian (@roughplastic with Ks 0
 * and Ni 1), through the .mtl (pbr with Ps 1 over a black base), and beside a grey Lambertian
 * under a smooth clear coat (the sheen is part of the base the coat covers).
 *
 * The reference writes the lobe again from its description (docs/materials.md), not from the
 * shader: f cos = w (1 - i.h)^5 cos_i, integrated over the hemisphere on a grid; the coat's
 * smooth Fresnel both ways and 1 / (1 - Fdr) as test_coat.c has them. A sheen left out, doubled,
 * or of another shape, moves a tile by more than the tolerance (the sheen alone is 0.048 at
 * weight 1); a pdf that does not match the sampling moves the MIS render or the one with light
 * samples alone (which sees bsdf_eval only). Whitted's rough built-ins see the ambient light
 * through the sheen's albedo (a fitted polynomial in the shader): a second render under ambient
 * light alone holds that fit to the integral. It prints the sheen's albedo at several angles.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>

#include <cmocka.h>

#include "../glsl/shared.h"
#include "furnace.h"
#include "render/renderer.h"
#include "scene_dir.h"

/* ---- The sheen, written again from its description ----------------------------------------- */

static const double coat_eta = 1.5;

/* int g(i) w (1 - i.h)^5 cos_i di over the hemisphere about z, for the viewer at cosine mu:
 * g the coat's transmission 1 - F(cos_i) where `coated`, else 1. A midpoint grid in (cos_i, phi),
 * 400 x 800: the integrand is smooth, and the grid is within 1e-5 of a finer one. */
static double sheen_albedo(double mu, double w, bool coated)
{
    const int n = 400;
    const double pi = 3.14159265358979323846;
    v3 o = {sqrt(1 - mu * mu), 0, mu};
    double sum = 0;
    for (int a = 0; a < n; ++a) {
        double c = (a + 0.5) / n, s = sqrt(1 - c * c);
        for (int b = 0; b < 2 * n; ++b) {
            double phi = 2 * pi * (b + 0.5) / (2 * n);
            v3 i = {s * cos(phi), s * sin(phi), c};
            v3 h = {o.x + i.x, o.y + i.y, o.z + i.z};
            double len = sqrt(dot3(h, h));
            double x = 1 - dot3(i, h) / len;
            double g = coated ? 1 - fresnel(c, coat_eta) : 1;
            sum += g * w * x * x * x * x * x * c;
        }
    }
    return sum * 2 * pi / ((double)n * 2 * n); /* d(cos) d(phi) over 1 x 2 pi */
}

/* The coat's hemispherical Fresnel Fdr = 2 int_0^1 F(mu) mu dmu and int T(i) cos_i / pi di (the
 * same integral with 1 - F), by a 4000-point midpoint rule. */
static double coat_fdr(void)
{
    const int n = 4000;
    double sum = 0;
    for (int k = 0; k < n; ++k) {
        double mu = (k + 0.5) / n;
        sum += fresnel(mu, coat_eta) * mu;
    }
    return 2 * sum / n;
}

/* ---- The furnace ---------------------------------------------------------------------------- */

enum { COLUMNS = 5, ROWS = 1, TILE = 16, MARGIN = 2, SPP = 64 };
static const double view_cos = 0.2;

/* Material-file lines (numbers in the .mtl layout; 20 the sheen) or .mtl blocks of the tiles. */
static const char *const tile_line[COLUMNS] = {
    "@roughplastic 0 0 0 0  0 0 0 0  0 0 0  1  0 0 0  0  0  0  0 0  0.5",
    "@roughplastic 0 0 0 0  0 0 0 0  0 0 0  1  0 0 0  0  0  0  0 0  1",
    "@roughplastic 1 1 1 0  0 0 0 0  0 0 0  1  0 0 0  0  0  0  0 0  1",
    NULL, /* the .mtl's */
    "@roughplastic 0.5 0.5 0.5 0  0 0 0 0  0 0 0  1  0 0 0  0  0  0  1 0  1",
};
static const char *const mtl_block = "Kd 0 0 0\nPr 0.5\nNi 1.0001\nPs 1\n";
static const char *const names[COLUMNS] = {"sheen 0.5", "sheen 1", "Lambertian 1 + sheen 1",
                                           ".mtl Ps 1", "0.5 + sheen 1, coat"};
static const double sheen_weight[COLUMNS] = {0.5, 1, 1, 1, 1};
static const double kd[COLUMNS] = {0, 0, 1, 0, 0.5};
static const bool coat[COLUMNS] = {false, false, false, false, true};

static void write_tiles(void)
{
    FILE *obj = scene_dir_open("tiles.obj");
    FILE *mtl = scene_dir_open("tiles.mtl");
    FILE *mat = scene_dir_open("tiles.mat");
    fprintf(obj, "mtllib tiles.mtl\n");
    for (int column = 0; column < COLUMNS; ++column) {
        furnace_write_tile_deep(obj, COLUMNS, ROWS, 0, column, 1 / view_cos);
        fprintf(mtl, "newmtl t0%d\n%s", column, tile_line[column] ? "" : mtl_block);
        if (tile_line[column])
            fprintf(mat, "t0%d 0 %s\n", column, tile_line[column]);
    }
    fclose(obj);
    fclose(mtl);
    fclose(mat);
}

/* What tile `column` shows under the environment of radiance 1 (ambient: under ambient light of
 * radiance 1 in Whitted's model, where the diffuse base and the sheen see it through their
 * albedo and the coat's transmission at the viewer). */
static double expected(int column, bool ambient)
{
    double mu = view_cos, w = sheen_weight[column];
    if (!coat[column])
        return kd[column] + sheen_albedo(mu, w, false);
    double t = 1 - fresnel(mu, coat_eta);
    if (ambient)
        return (kd[column] + sheen_albedo(mu, w, false)) * t;
    /* The smooth coat's mirror F(mu), and the base (Lambertian and sheen) under its Fresnel
     * transmission both ways over 1 - Fdr: int T(i) cos_i / pi di = 1 - Fdr. */
    double fdr = coat_fdr();
    return fresnel(mu, coat_eta) +
           t * (kd[column] * (1 - fdr) + sheen_albedo(mu, w, true)) / (1 - fdr);
}

/* Every tile against the integral, within 4 standard errors of its pixels and 0.003; with light
 * samples alone not the smooth coat (a delta lobe is never found by a light sample). */
static bool furnace_agrees(vkrt_integrator integrator, uint32_t mode, bool ambient)
{
    float *rgb = furnace_render(COLUMNS, ROWS, TILE, SPP, integrator, mode);
    bool all = true;
    for (int column = 0; column < COLUMNS; ++column) {
        if (mode == VKRT_SAMPLING_LIGHTS && coat[column])
            continue;
        double mean, se, want = expected(column, ambient);
        furnace_tile_mean(rgb, COLUMNS, TILE, MARGIN, 0, column, &mean, &se);
        print_message("%-24s: picture %.5f, integral %.5f (+- %.5f)\n", names[column], mean, want,
                      4 * se);
        all &= furnace_tile_agrees(mean, se, want, 0, column);
    }
    free(rgb);
    return all;
}

/* The sheen's directional albedo per unit weight, by the integral: what it adds to a base. */
static void print_sheen_energy(void)
{
    static const double mus[] = {1.0, 0.8, 0.5, 0.2, 0.05};
    char line[256];
    int n = snprintf(line, sizeof line, "sheen 1 adds at cos");
    for (size_t a = 0; a < sizeof mus / sizeof *mus; ++a)
        n += snprintf(line + n, sizeof line - (size_t)n, " %.2f: %.4f", mus[a],
                      sheen_albedo(mus[a], 1, false));
    print_message("%s\n", line);
}

static void white_furnace_sheen(void **state)
{
    (void)state;
    write_tiles();
    print_sheen_energy();
    furnace_write_cfg(ROWS, view_cos);
    print_message("MIS:\n");
    bool mis = furnace_agrees(VKRT_INTEGRATOR_PATH, VKRT_SAMPLING_MIS, false);
    print_message("light samples alone:\n");
    bool lights = furnace_agrees(VKRT_INTEGRATOR_PATH, VKRT_SAMPLING_LIGHTS, false);
    furnace_write_cfg_lit(ROWS, view_cos, "environment 0 0 0\nlight ambient 1 1 1\n");
    print_message("whitted, ambient light:\n");
    bool whitted = furnace_agrees(VKRT_INTEGRATOR_WHITTED, VKRT_SAMPLING_MIS, true);
    assert_true(mis && lights && whitted);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(white_furnace_sheen),
    };
    return cmocka_run_group_tests(tests, scene_dir_make, scene_dir_remove);
}
