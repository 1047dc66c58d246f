/*
 * test_adaptive.c: sampling to a target error (vkrt_render_desc.target_error,
 * glsl/lib/adaptive.glsl), on a scene with a flat region and a noisy one: the upper half of the
 * image sees a constant sky (every sample the same: no noise), the lower half a floor lit by the
 * sky and a small lamp (noise from the light samples and the bounces).
 *   1. The estimate is honest: after a render to E, the true relative error of the pixels'
 *      luminance, measured as the estimate is defined (the same floor), against a uniform render
 *      of 1024 samples with another seed (its own error about a third of E), has a root mean
 *      square of at most 1.5 E, and the image's estimates (vkrt_renderer_convergence) are
 *      within E where a pixel stopped before the cap. The estimate assumes independent samples;
 *      the stratified sampler does better on this smooth light, and the neighbours of noisy
 *      pixels sample on (glsl/adapt.comp), so the true error is about an eighth of E here and
 *      from below it is only held to E / 10; an estimate that sent every pixel to the cap would
 *      fall under that (0.08 E), and the floor's pixels are held to half the cap.
 *   2. The samples go where the noise is: sky pixels take the fewest a pixel may
 *      (VKRT_ADAPTIVE_MIN_SAMPLES), floor pixels several times more, and the row of sky above the
 *      horizon, flat itself, over twice the fewest, since the floor's pixels beside it are not
 *      done (the neighbourhood rule).
 *   3. A pixel's samples are the uniform render's first ones (the sampler's indices stay
 *      consecutive): with every noisy pixel at the cap, the image is the uniform one.
 * Breaking the estimate (variance ignored, or not divided by the samples) fails 1 or 2; judging
 * each pixel by its own estimate alone (no neighbourhood) fails 2.
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
#include "gpu_fixture.h"
#include "render/renderer.h"
#include "scene/scene.h"
#include "scene_dir.h"

enum { W = 24, H = 16, PIXELS = W * H };

/* The floor (y = 0, 20 x 20) under a lamp (a 0.2 x 0.2 square at y = 0.6 that emits downwards
 * only, its top black) and a sky of radiance 0.5, seen level from above the lamp, so that the
 * horizon cuts the image in half. */
static void write_scene(void)
{
    scene_dir_write("scene.obj", "mtllib scene.mtl\nusemtl floor\n"
                                 "v -10 0 -10\nv 10 0 -10\nv 10 0 10\nv -10 0 10\nf 1 4 3 2\n"
                                 "usemtl lamp\n"
                                 "v -0.1 0.6 -0.1\nv 0.1 0.6 -0.1\nv 0.1 0.6 0.1\nv -0.1 0.6 0.1\n"
                                 "f 5 6 7 8\n");
    scene_dir_write("scene.mtl", "newmtl floor\nKd 0.6 0.6 0.6\nnewmtl lamp\nKd 0 0 0\n"
                                 "Ke 30 30 30\n");
    scene_dir_write("scene.cfg", "geometry scene.obj\nresolution 24 16\nmax-depth 2\n"
                                 "environment 0.5 0.5 0.5\nintegrator path\n"
                                 "camera eye 0 0.8 2.5 look 0 0.8 0 up 0 1 0 fov 60\n");
}

/* Renders the folder's scene with desc at W x H into rgb; with a target error, also each
 * pixel's estimate and samples. */
static void render(const vkrt_render_desc *desc, float *rgb, float *estimates, uint32_t *samples,
                   vkrt_convergence *c)
{
    char path[256];
    snprintf(path, sizeof path, "%s/scene.cfg", scene_dir);
    vkrt_error err = {{0}};
    vkrt_scene scene;
    if (!vkrt_scene_load(path, &scene, &err))
        fail_msg("%s", err.msg);
    gpu_context ctx;
    fixture_context_create(&ctx);
    vkrt_render_desc d = *desc;
    d.width = W;
    d.height = H;
    vkrt_renderer *r = NULL;
    bool ok = vkrt_renderer_create(&r, &ctx, &scene, &d, &err) &&
              vkrt_renderer_render(r, &scene.cameras[0], 0, rgb, NULL, &err) &&
              (d.target_error <= 0 || vkrt_renderer_convergence(r, c, estimates, samples, &err));
    vkrt_renderer_destroy(r);
    fixture_context_destroy(&ctx);
    vkrt_scene_free(&scene);
    if (!ok)
        fail_msg("%s", err.msg);
}

static double luminance_of(const float *rgb, int i)
{
    return 0.2126 * rgb[3 * i] + 0.7152 * rgb[3 * i + 1] + 0.0722 * rgb[3 * i + 2];
}

