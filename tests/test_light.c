/*
 * test_light.c: light from emissive geometry in the Whitted integrator, held against the closed
 * form of a square lamp's irradiance and against the path tracer.
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

#include "render/renderer.h"
#include "scene_dir.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static void render_ok(uint32_t w, uint32_t h, const vkrt_render_desc *desc, float *rgb,
                      vkrt_frame_stats *stats)
{
    vkrt_error err = {{0}};
    if (!scene_dir_render(w, h, desc, rgb, stats, &err))
        fail_msg("render: %s", err.msg);
}

/* The mean of channel 0 over an n x n image, and its standard error from the pixels' spread. */
static double mean_red(const float *rgb, int n, double *standard_error)
{
    double sum = 0, sum2 = 0;
    for (int i = 0; i < n * n; ++i) {
        sum += rgb[3 * i];
        sum2 += (double)rgb[3 * i] * rgb[3 * i];
    }
    double mean = sum / (n * n);
    *standard_error = sqrt(fmax(sum2 / (n * n) - mean * mean, 0) / (n * n - 1));
    return mean;
}

/* Irradiance per unit radiance at a point under the centre of a square lamp of half side b at
 * height h, facing it: four corner rectangles, each the configuration factor of a differential
 * area to a parallel rectangle with a corner above it (Howell's catalogue, B-3), times pi:
 * E / Le = 4 * (1/2) [2 X / sqrt(1 + X^2) atan(X / sqrt(1 + X^2))], X = b / h. */
static double square_lamp_irradiance(double b, double h)
{
    double x = b / h, s = sqrt(1 + x * x);
    return 4 * x / s * atan(x / s);
}

/* A diffuse floor (Kd 0.5) under a square lamp of side 0.5 at height 1 facing down (Ke 4); with
 * `blocker`, an opaque square of side 0.4 half way between, over the lamp's centre: its umbra on
 * the floor is the square of side 0.3 about the origin, its penumbra reaches out to 0.65. */
static void write_lamp_scene(const char *integrator, bool blocker, const char *camera)
{
    FILE *f = scene_dir_open("scene.obj");
    fprintf(f, "mtllib scene.mtl\nusemtl floor\nv -2 0 -2\nv 2 0 -2\nv 2 0 2\nv -2 0 2\n"
               "f 1 4 3 2\nusemtl lamp\nv -0.25 1 -0.25\nv 0.25 1 -0.25\nv 0.25 1 0.25\n"
               "v -0.25 1 0.25\nf 5 6 7 8\n");
    if (blocker)
        fprintf(f, "usemtl floor\nv -0.2 0.5 -0.2\nv 0.2 0.5 -0.2\nv 0.2 0.5 0.2\n"
                   "v -0.2 0.5 0.2\nf 9 10 11 12\n");
    fclose(f);
    scene_dir_write("scene.mtl", "newmtl floor\nKd 0.5 0.5 0.5\nnewmtl lamp\nKd 0 0 0\n"
                                 "Ke 4 4 4\n");
    char cfg[512];
    snprintf(cfg, sizeof cfg,
             "geometry scene.obj\nresolution 16 16\nmax-depth 0\n"
             "integrator %s\ncamera %s\n",
             integrator, camera);
    scene_dir_write("scene.cfg", cfg);
}

/* The point under the lamp seen from the side, below the lamp and past the blocker, with a field
 * of view of 2 degrees: within 0.03 of the point, where the irradiance changes by 0.1%. */
static const char *const narrow_camera = "eye 0 0.9 0.6 look 0 0 0 up 0 1 0 fov 2";

/* Whitted lights the floor with the lamp: under it the floor shows Kd / pi * E, E from the closed
 * form (Le 4: 0.924, so 0.1470), within 5 standard errors and 1%; the path tracer's direct light
 * (max-depth 0, light and BSDF samples weighed by MIS) shows the same. Without the lamp as a
 * light (Whitted before emitters were sampled) the floor is black. */
static void whitted_emitters_light_the_floor(void **state)
{
    (void)state;
    enum { N = 16, SPP = 16 };
    double expected = 0.5 / M_PI * 4 * square_lamp_irradiance(0.25, 1.0);
    static const char *const integrators[] = {"whitted", "path"};
    for (int k = 0; k < 2; ++k) {
        write_lamp_scene(integrators[k], false, narrow_camera);
        float rgb[N * N * 3];
        vkrt_frame_stats stats;
        render_ok(N, N, &(vkrt_render_desc){.samples = SPP}, rgb, &stats);
        double se, mean = mean_red(rgb, N, &se);
        print_message("%s: floor under the lamp %.5f +- %.5f (closed form %.5f), %llu shadow "
                      "rays\n",
                      integrators[k], mean, se, expected, (unsigned long long)stats.shadow_rays);
        assert_true(fabs(mean - expected) < 5 * se + 0.01 * expected);
        /* One shadow ray per pixel and sample pass: a sample of the lamp, not of every triangle. */
        if (k == 0)
            assert_int_equal(stats.shadow_rays, N * N * SPP);
    }
}

/* A blocker between lamp and floor casts a soft shadow: in its umbra the floor is exactly black
 * in Whitted (no ambient light, no indirect light), and around it the floor takes every value
 * between black and lit over a broad band (a lamp sampled at one point, as a point light, gives
 * a hard edge: black or lit, and between only where the edge crosses a pixel). Seen from below
 * the blocker's height, which keeps blocker and lamp out of the view. */
static void whitted_emitters_cast_soft_shadows(void **state)
{
    (void)state;
    enum { N = 32, SPP = 16 };
    const char *camera = "eye 0 0.3 0.9 look 0 0 0 up 0 1 0 fov 40";
    float lit[N * N * 3], shadowed[N * N * 3];
    write_lamp_scene("whitted", false, camera);
    render_ok(N, N, &(vkrt_render_desc){.samples = SPP}, lit, NULL);
    write_lamp_scene("whitted", true, camera);
    render_ok(N, N, &(vkrt_render_desc){.samples = SPP}, shadowed, NULL);
    int umbra = 0, penumbra = 0;
    for (int i = 0; i < N * N; ++i) {
        if (!(lit[3 * i] > 0.02f))
            continue; /* the floor far from the lamp */
        double ratio = shadowed[3 * i] / lit[3 * i];
        umbra += ratio == 0.0;
        penumbra += ratio > 0.2 && ratio < 0.8;
    }
    print_message("%d pixels in the umbra, %d in the penumbra (20-80%% lit)\n", umbra, penumbra);
    /* 87 and 421 pixels when written; a lamp sampled at one point gave 36 in the penumbra (a
     * hard edge, antialiased within pixels). */
    assert_true(umbra >= 20);
    assert_true(penumbra >= 150);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(whitted_emitters_light_the_floor),
        cmocka_unit_test(whitted_emitters_cast_soft_shadows),
    };
    return cmocka_run_group_tests(tests, scene_dir_make, scene_dir_remove);
}
