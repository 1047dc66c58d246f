/* furnace.c: see furnace.h. */
#include "furnace.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>

#include <cmocka.h>

#include "scene_dir.h"

double dot3(v3 a, v3 b)
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

double fresnel(double cos_i, double eta)
{
    double sin_t2 = (1 - cos_i * cos_i) / (eta * eta);
    if (sin_t2 >= 1)
        return 1;
    double cos_t = sqrt(1 - sin_t2);
    double rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    double rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    return 0.5 * (rs * rs + rp * rp);
}

double smith_g1(v3 w, v3 m, double alpha)
{
    if (dot3(w, m) * w.z <= 0)
        return 0;
    double tan2 = (1 - w.z * w.z) / (w.z * w.z);
    return 2 / (1 + sqrt(1 + alpha * alpha * tan2));
}

/* furnace_integrate's grid, or with tails: u = 1 - s^2 on a midpoint grid in s, weighted 2 s. */
static double integrate_grid(v3 o, double alpha, double eta, int n, bool tails,
                             double (*term)(const furnace_facet *f, double alpha, void *ctx),
                             void *ctx)
{
    const double pi = 3.14159265358979323846;
    double sum = 0;
    for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b) {
            double s = (a + 0.5) / n, phi = 2 * pi * (b + 0.5) / n;
            double u = tails ? 1 - s * s : s, weight = tails ? 2 * s : 1;
            double theta = atan(alpha * sqrt(u / (1 - u)));
            furnace_facet f;
            f.m = (v3){sin(theta) * cos(phi), sin(theta) * sin(phi), cos(theta)};
            f.om = dot3(o, f.m);
            if (f.om <= 0)
                continue;
            f.common = smith_g1(o, f.m, alpha) * f.om / (o.z * f.m.z);
            f.r = (v3){2 * f.om * f.m.x - o.x, 2 * f.om * f.m.y - o.y, 2 * f.om * f.m.z - o.z};
            double k2 = 1 - (1 - f.om * f.om) / (eta * eta), c = f.om / eta;
            double k = k2 > 0 ? sqrt(k2) : 0;
            f.t = k2 > 0 ? (v3){(c - k) * f.m.x - o.x / eta, (c - k) * f.m.y - o.y / eta,
                                (c - k) * f.m.z - o.z / eta}
                         : (v3){0, 0, 0};
            sum += weight * term(&f, alpha, ctx);
        }
    return sum / ((double)n * n);
}

double furnace_integrate(v3 o, double alpha, double eta, int n,
                         double (*term)(const furnace_facet *f, double alpha, void *ctx), void *ctx)
{
    return integrate_grid(o, alpha, eta, n, false, term, ctx);
}

double furnace_integrate_tails(v3 o, double alpha, double eta, int n,
                               double (*term)(const furnace_facet *f, double alpha, void *ctx),
                               void *ctx)
{
    return integrate_grid(o, alpha, eta, n, true, term, ctx);
}

static double transmitted_term(const furnace_facet *f, double alpha, void *ctx)
{
    double eta = *(const double *)ctx, fr = fresnel(f->om, eta);
    return fr < 1 && f->t.z < 0 ? (1 - fr) * smith_g1(f->t, f->m, alpha) * f->common : 0;
}

static double reflected_term(const furnace_facet *f, double alpha, void *ctx)
{
    double eta = *(const double *)ctx;
    return f->r.z > 0 ? fresnel(f->om, eta) * smith_g1(f->r, f->m, alpha) * f->common : 0;
}

void furnace_plastic_coat(double alpha, double eta, double t[FURNACE_PLASTIC_COSINES], double *ri)
{
    const int n = 100;
    double inside = 1 / eta, sum = 0;
    for (int k = 0; k < FURNACE_PLASTIC_COSINES; ++k) {
        double mu = fmax(1e-6, k / (double)(FURNACE_PLASTIC_COSINES - 1));
        v3 o = {sqrt(1 - mu * mu), 0, mu};
        t[k] = furnace_integrate_tails(o, alpha, eta, n, transmitted_term, &eta);
        sum += furnace_integrate_tails(o, alpha, inside, n, reflected_term, &inside) * mu;
    }
    *ri = 2 * sum / FURNACE_PLASTIC_COSINES;
}

