/*
 * test_coat.c: the clear coat of the GGX built-ins (glsl/lib/microfacet.glsl, "The clear coat":
 * Blender's Principled coat, the .mtl's Pc and Pcr) in a white furnace, against the albedo of
 * the layer model integrated numerically on the CPU.
 *
 * The furnace is tests/test_microfacet.c's: flat tiles under a uniform environment of radiance 1,
 * seen at one angle (cos 0.5), so that each tile shows its BSDF's directional albedo there. The
 * tiles: a coat of weight 1 at roughness 0.05, 0.2 and 0.5, of weight 0.5 at 0.2, and a smooth
 * one (roughness 0, a delta lobe), over four white bases of roughness 0.5: a conductor of F0 1,
 * a Lambertian (@roughplastic with Ks 0 and Ni 1: no coat of its own), a plastic (Kd 1 under its
 * own coat of index 1.5: Mitsuba's roughplastic, furnace.h) and a glass of index 1.5; and over a
 * black base, where the picture is the coat's reflection alone (the white bases are nearly as
 * bright with as without a coat at this angle: the model conserves energy). A row of .mtl materials
 * takes Pc and Pcr through the pbr and roughdielectric built-ins (Blender's Coat Weight = Pc / 4).
 *
 * The reference writes the layer model again from its description (docs/materials.md), not from
 * the shader: the coat's reflection w F(i.h) D G / (4 cos_o), the base under it scaled by
 * (1 - w F(cos_o)) (1 - w F(cos_i)) / (1 - w Fdr) (Fdr integrated here, not the shader's
 * constant), a glass's reflection by both transmissions and its transmission by one; integrated
 * over microfacet normals on a grid warped by GGX's distribution (test_microfacet.c's method).
 * A missing coat, a coat of the wrong weight, index or roughness, a base attenuated one way only,
 * or a pdf that does not match the sampling (the light-samples-only run sees bsdf_eval alone)
 * moves a tile by more than the tolerance. It prints, by the integral, the energy the coat adds
 * to or takes from each base's at four viewing angles.
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

/* ---- The layer model, written again from its description ------------------------------------ */

static const double coat_eta = 1.5, base_eta = 1.5, base_roughness = 0.5;

/* The plastic base's rough coat (furnace.h, furnace_plastic_coat: Mitsuba's roughplastic), its
 * transmittance at the 64 cosines and internal reflectance, integrated once. */
static const double *plastic_coat(double *ri)
{
    static double t[FURNACE_PLASTIC_COSINES], internal;
    static bool done;
    if (!done)
        furnace_plastic_coat(base_roughness * base_roughness, base_eta, t, &internal);
    done = true;
    *ri = internal;
    return t;
}

/* 2 int_0^1 g(mu) mu dmu by a 4000-point midpoint rule; g of the kind asked: the coat's
 * Fresnel (0: Fdr), or the plastic's transmission times the coat's (1: the rough coat's T,
 * Mitsuba's roughplastic; 2: the smooth coat's 1 - F, @pbr's). */
static double hemispherical(int kind, double w)
{
    const int n = 4000;
    double ri, sum = 0;
    const double *t = kind == 1 ? plastic_coat(&ri) : NULL;
    for (int k = 0; k < n; ++k) {
        double mu = (k + 0.5) / n;
        double g = kind == 0   ? fresnel(mu, coat_eta)
                   : kind == 1 ? furnace_plastic_lerp(t, mu) * (1 - w * fresnel(mu, coat_eta))
                               : (1 - fresnel(mu, base_eta)) * (1 - w * fresnel(mu, coat_eta));
        sum += g * mu;
    }
    return 2 * sum / n;
}

enum base { CONDUCTOR, LAMBERT, PLASTIC, GLASS, BLACK, COLUMNS, PBR_PLASTIC = COLUMNS };

typedef struct {
    double w;     /* coat weight */
    double alpha; /* coat GGX alpha */
} coat;

static double transmission(coat c, double cos_t)
{
    return 1 - c.w * fresnel(fabs(cos_t), coat_eta);
}

/* What coated_albedo integrates for one microfacet normal: the coat's reflection (pass 0) or
 * the base's lobes under the coat's transmissions (pass 1), all energy returned, what the picture
 * shows (a glass's transmitted radiance carries 1 / eta^2) gathered in seen. */
typedef struct {
    enum base kind;
    coat c;
    int pass;
    double to, inside, seen;
} coat_term_ctx;

static double coat_term(const furnace_facet *f, double alpha, void *ctx)
{
    coat_term_ctx *x = ctx;
    double g_r = f->r.z > 0 ? smith_g1(f->r, f->m, alpha) * f->common : 0;
    double term;
    if (x->pass == 0)
        term = x->c.w * fresnel(f->om, coat_eta) * g_r;
    else if (x->kind == CONDUCTOR)
        term = g_r * x->to * transmission(x->c, f->r.z) / x->inside;
    else if (x->kind == PLASTIC || x->kind == PBR_PLASTIC)
        term = fresnel(f->om, base_eta) * g_r * x->to * transmission(x->c, f->r.z) / x->inside;
    else
        term = fresnel(f->om, base_eta) * g_r * x->to * transmission(x->c, f->r.z);
    x->seen += term;
    if (x->pass == 1 && x->kind == GLASS && f->t.z < 0) {
        double through =
            (1 - fresnel(f->om, base_eta)) * smith_g1(f->t, f->m, alpha) * f->common * x->to;
        term += through;
        x->seen += through / (base_eta * base_eta);
    }
    return term;
}

