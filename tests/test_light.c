/*
 * test_light.c: light from emissive geometry in the Whitted integrator, held against the closed
 * form of a square lamp's irradiance and against the path tracer; and `--clamp`, the limit on
 * what one path may add to a pixel, against the bound it promises.
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

/* `clamp L`: a floor that sees a small, bright lamp (Ke 1000 500 250) in a mirror, light only
 * BSDF samples find (the mirror is a delta lobe: no light sample reaches through it), each such
 * path a firefly. Every path adds at most 2 max-depth + 3 contributions in path (a light sample
 * and the light found at every vertex, and the light the last ray finds), each clamped to L in
 * its largest channel, so no pixel may exceed that many L; without the clamp the lamp and the
 * fireflies do. The lamp seen in the mirror, one contribution per sample: exactly L in its
 * largest channel, its hue kept. Whitted clamps the same way (there the lamp's back shows Ke too:
 * Whitted's built-ins show it on both faces). */
static void clamp_bounds_every_contribution(void **state)
{
    (void)state;
    enum { N = 24, SPP = 4 };
    scene_dir_write("scene.obj",
                    "mtllib scene.mtl\nusemtl floor\nv -2 0 -2\nv 2 0 -2\nv 2 0 2\nv -2 0 2\n"
                    "f 1 4 3 2\nusemtl mirror\nv -2 0 -1\nv 2 0 -1\nv 2 2 -1\nv -2 2 -1\n"
                    "f 5 6 7 8\nusemtl lamp\nv 0.4 0.4 0.5\nv 0.8 0.4 0.5\nv 0.8 0.8 0.5\n"
                    "v 0.4 0.8 0.5\nf 12 11 10 9\n");
    scene_dir_write("scene.mtl", "newmtl floor\nKd 0.5 0.5 0.5\nnewmtl mirror\nillum 3\nKd 0 0 0\n"
                                 "Ks 1 1 1\nnewmtl lamp\nKd 0 0 0\nKe 1000 500 250\n");
    const uint32_t max_depth = 1;
    const float limit = 2.0f;
    float bound = limit * (float)(2 * max_depth + 3);
    int lamp = -1;
    static const char *const integrators[] = {"path", "whitted"};
    for (int k = 0; k < 2; ++k) {
        char cfg[512];
        snprintf(cfg, sizeof cfg,
                 "geometry scene.obj\nresolution 24 24\nmax-depth %u\nintegrator %s\n"
                 "camera eye 0 0.6 2.5 look 0 0.3 0 up 0 1 0 fov 60\n",
                 max_depth, integrators[k]);
        scene_dir_write("scene.cfg", cfg);
        float plain[N * N * 3], clamped[N * N * 3];
        if (k == 0) {
            /* Without the clamp (path): above the bound, and where the lamp is. */
            render_ok(N, N, &(vkrt_render_desc){.samples = SPP}, plain, NULL);
            float plain_max = 0;
            for (int i = 0; i < N * N; ++i) {
                for (int c = 0; c < 3; ++c)
                    plain_max = fmaxf(plain_max, plain[3 * i + c]);
                if (plain[3 * i] == 1000.0f)
                    lamp = i; /* all of its samples see the lamp, and nothing else */
            }
            print_message("largest channel %g without the clamp\n", plain_max);
            assert_true(plain_max > bound);
            assert_true(lamp >= 0);
        }
        render_ok(N, N, &(vkrt_render_desc){.samples = SPP, .clamp = limit}, clamped, NULL);
        float clamped_max = 0;
        for (int i = 0; i < N * N * 3; ++i)
            clamped_max = fmaxf(clamped_max, clamped[i]);
        print_message("%s: largest channel %g with clamp %g (bound %g); the lamp's pixel %g %g "
                      "%g\n",
                      integrators[k], clamped_max, limit, bound, clamped[3 * lamp],
                      clamped[3 * lamp + 1], clamped[3 * lamp + 2]);
        assert_true(clamped_max <= bound);
        assert_float_equal(clamped[3 * lamp], limit, 1e-5);
        assert_float_equal(clamped[3 * lamp + 1], limit / 2, 1e-5);
        assert_float_equal(clamped[3 * lamp + 2], limit / 4, 1e-5);
    }
}

/* A clamp that is negative, infinite or not a number is refused with a message. */
static void clamp_must_be_a_positive_number(void **state)
{
    (void)state;
    scene_dir_write("scene.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    scene_dir_write("scene.cfg", "geometry scene.obj\ncamera eye 0 0 3 look 0 0 0 up 0 1 0 "
                                 "fov 40\n");
    const float bad[] = {-1.0f, INFINITY, NAN};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; ++i) {
        vkrt_error err = {{0}};
        float rgb[4 * 4 * 3];
        assert_false(scene_dir_render(4, 4, &(vkrt_render_desc){.clamp = bad[i]}, rgb, NULL, &err));
        print_message("clamp %g: %s\n", bad[i], err.msg);
        assert_non_null(strstr(err.msg, "clamp"));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(whitted_emitters_light_the_floor),
        cmocka_unit_test(whitted_emitters_cast_soft_shadows),
        cmocka_unit_test(clamp_bounds_every_contribution),
        cmocka_unit_test(clamp_must_be_a_positive_number),
    };
    return cmocka_run_group_tests(tests, scene_dir_make, scene_dir_remove);
}