static void estimate_is_honest_and_samples_go_to_noise(void **state)
{
    (void)state;
    write_scene();
    const float target = 0.015f;
    const uint32_t cap = 1024;
    static float rgb[PIXELS * 3], reference[PIXELS * 3], estimates[PIXELS];
    static uint32_t samples[PIXELS];
    vkrt_convergence c;
    render(&(vkrt_render_desc){.samples = cap, .target_error = target}, rgb, estimates, samples,
           &c);
    render(&(vkrt_render_desc){.samples = 1024, .seed = 1}, reference, NULL, NULL, NULL);
    /* True error, as the estimate is defined: |luminance - reference| / max(reference, floor). */
    double squares = 0, sky_samples = 0, floor_samples = 0, border_samples = 0;
    int sky = 0, ground = 0, within = 0, stopped = 0;
    for (int i = 0; i < PIXELS; ++i) {
        double ref = luminance_of(reference, i);
        double e = fabs(luminance_of(rgb, i) - ref) / fmax(ref, VKRT_ADAPTIVE_FLOOR);
        squares += e * e;
        if (samples[i] < cap) {
            ++stopped;
            within += estimates[i] <= target;
        }
        /* The horizon is the middle row, and the floor's noise begins there; the sky row above
         * it is as flat as the rest of the sky, but borders on unconverged pixels, which keep
         * it listed (glsl/adapt.comp). */
        int y = i / W;
        if (y == H / 2 - 1) {
            border_samples += samples[i];
        } else if (y < H / 2 - 1) {
            ++sky;
            sky_samples += samples[i];
        } else if (y > H / 2) {
            ++ground;
            floor_samples += samples[i];
        }
    }
    double true_rms = sqrt(squares / PIXELS);
    sky_samples /= sky;
    floor_samples /= ground;
    border_samples /= W;
    print_message("target %.3f: estimate rms %.4f (max %.4f), true rms %.4f (%.2fx); samples: "
                  "sky %.1f, sky beside the horizon %.1f, floor %.1f, mean %.1f; %d of %d stopped "
                  "before the cap, %d within\n",
                  (double)target, c.rms_error, (double)c.max_error, true_rms, true_rms / target,
                  sky_samples, border_samples, floor_samples, c.mean_samples, stopped, PIXELS,
                  within);
    assert_true(true_rms <= 1.5 * target && true_rms >= target / 10);
    assert_int_equal(within, stopped);
    assert_true(c.rms_error <= target);
    assert_true(sky_samples == VKRT_ADAPTIVE_MIN_SAMPLES);
    assert_true(border_samples > 2 * VKRT_ADAPTIVE_MIN_SAMPLES);
    assert_true(floor_samples > 4 * sky_samples && floor_samples < cap / 2);
}

/* With a target no noisy pixel reaches, every such pixel takes the cap's samples, the uniform
 * render's: the same image up to the order of the float atomic adds (1e-4 relative, as
 * test_path's seeds). The
 * cap spans several passes (VKRT_ADAPTIVE_MIN_SAMPLES each), so later passes' sample indices are
 * checked too. */
static void samples_are_the_uniform_ones(void **state)
{
    (void)state;
    write_scene();
    static float adaptive[PIXELS * 3], uniform[PIXELS * 3];
    static uint32_t samples[PIXELS];
    vkrt_convergence c;
    render(&(vkrt_render_desc){.samples = 40, .target_error = 1e-6f}, adaptive, NULL, samples, &c);
    render(&(vkrt_render_desc){.samples = 40}, uniform, NULL, NULL, NULL);
    double worst = 0;
    for (int i = 0; i < PIXELS * 3; ++i)
        worst = fmax(worst, fabs(adaptive[i] - uniform[i]) / fmax(fabs(uniform[i]), 1e-3));
    /* The sky's samples are all alike (variance 0): those pixels stop at the fewest, 16, with
     * the same average. Every floor pixel is noisy and goes to the cap. */
    uint32_t floor_fewest = 40;
    for (int i = (H / 2 + 1) * W; i < PIXELS; ++i)
        floor_fewest = samples[i] < floor_fewest ? samples[i] : floor_fewest;
    print_message("target 1e-6, cap 40: %u to %u samples (floor: at least %u); differs from "
                  "uniform by %.2g\n",
                  c.min_samples, c.max_samples, floor_fewest, worst);
    assert_int_equal(floor_fewest, 40);
    assert_int_equal(c.max_samples, 40);
    assert_true(worst < 1e-4);
}

/* Pixels of one sample have no estimate (adaptive.glsl's 1e30 sentinel): they are counted apart,
 * never averaged into the rms or shown as the max; with only such pixels there is no figure. */
static void single_samples_are_not_estimates(void **state)
{
    (void)state;
    /* Two pixels of 10 samples with variance 0.36 and mean 2: error sqrt(0.36 / 10) / 2. */
    PixelStats stats[4] = {{1.0f, 0.0f, 1, 0}, {2.0f, 0.36f * 9, 10, 0}, {0.5f, 0.0f, 1, 0},
                           {2.0f, 0.36f * 9, 10, 0}};
    float sorted[4];
    vkrt_convergence c;
    vkrt_convergence_of(stats, 4, 0.05f, &c, sorted, NULL, NULL);
    double want = sqrt(0.36 / 10) / 2;
    assert_int_equal(c.unestimated, 2);
    assert_float_equal(c.rms_error, want, 1e-6);
    assert_float_equal(c.max_error, want, 1e-6);
    assert_float_equal(c.p99_error, want, 1e-6);
    assert_int_equal(c.converged, 0);
    assert_int_equal(c.min_samples, 1);
    assert_int_equal(c.max_samples, 10);

    PixelStats ones[2] = {{1.0f, 0.0f, 1, 0}, {3.0f, 0.0f, 1, 0}};
    vkrt_convergence_of(ones, 2, 0.05f, &c, sorted, NULL, NULL);
    assert_int_equal(c.unestimated, 2);
    assert_true(c.rms_error == 0.0 && c.max_error == 0.0f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(estimate_is_honest_and_samples_go_to_noise),
        cmocka_unit_test(samples_are_the_uniform_ones),
        cmocka_unit_test(single_samples_are_not_estimates),
    };
    return cmocka_run_group_tests(tests, scene_dir_make, scene_dir_remove);
}