/* The directional albedo at mu of base `kind` under coat c: *seen is what the picture shows, the
 * return value counts all energy. The microfacet lobes by furnace_integrate (500 x 500), the
 * diffuse bases' by hemispherical. */
static double coated_albedo(enum base kind, coat c, double mu, double *seen)
{
    const int n = 500;
    v3 o = {sqrt(1 - mu * mu), 0, mu};
    double fdr = hemispherical(0, 0); /* the coat's */
    coat_term_ctx x = {kind, c, 0, transmission(c, mu), 1 - c.w * fdr, 0};
    double energy = 0, shown = 0;
    if (c.alpha == 0) {
        energy = shown = c.w * fresnel(mu, coat_eta); /* the smooth coat's mirror */
    } else {
        energy = furnace_integrate(o, c.alpha, coat_eta, n, coat_term, &x);
        shown = x.seen / ((double)n * n);
    }
    if (kind != LAMBERT && kind != BLACK) {
        x.pass = 1;
        x.seen = 0;
        energy += furnace_integrate(o, base_roughness * base_roughness, base_eta, n, coat_term, &x);
        shown += x.seen / ((double)n * n);
    }
    if (kind == LAMBERT || kind == PLASTIC || kind == PBR_PLASTIC) {
        /* The diffuse base: Kd / (pi eta^2 (1 - Ri)) T(o) T(i) for the plastic, Kd / pi
         * (1 - F_b(o)) (1 - F_b(i)) / (1 - Fdr_b) for @pbr's (Kd / pi for the Lambertian), under
         * the coat's two transmissions and 1 / (1 - w Fdr). */
        double d = x.to * (1 - c.w * fdr) / x.inside;
        if (kind == PLASTIC) {
            double ri;
            const double *t = plastic_coat(&ri);
            d = furnace_plastic_lerp(t, mu) * x.to * hemispherical(1, c.w) /
                (base_eta * base_eta * (1 - ri) * x.inside);
        } else if (kind == PBR_PLASTIC) {
            /* Both of index 1.5: Fdr_b is the coat's. */
            d = (1 - fresnel(mu, base_eta)) * x.to * hemispherical(2, c.w) / ((1 - fdr) * x.inside);
        }
        energy += d;
        shown += d;
    }
    if (seen)
        *seen = shown;
    return energy;
}

/* ---- The furnace ---------------------------------------------------------------------------- */

enum { ROWS = 6, TILE = 16, MARGIN = 2, SPP = 64 };
static const double view_cos = 0.5;
/* Rows 0-4: (weight, roughness) of the coat over the four bases. */
static const coat row_coat[5] = {
    {1, 0.05 * 0.05}, {1, 0.2 * 0.2}, {1, 0.5 * 0.5}, {0.5, 0.2 * 0.2}, {1, 0}};
static const double row_roughness[5] = {0.05, 0.2, 0.5, 0.2, 0};
static const char *const base_line[COLUMNS] = {
    "@roughconductor 0 0 0 0  1 1 1 0  0 0 0  0    0 0 0  0  0.5  0",
    "@roughplastic   1 1 1 0  0 0 0 0  0 0 0  1    0 0 0  0  0  0",
    "@roughplastic   1 1 1 0  1 1 1 0  0 0 0  1.5  0 0 0  0  0.5  0",
    "@roughdielectric 0 0 0 0  0 0 0 0  0 0 0  1.5  0 0 0  0  0.5  0",
    "@roughplastic   0 0 0 0  0 0 0 0  0 0 0  1    0 0 0  0  0  0",
};
static const char *const names[COLUMNS] = {"conductor F0=1", "Lambertian Kd=1", "plastic Kd=1",
                                           "glass 1.5", "black"};
/* Row 5: the .mtl's Pc (Coat Weight Pc / 4) and Pcr: a metal (pbr, Kd as F0) under a half coat;
 * a plastic under a full one; a plastic made pbr by Pc alone (roughness from Ns 30: 0.5); a
 * rough glass (illum 7 with Pr). */
static const char *const mtl_row[COLUMNS] = {
    "Kd 1 1 1\nPm 1\nPr 0.5\nPc 2\nPcr 0.2\n",
    "Kd 1 1 1\nPm 0\nPr 0.5\nPc 4\nPcr 0.2\n",
    "Kd 1 1 1\nKs 0.5 0.5 0.5\nNs 30\nPc 4\nPcr 0.5\n",
    "Ni 1.5\nillum 7\nPr 0.5\nPc 4\nPcr 0.2\n",
    "Kd 0 0 0\nPm 0\nPr 0.5\nNi 1.0001\nPc 1\nPcr 0.05\n",
};
static const char *const mtl_names[COLUMNS] = {"metal, Pc 2 Pcr 0.2", "plastic, Pc 4 Pcr 0.2",
                                               "Pc alone, Pc 4 Pcr 0.5", "glass, Pc 4 Pcr 0.2",
                                               "black, Pc 1 Pcr 0.05"};
