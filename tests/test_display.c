/*
 * test_display.c: glsl/display.comp, the viewer's 8-bit path, against the PNG writer's
 * (src/output/finish.c): the window must show what a PNG of the frame holds. The real kernel runs
 * on a small image of chosen radiances (greys over 31 stops, colours, NaN, infinity, negatives)
 * with each tone curve and an exposure, and its pixels are compared with vkrt_finish_srgb8's
 * codes: equal, or one code value apart where float arithmetic on the GPU lands on the other side
 * of a rounding boundary.
 */
#include <setjmp.h> /* cmocka needs these before its header */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdlib.h>

#include "../glsl/shared.h"
#include "gpu_fixture.h"
#include "output/finish.h"

enum { PIXELS = 256 };

/* The radiances shown: greys from 2^-14 to 2^17, then colours, then the values a bad sample
 * leaves. */
static void fill_image(float (*rgb)[3])
{
    size_t n = 0;
    for (; n < 125; ++n)
        rgb[n][0] = rgb[n][1] = rgb[n][2] = exp2f(-14.0f + 0.25f * (float)n);
    uint32_t state = 777u;
    for (; n < PIXELS - 6; ++n)
        for (int c = 0; c < 3; ++c) {
            state = state * 1664525u + 1013904223u; /* Numerical Recipes' LCG */
            rgb[n][c] = 16.0f * (float)(state >> 8) / (float)(1u << 24);
        }
    const float special[6][3] = {{0, 0, 0},         {NAN, 0.5f, 0.5f},   {INFINITY, 1, 1},
                                 {-1, 0.5f, 2},     {1e30f, 0.2f, 0.1f}, {0.18f, 0.18f, 0.18f}};
    for (int i = 0; i < 6; ++i, ++n)
        for (int c = 0; c < 3; ++c)
            rgb[n][c] = special[i][c];
}

static const char KERNEL[] = "#include \"display.comp\"\n";

static void test_window_matches_png(void **state)
{
    (void)state;
    static float rgb[PIXELS][3];
    fill_image(rgb);
    /* The renderer's image: a sum of one pass per pixel, w its count. */
    static float image[PIXELS][4];
    for (size_t i = 0; i < PIXELS; ++i)
        for (int c = 0; c < 4; ++c)
            image[i][c] = c < 3 ? rgb[i][c] : 1.0f;

    gpu_context ctx;
    fixture_context_create(&ctx);
    vkrt_error err = {{0}};
    gpu_buffer buffers[2];
    assert_true(gpu_buffer_create_from(&ctx, &buffers[0], image, sizeof image, "image", &err));
    assert_true(gpu_buffer_create(&ctx, &buffers[1], PIXELS * 4, "window", &err));
    uint8_t codes[PIXELS * 3];
    uint32_t window[PIXELS];
    for (vkrt_tonemap curve = VKRT_TONEMAP_NONE; curve <= VKRT_TONEMAP_AGX; ++curve) {
        vkrt_finish_desc desc = {.exposure = 0.5f, .tonemap = curve};
        vkrt_finish_display shown = vkrt_finish_display_params(&desc);
        DisplayParams push = {
            .size = {PIXELS, 1, PIXELS, 1},
            .scale = {1.0f, shown.scale, 0.0f, 0.0f},
            .curve = {shown.tonemap, 0, 0, 0},
        };
        fixture_run_kernel(&ctx, KERNEL, buffers, 2, &push, sizeof push, PIXELS);
        assert_true(gpu_buffer_download(&ctx, &buffers[1], window, sizeof window, &err));
        const vkrt_finish_frame frame = {.width = PIXELS, .height = 1, .rgb = &rgb[0][0]};
        assert_true(vkrt_finish_srgb8(&desc, &frame, codes, &err));
        int apart = 0;
        for (size_t i = 0; i < PIXELS; ++i)
            for (int c = 0; c < 3; ++c) {
                int gpu = (int)((window[i] >> (8 * c)) & 0xff), png = codes[3 * i + c];
                if (abs(gpu - png) > 1)
                    fail_msg("%s: pixel %zu (%g, %g, %g) channel %d: window %d, PNG %d",
                             vkrt_tonemap_name(curve), i, rgb[i][0], rgb[i][1], rgb[i][2], c, gpu,
                             png);
                apart += gpu != png;
            }
        /* A step apart happens only on a boundary: rare, not the rule. */
        assert_true(apart <= PIXELS * 3 / 50);
        print_message("%s: %d of %d channels one code value apart\n", vkrt_tonemap_name(curve),
                      apart, PIXELS * 3);
    }
    gpu_buffer_destroy(&ctx, &buffers[0]);
    gpu_buffer_destroy(&ctx, &buffers[1]);
    fixture_context_destroy(&ctx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_window_matches_png),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
