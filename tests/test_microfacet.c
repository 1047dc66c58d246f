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
 * scattering drops the light that would bounce again between microfacets.
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
#include "scene_dir.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

typedef struct {
    double x, y, z;
} v3;

static double dot3(v3 a, v3 b)
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

/* ---- The model, written again from the papers (on purpose: not the shader's code) ----------- */

static double fresnel(double cos_i, double eta)
{
    double sin_t2 = (1 - cos_i * cos_i) / (eta * eta);
    if (sin_t2 >= 1)
        return 1;
    double cos_t = sqrt(1 - sin_t2);
    double rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    double rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    return 0.5 * (rs * rs + rp * rp);
}

/* Smith's G1 for GGX (Heitz 2014, "Understanding the Masking-Shadowing Function", eq. 72 with
 * 86): 2 / (1 + sqrt(1 + alpha^2 tan^2)); 0 where w sees the back of m. */
static double smith_g1(v3 w, v3 m, double alpha)
{
    if (dot3(w, m) * w.z <= 0)
        return 0;
    double tan2 = (1 - w.z * w.z) / (w.z * w.z);
    return 2 / (1 + sqrt(1 + alpha * alpha * tan2));
}

enum bsdf { CONDUCTOR, PLASTIC, DIELECTRIC };

/* The directional albedo at o (o.z = mu) of the white BSDF: F0 = 1 conductor, plastic of Kd 1
 * and a plain coat, glass of eta; for glass, *seen is what the picture shows: reflection plus
 * transmission carrying radiance (1 / eta^2), and the return value counts the transmitted
 * energy in full. Integrated over microfacet normals m, drawn on an n x n midpoint grid warped
 * by GGX's distribution of m (density D(m) cos(theta_m), so that the grid follows the lobe at
 * any roughness); each term is the integrand in m over that density. */
static double albedo(enum bsdf kind, double mu, double alpha, double eta, double *seen)
{
    const int n = 600;
    v3 o = {sqrt(1 - mu * mu), 0, mu};
    double sum = 0, sum_seen = 0;
    for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b) {
            double u = (a + 0.5) / n, phi = 2 * M_PI * (b + 0.5) / n;
            double theta = atan(alpha * sqrt(u / (1 - u)));
            v3 m = {sin(theta) * cos(phi), sin(theta) * sin(phi), cos(theta)};
            double om = dot3(o, m);
            if (om <= 0)
                continue;
            /* D G1(o) G1(i) (o.m) / o.z is f cos with the Jacobian of m to i (Walter's eq. 14
             * and 17, the (o.m) and eta terms cancelling), over D cos(theta_m). */
            double common = smith_g1(o, m, alpha) * om / (o.z * m.z);
            v3 r = {2 * om * m.x - o.x, 2 * om * m.y - o.y, 2 * om * m.z - o.z};
            double f = kind == CONDUCTOR ? 1 : fresnel(om, eta);
            double reflected = r.z > 0 ? f * smith_g1(r, m, alpha) * common : 0;
            sum += reflected;
            sum_seen += reflected;
            if (kind == DIELECTRIC && f < 1) {
                double c = om / eta, k = sqrt(1 - (1 - om * om) / (eta * eta));
                v3 t = {(c - k) * m.x - o.x / eta, (c - k) * m.y - o.y / eta,
                        (c - k) * m.z - o.z / eta};
                double through = t.z < 0 ? (1 - f) * smith_g1(t, m, alpha) * common : 0;
                sum += through;
                sum_seen += through / (eta * eta);
            }
        }
    sum /= (double)n * n;
    sum_seen /= (double)n * n;
    if (kind == PLASTIC) {
        /* The base under a coat of Kd 1 returns all the coat lets in: 1 - F(mu) (the shader's
         * normalisation by the average Fresnel reflectance is exactly that). */
        sum += 1 - fresnel(mu, eta);
        sum_seen += 1 - fresnel(mu, eta);
    }
    if (seen)
        *seen = sum_seen;
    return sum;
}

/* ---- The furnace ---------------------------------------------------------------------------- */