static const coat mtl_coat[COLUMNS] = {
    {0.5, 0.04}, {1, 0.04}, {1, 0.25}, {1, 0.04}, {0.25, 0.0025}};
static const enum base mtl_base[COLUMNS] = {CONDUCTOR, PBR_PLASTIC, PBR_PLASTIC, GLASS, BLACK};

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
            if (row < 5)
                fprintf(mat, "t%d%d 0 %s  %g %g\n", row, column, base_line[column], row_coat[row].w,
                        row_roughness[row]);
        }
    fclose(obj);
    fclose(mtl);
    fclose(mat);
    furnace_write_cfg(ROWS, view_cos);
}

/* "coat W r R" of furnace row `row` (0-4). */
static const char *row_name(int row)
{
    static char name[5][32];
    snprintf(name[row], sizeof name[row], "coat %.1f r %.2f", row_coat[row].w, row_roughness[row]);
    return name[row];
}

/* Every tile against the integral, within 4 standard errors of its pixels and 0.003 (the
 * perspective's spread of the viewing angle over a tile); for light samples alone only the
 * roughest coat's row (a narrower lobe is not found by uniform directions often enough, a delta
 * never); for Whitted not the diffuse bases (Whitted's diffuse surfaces see lights, not the
 * environment). */
static bool furnace_agrees(vkrt_integrator integrator, uint32_t mode)
{
    bool whitted = integrator == VKRT_INTEGRATOR_WHITTED;
    bool lights_only = mode == VKRT_SAMPLING_LIGHTS && !whitted;
    float *rgb = furnace_render(COLUMNS, ROWS, TILE, SPP, integrator, mode);
    bool all = true;
    for (int row = 0; row < ROWS; ++row) {
        if (lights_only && row != 2)
            continue;
        for (int column = 0; column < COLUMNS; ++column) {
            enum base kind = row < 5 ? (enum base)column : mtl_base[column];
            coat c = row < 5 ? row_coat[row] : mtl_coat[column];
            if (whitted && (kind == LAMBERT || kind == PLASTIC || kind == PBR_PLASTIC))
                continue;
            double mean, se, seen;
            furnace_tile_mean(rgb, COLUMNS, TILE, MARGIN, row, column, &mean, &se);
            coated_albedo(kind, c, view_cos, &seen);
            print_message("%-15s under %-22s: picture %.5f, integral %.5f (+- %.5f)\n",
                          row < 5 ? names[column] : ".mtl",
                          row < 5 ? row_name(row) : mtl_names[column], mean, seen, 4 * se);
            all &= furnace_tile_agrees(mean, se, seen, row, column);
        }
    }
    free(rgb);
    return all;
}

/* What the coat costs or adds, by the integral (no render): the coated BSDF's albedo less the
 * bare base's, at several viewing angles, in percent of the incident energy (negative: the coat
 * loses energy that the base alone would have returned). Over a white Lambertian the loss is the
 * rough coat's single scattering only; over other bases the normalisation 1 / (1 - w Fdr), exact
 * for a Lambertian, is too much near the normal and too little at grazing angles. */
static void print_coat_energy(void)
{
    static const double mus[] = {1.0, 0.8, 0.5, 0.2};
    static const coat bare = {0, 0};
    for (int r = 0; r < 3; ++r)
        for (int k = 0; k < COLUMNS; ++k) {
            char line[256];
            int n = snprintf(line, sizeof line, "%-15s under %s: coat adds at cos", names[k],
                             row_name(r));
            for (size_t a = 0; a < sizeof mus / sizeof *mus; ++a) {
                double coated = coated_albedo((enum base)k, row_coat[r], mus[a], NULL);
                double base = coated_albedo((enum base)k, bare, mus[a], NULL);
                n += snprintf(line + n, sizeof line - (size_t)n, " %.1f: %+.2f%%", mus[a],
                              100 * (coated - base));
            }
            print_message("%s\n", line);
        }
}

static void white_furnace_coats(void **state)
{
    (void)state;
    write_tiles();
    print_coat_energy();
    print_message("MIS:\n");
    bool mis = furnace_agrees(VKRT_INTEGRATOR_PATH, VKRT_SAMPLING_MIS);
    print_message("light samples alone:\n");
    bool lights = furnace_agrees(VKRT_INTEGRATOR_PATH, VKRT_SAMPLING_LIGHTS);
    print_message("whitted:\n");
    bool whitted = furnace_agrees(VKRT_INTEGRATOR_WHITTED, VKRT_SAMPLING_MIS);
    assert_true(mis && lights && whitted);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(white_furnace_coats),
    };
    return cmocka_run_group_tests(tests, scene_dir_make, scene_dir_remove);
}