double furnace_plastic_lerp(const double t[FURNACE_PLASTIC_COSINES], double mu)
{
    double x = mu * (FURNACE_PLASTIC_COSINES - 1);
    int k = (int)x < FURNACE_PLASTIC_COSINES - 2 ? (int)x : FURNACE_PLASTIC_COSINES - 2;
    return t[k] + (t[k + 1] - t[k]) * (x - k);
}

void furnace_write_tile(FILE *obj, int columns, int rows, int row, int column)
{
    furnace_write_tile_deep(obj, columns, rows, row, column, 2);
}

void furnace_write_tile_deep(FILE *obj, int columns, int rows, int row, int column, double depth)
{
    double x0 = column - 0.5 * columns, x1 = x0 + 1, z0 = depth * (row - 0.5 * rows),
           z1 = z0 + depth;
    fprintf(obj, "v %g 0 %g\nv %g 0 %g\nv %g 0 %g\nv %g 0 %g\nusemtl t%d%d\nf -4 -3 -2 -1\n", x0,
            z1, x1, z1, x1, z0, x0, z0, row, column);
}

void furnace_write_cfg(int rows, double view_cos)
{
    furnace_write_cfg_lit(rows, view_cos, "environment 1 1 1\n");
}

void furnace_write_cfg_lit(int rows, double view_cos, const char *lighting)
{
    const double pi = 3.14159265358979323846;
    char cfg[768];
    double d = 500, s = sqrt(1 - view_cos * view_cos);
    snprintf(cfg, sizeof cfg,
             "geometry tiles.obj\nmaterials tiles.mat\nmax-depth 8\nintegrator path\n"
             "%scamera eye 0 %.9g %.9g look 0 0 0 up 0 1 0 fov %.9g\n",
             lighting, d * view_cos, d * s, 2 * atan(0.5 * rows / d) * 180 / pi);
    scene_dir_write("scene.cfg", cfg);
}

float *furnace_render(int columns, int rows, int tile, uint32_t spp, vkrt_integrator integrator,
                      uint32_t mode)
{
    int w = columns * tile, h = rows * tile;
    float *rgb = malloc((size_t)w * h * 3 * sizeof *rgb);
    assert_non_null(rgb);
    vkrt_error err = {{0}};
    vkrt_frame_stats stats;
    if (!scene_dir_render(
            (uint32_t)w, (uint32_t)h,
            &(vkrt_render_desc){.samples = spp, .integrator = integrator, .light_sampling = mode},
            rgb, &stats, &err))
        fail_msg("render: %s", err.msg);
    assert_int_equal(stats.nonfinite, 0);
    return rgb;
}

void furnace_tile_mean(const float *rgb, int columns, int tile, int margin, int row, int column,
                       double *mean, double *se)
{
    int w = columns * tile;
    double sum = 0, sum2 = 0;
    int n = 0;
    for (int y = row * tile + margin; y < (row + 1) * tile - margin; ++y)
        for (int x = column * tile + margin; x < (column + 1) * tile - margin; ++x) {
            const float *p = &rgb[3 * (y * w + x)];
            double v = (p[0] + p[1] + p[2]) / 3.0;
            sum += v;
            sum2 += v * v;
            ++n;
        }
    *mean = sum / n;
    *se = sqrt(fmax(sum2 / n - *mean * *mean, 0) / (n - 1));
}

bool furnace_tile_agrees(double mean, double se, double expected, int row, int column)
{
    if (fabs(mean - expected) <= 4 * se + 0.003)
        return true;
    printf("  tile (%d, %d) is off by %.5f\n", row, column, mean - expected);
    return false;
}