enum { COLUMNS = 3, ROWS = 6, TILE = 16, MARGIN = 2, SPP = 64 };
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
            double x0 = column - 1.5, x1 = x0 + 1, z0 = 2.0 * row - ROWS, z1 = z0 + 2;
            /* Counter-clockwise seen from +y. */
            fprintf(obj,
                    "v %g 0 %g\nv %g 0 %g\nv %g 0 %g\nv %g 0 %g\nusemtl t%d%d\n"
                    "f -4 -3 -2 -1\n",
                    x0, z1, x1, z1, x1, z0, x0, z0, row, column);
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
    char cfg[512];
    double d = 500, s = sqrt(1 - view_cos * view_cos);
    snprintf(cfg, sizeof cfg,
             "geometry tiles.obj\nmaterials tiles.mat\nmax-depth 8\nintegrator path\n"
             "environment 1 1 1\ncamera eye 0 %.9g %.9g look 0 0 0 up 0 1 0 fov %.9g\n",
             d * view_cos, d * s, 2 * atan(0.5 * ROWS / d) * 180 / M_PI);
    scene_dir_write("scene.cfg", cfg);
}

/* Mean and standard error of the tile's inner pixels (TILE - 2 MARGIN square), by luminance-free
 * channel average (the tiles are white). */
static void tile_mean(const float *rgb, int row, int column, double *mean, double *se)
{
    int w = COLUMNS * TILE;
    double sum = 0, sum2 = 0;
    int n = 0;
    for (int y = row * TILE + MARGIN; y < (row + 1) * TILE - MARGIN; ++y)
        for (int x = column * TILE + MARGIN; x < (column + 1) * TILE - MARGIN; ++x) {
            const float *p = &rgb[3 * (y * w + x)];
            double v = (p[0] + p[1] + p[2]) / 3.0;
            sum += v;
            sum2 += v * v;
            ++n;
        }
    *mean = sum / n;
    *se = sqrt(fmax(sum2 / n - *mean * *mean, 0) / (n - 1));
}

/* Every tile's picture, rendered with the sampling `mode`, against the albedo the CPU
 * integrates, within 4 standard errors of its pixels and 0.003 (the perspective's spread of the
 * viewing angle over a tile, which the integral at the tile's centre does not see); rows of
 * roughness below min_roughness are not checked. Prints the energy each BSDF loses. */
static bool furnace_agrees(vkrt_integrator integrator, uint32_t mode, double min_roughness)
{
    bool whitted = integrator == VKRT_INTEGRATOR_WHITTED;
    int w = COLUMNS * TILE, h = ROWS * TILE;
    float *rgb = malloc((size_t)w * h * 3 * sizeof *rgb);
    vkrt_error err = {{0}};
    vkrt_frame_stats stats;
    if (!scene_dir_render(
            (uint32_t)w, (uint32_t)h,
            &(vkrt_render_desc){.samples = SPP, .integrator = integrator, .light_sampling = mode},
            rgb, &stats, &err))
        fail_msg("render: %s", err.msg);
    static const char *const names[COLUMNS] = {"conductor F0=1", "plastic Kd=1", "dielectric 1.5"};
    bool all = true;
    for (int row = 0; row < ROWS; ++row) {
        if (row < 4 ? roughness[row] < min_roughness : row == 4 && min_roughness > 0)
            continue; /* light samples alone cannot find a narrow lobe, nor a delta one */
        for (int column = 0; column < COLUMNS; ++column) {
            /* Whitted's diffuse surfaces see lights, not the environment: not the plastics. */
            if (whitted && column == 1)
                continue;
            double mean, se, seen, energy;
            tile_mean(rgb, row, column, &mean, &se);
            if (row < 4) {
                double alpha = roughness[row] * roughness[row];
                energy = albedo((enum bsdf)column, view_cos, alpha, eta, &seen);
                print_message("%-15s roughness %.2f: picture %.5f, integral %.5f (+- %.5f); "
                              "energy lost at cos 0.5: %.2f%%\n",
                              names[column], roughness[row], mean, seen, 4 * se,
                              100 * (1 - energy));
            } else if (row == 5) {
                double r = mtl_row_roughness[column];
                albedo(column == 1 ? PLASTIC : CONDUCTOR, view_cos, r * r, eta, &seen);
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
            if (!(fabs(mean - seen) <= 4 * se + 0.003)) {
                print_message("  tile (%d, %d) is off by %.5f\n", row, column, mean - seen);
                all = false;
            }
        }
    }
    assert_int_equal(stats.nonfinite, 0);
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
