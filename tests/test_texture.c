/*
 * test_texture.c: tests of the texture set (src/scene/texture.h).
 *
 * Small images written with stb_image_write into a temporary folder (PNG, TGA, JPEG, HDR) pin
 * down the texel words, the flags, the sampling (against the closed-form sRGB curve and means of
 * texels computed here, not by the code under test), the file-name fallbacks and every error.
 * Then, when $VKRT_SCENES_DIR is set, every texture the .mtl files of the textured shared scenes
 * name is loaded through the OBJ loader's map_Kd / map_d, as the scene loader does.
 */
#define _XOPEN_SOURCE 700
#include <dirent.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>
#include <stb_image_write.h>

#include "../glsl/shared.h"
#include "scene/obj/obj_load.h"
#include "scene/texture.h"
#include "scene/texture_levels.h"
#include "temp_dir.h"

/* ------------------------------------------------------------------------ helpers */

static const char *write_png(temp_dir *fx, const char *name, int w, int h, int comp,
                             const unsigned char *px)
{
    assert_true(stbi_write_png(temp_dir_path(fx, name), w, h, comp, px, w * comp) != 0);
    return fx->path;
}

static uint32_t add_ok(vkrt_texture_set *set, const char *path, vkrt_texture_usage usage)
{
    uint32_t index = 12345;
    vkrt_error err = {{0}};
    if (!vkrt_texture_set_add(set, path, usage, "test", &index, &err))
        fail_msg("adding %s failed: %s", path, err.msg);
    return index;
}

/* Adds path expecting failure with exactly "test.mtl:7: texture '<path>': <reason...>" where the
 * reason starts with `reason`; the set must be unchanged. */
static void add_fails(vkrt_texture_set *set, const char *path, vkrt_texture_usage usage,
                      const char *reason)
{
    vkrt_texture_set before = *set;
    uint32_t index = 777;
    vkrt_error err = {{0}};
    assert_false(vkrt_texture_set_add(set, path, usage, "test.mtl:7", &index, &err));
    char want[1024];
    snprintf(want, sizeof want, "test.mtl:7: texture '%s': %s", path, reason);
    if (strncmp(err.msg, want, strlen(want)) != 0)
        fail_msg("error \"%s\" does not start with \"%s\"", err.msg, want);
    assert_int_equal(index, 777);
    assert_int_equal(set->count, before.count);
    assert_int_equal(set->texel_words, before.texel_words);
}

/* The sRGB decoding curve of IEC 61966-2-1, in double: the reference the sampler must match. */
static double srgb(double c)
{
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

static void assert_near(double got, double want, double tolerance, const char *what)
{
    if (!(fabs(got - want) <= tolerance))
        fail_msg("%s: got %.9g, want %.9g (tolerance %g)", what, got, want, tolerance);
}

static void assert_rgba_near(const float got[4], const double want[4], double tolerance,
                             const char *what)
{
    for (int k = 0; k < 4; k++) {
        char label[200];
        snprintf(label, sizeof label, "%s, channel %d", what, k);
        assert_near(got[k], want[k], tolerance, label);
    }
}

/* A small RGB image with distinct, uneven values so any mix-up of texels shows. */
enum { W = 4, H = 3 };
static unsigned char test_rgb[H][W][3];

static void fill_test_rgb(void)
{
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            for (int k = 0; k < 3; k++)
                test_rgb[y][x][k] = (unsigned char)((37 * x + 91 * y + 59 * k + 13 * x * y) % 256);
}

/* Texel (x, y) of test_rgb (y from the top) decoded from sRGB, alpha 1, in double. */
static void expected_texel(int x, int y, double out[4])
{
    x = ((x % W) + W) % W;
    y = ((y % H) + H) % H;
    for (int k = 0; k < 3; k++)
        out[k] = srgb(test_rgb[y][x][k] / 255.0);
    out[3] = 1.0;
}

/* ------------------------------------------------------------------------ formats and texels */

static void png_texel_words_and_flags(void **state)
{
    temp_dir *fx = *state;
    unsigned char px[2][3][4];
    for (int y = 0; y < 2; y++)
        for (int x = 0; x < 3; x++)
            for (int k = 0; k < 4; k++)
                px[y][x][k] = (unsigned char)(10 * y + 3 * x + 100 * (k == 3) + k);
    const char *path = write_png(fx, "rgba.png", 3, 2, 4, &px[0][0][0]);
    vkrt_texture_set set = {0};
    assert_int_equal(add_ok(&set, path, VKRT_TEXTURE_COLOUR), 0);
    assert_int_equal(add_ok(&set, path, VKRT_TEXTURE_DATA), 1);
    assert_int_equal(set.count, 2);
    /* 3 x 2 texels and a 1 x 1 level each. */
    assert_int_equal(set.texel_words, 14);
    assert_int_equal(set.info[0].offset, 0);
    assert_int_equal(set.info[0].width, 3);
    assert_int_equal(set.info[0].height, 2);
    assert_int_equal(set.info[0].flags, VKRT_TEXTURE_SRGB | VKRT_TEXTURE_LEVELS(1u));
    assert_int_equal(set.info[1].offset, 7);
    assert_int_equal(set.info[1].flags, VKRT_TEXTURE_LEVELS(1u));
    assert_int_equal(set.usages[0], VKRT_TEXTURE_COLOUR);
    assert_int_equal(set.usages[1], VKRT_TEXTURE_DATA);
    char *canonical = realpath(path, NULL);
    assert_string_equal(set.paths[0], canonical);
    free(canonical);
    /* Rows top first as in the file, r in the low byte, for both copies. */
    for (int t = 0; t < 2; t++)
        for (int y = 0; y < 2; y++)
            for (int x = 0; x < 3; x++) {
                const unsigned char *p = px[y][x];
                uint32_t want =
                    p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
                assert_int_equal(set.texels[set.info[t].offset + (uint32_t)(y * 3 + x)], want);
            }
    /* DATA is linear: texel = byte / 255, alpha too. */
    float got[4];
    vkrt_texture_texel(&set, 1, 2, 1, got);
    double want[4] = {px[1][2][0] / 255.0, px[1][2][1] / 255.0, px[1][2][2] / 255.0,
                      px[1][2][3] / 255.0};
    assert_rgba_near(got, want, 1e-7, "data texel");
    vkrt_texture_set_free(&set);
    assert_null(set.info);
    assert_int_equal(set.count, 0);
    vkrt_texture_set_free(&set); /* safe on a zeroed set */
}

/* Every 8-bit level through the COLOUR path against the closed-form curve, alpha untouched. */
static void srgb_decoding_matches_closed_form(void **state)
{
    temp_dir *fx = *state;
    unsigned char px[256][4];
    for (int i = 0; i < 256; i++) {
        px[i][0] = (unsigned char)i;
        px[i][1] = (unsigned char)(255 - i);
        px[i][2] = (unsigned char)((i * 7) % 256);
        px[i][3] = (unsigned char)((i * 3) % 256);
    }
    const char *path = write_png(fx, "levels.png", 256, 1, 4, &px[0][0]);
    vkrt_texture_set set = {0};
    uint32_t t = add_ok(&set, path, VKRT_TEXTURE_COLOUR);
    for (int i = 0; i < 256; i++) {
        double want[4] = {srgb(px[i][0] / 255.0), srgb(px[i][1] / 255.0), srgb(px[i][2] / 255.0),
                          px[i][3] / 255.0};
        float got[4];
        vkrt_texture_texel(&set, t, i, 0, got);
        assert_rgba_near(got, want, 2e-7, "sRGB texel");
        /* at the texel's centre the bilinear sample is the texel */
        vkrt_texture_sample(&set, t, (i + 0.5f) / 256.0f, 0.5f, got);
        assert_rgba_near(got, want, 2e-7, "sample at a texel centre");
    }
    /* Two known points of the curve, so a mistake shared by srgb() above would show too. */
    float got[4];
    vkrt_texture_texel(&set, t, 255, 0, got);
    assert_near(got[0], 1.0, 1e-7, "sRGB 255");
    vkrt_texture_texel(&set, t, 10, 0, got); /* 10/255 = 0.0392 < 0.04045: linear segment */
    assert_near(got[0], 10.0 / 255.0 / 12.92, 1e-9, "sRGB 10");
    vkrt_texture_texel(&set, t, 128, 0, got);
    assert_near(got[0], 0.2158605, 1e-6, "sRGB 128"); /* the published value */
    vkrt_texture_set_free(&set);
}

static void tga_is_lossless_and_jpeg_close(void **state)
{
    temp_dir *fx = *state;
    enum { N = 16 };
    unsigned char px[N][N][3];
    for (int y = 0; y < N; y++)
        for (int x = 0; x < N; x++) {
            px[y][x][0] = (unsigned char)(x * 16);
            px[y][x][1] = (unsigned char)(y * 16);
            px[y][x][2] = (unsigned char)(128 + 4 * (x - y));
        }
    assert_true(stbi_write_tga(temp_dir_path(fx, "grad.tga"), N, N, 3, px) != 0);
    char tga[512];
    snprintf(tga, sizeof tga, "%s", fx->path);
    assert_true(stbi_write_jpg(temp_dir_path(fx, "grad.jpg"), N, N, 3, px, 100) != 0);
    vkrt_texture_set set = {0};
    uint32_t t = add_ok(&set, tga, VKRT_TEXTURE_DATA);
    uint32_t j = add_ok(&set, fx->path, VKRT_TEXTURE_DATA);
    assert_int_equal(set.info[j].offset, vkrt_texture_words_with_levels(N, N, 1));
    for (int y = 0; y < N; y++)
        for (int x = 0; x < N; x++) {
            uint32_t want = px[y][x][0] | (uint32_t)px[y][x][1] << 8 | (uint32_t)px[y][x][2] << 16 |
                            0xFF000000u;
            assert_int_equal(set.texels[set.info[t].offset + (uint32_t)(y * N + x)], want);
            uint32_t got = set.texels[set.info[j].offset + (uint32_t)(y * N + x)];
            for (int k = 0; k < 3; k++) {
                int d = (int)((got >> (8 * k)) & 0xFF) - px[y][x][k];
                if (abs(d) > 6) /* JPEG at quality 100 of a smooth gradient: a few levels */
                    fail_msg("JPEG texel (%d, %d) channel %d off by %d", x, y, k, d);
            }
            assert_int_equal(got >> 24, 0xFF);
        }
    vkrt_texture_set_free(&set);
}

/* Half-float bit patterns written out by hand (sign | exponent + 15 << 10 | mantissa). */
static void hdr_becomes_half_floats(void **state)
{
    temp_dir *fx = *state;
    /* Values whose channels share an exponent are exact in RGBE (8-bit mantissas), and then in
     * half, except below half's normal range (2^-14), where they round to steps of 2^-24. */
    const float tiny = 0x1p-30f;
    const float px[2][3][3] = {
        {{1.0f, 0.5f, 0.25f}, {4.0f, 2.0f, 3.0f}, {255 * tiny, 96 * tiny, 0.0f}},
        {{0.125f, 0.0625f, 0.09375f}, {100000.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}},
    };
    const uint16_t half[2][3][3] = {
        /* 255 * 2^-30 = 3.98 * 2^-24 rounds to 4 steps; 96 * 2^-30 = 1.5 steps, a tie, to even 2 */
        {{0x3C00, 0x3800, 0x3400}, {0x4400, 0x4000, 0x4200}, {0x0004, 0x0002, 0x0000}},
        {{0x3000, 0x2C00, 0x2E00}, {0x7BFF, 0x0000, 0x0000}, {0, 0, 0}}, /* beyond half: 65504 */
    };
    assert_true(stbi_write_hdr(temp_dir_path(fx, "sky.hdr"), 3, 2, 3, &px[0][0][0]) != 0);
    vkrt_texture_set set = {0};
    uint32_t t = add_ok(&set, fx->path, VKRT_TEXTURE_COLOUR);
    /* Linear already: no sRGB flag. 3 x 2 texels and a 1 x 1 level, two words each. */
    assert_int_equal(set.info[t].flags, VKRT_TEXTURE_HALF | VKRT_TEXTURE_LEVELS(1u));
    assert_int_equal(set.texel_words, 14);
    for (int y = 0; y < 2; y++)
        for (int x = 0; x < 3; x++) {
            const uint32_t *w = &set.texels[2 * (y * 3 + x)];
            assert_int_equal(w[0], half[y][x][0] | (uint32_t)half[y][x][1] << 16);
            assert_int_equal(w[1], half[y][x][2] | 0x3C00u << 16); /* alpha 1 */
        }
    float got[4];
    vkrt_texture_sample(&set, t, 0.5f, 0.75f, got); /* texel (1, 0) */
    const double want[4] = {4, 2, 3, 1};
    assert_rgba_near(got, want, 0, "HDR sample at a texel centre");
    vkrt_texture_sample(&set, t, 1.0f / 3.0f, 0.75f, got); /* between (0, 0) and (1, 0) */
    const double mean[4] = {2.5, 1.25, 1.625, 1};
    assert_rgba_near(got, mean, 1e-6, "HDR sample between two texels");
    /* as coverage: its first channel (RGBE has no alpha) in all four */
    uint32_t a = add_ok(&set, fx->path, VKRT_TEXTURE_ALPHA);
    assert_int_equal(set.info[a].flags, VKRT_TEXTURE_HALF | VKRT_TEXTURE_LEVELS(1u));
    const uint32_t *w = &set.texels[set.info[a].offset + 2];
    assert_int_equal(w[0], 0x44004400u);
    assert_int_equal(w[1], 0x44004400u);
    vkrt_texture_set_free(&set);
}

/* ------------------------------------------------------------------------ sampling */

static void bilinear_sample_and_wrap(void **state)
{
    temp_dir *fx = *state;
    fill_test_rgb();
    const char *path = write_png(fx, "test.png", W, H, 3, &test_rgb[0][0][0]);
    vkrt_texture_set set = {0};
    uint32_t t = add_ok(&set, path, VKRT_TEXTURE_COLOUR);
    const double tol = 1e-6;
    float got[4];
    double want[4], a[4], b[4], c[4], d[4];
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            /* texel (x, y) from the top has its centre at u = (x + .5) / W, v = 1 - (y + .5) / H */
            float u = (x + 0.5f) / W, v = 1.0f - (y + 0.5f) / H;
            expected_texel(x, y, want);
            vkrt_texture_sample(&set, t, u, v, got);
            assert_rgba_near(got, want, tol, "texel centre");
            /* any whole number of repeats, negative or not, is the same place */
            vkrt_texture_sample(&set, t, u - 3.0f, v + 2.0f, got);
            assert_rgba_near(got, want, tol, "texel centre, uv - (3, -2)");
            vkrt_texture_sample(&set, t, u + 5.0f, v - 4.0f, got);
            assert_rgba_near(got, want, tol, "texel centre, uv + (5, -4)");
            /* halfway to the right neighbour (wrapping past the last column): the mean after
             * decoding */
            expected_texel(x, y, a);
            expected_texel(x + 1, y, b);
            vkrt_texture_sample(&set, t, (float)(x + 1) / W, v, got);
            for (int k = 0; k < 4; k++)
                want[k] = 0.5 * (a[k] + b[k]);
            assert_rgba_near(got, want, tol, "halfway between horizontal neighbours");
            /* halfway to the row below, and to the four around a corner */
            expected_texel(x, y + 1, c);
            expected_texel(x + 1, y + 1, d);
            float v_below = 1.0f - (float)(y + 1) / H;
            vkrt_texture_sample(&set, t, u, v_below, got);
            for (int k = 0; k < 4; k++)
                want[k] = 0.5 * (a[k] + c[k]);
            assert_rgba_near(got, want, tol, "halfway between vertical neighbours");
            vkrt_texture_sample(&set, t, (float)(x + 1) / W, v_below, got);
            for (int k = 0; k < 4; k++)
                want[k] = 0.25 * (a[k] + b[k] + c[k] + d[k]);
            assert_rgba_near(got, want, tol, "centre of four texels");
        }
    /* u = 0 and u = 1 are the seam between the last and first column */
    float v0 = 1.0f - 0.5f / H; /* centre of the top row */
    expected_texel(W - 1, 0, a);
    expected_texel(0, 0, b);
    for (int k = 0; k < 4; k++)
        want[k] = 0.5 * (a[k] + b[k]);
    vkrt_texture_sample(&set, t, 0.0f, v0, got);
    assert_rgba_near(got, want, tol, "u = 0");
    vkrt_texture_sample(&set, t, 1.0f, v0, got);
    assert_rgba_near(got, want, tol, "u = 1");
    vkrt_texture_sample(&set, t, -1.0f, v0, got);
    assert_rgba_near(got, want, tol, "u = -1");
    /* v = 0 (bottom edge) and v = 1 (top edge) are the seam between the bottom and top rows */
    expected_texel(0, H - 1, a);
    expected_texel(0, 0, b);
    for (int k = 0; k < 4; k++)
        want[k] = 0.5 * (a[k] + b[k]);
    vkrt_texture_sample(&set, t, 0.5f / W, 0.0f, got);
    assert_rgba_near(got, want, tol, "v = 0");
    vkrt_texture_sample(&set, t, 0.5f / W, 1.0f, got);
    assert_rgba_near(got, want, tol, "v = 1");
    /* a quarter of the way from texel (1, 1) to (2, 1): 3/4 of one, 1/4 of the other */
    expected_texel(1, 1, a);
    expected_texel(2, 1, b);
    for (int k = 0; k < 4; k++)
        want[k] = 0.75 * a[k] + 0.25 * b[k];
    vkrt_texture_sample(&set, t, 1.75f / W, 1.0f - 1.5f / H, got);
    assert_rgba_near(got, want, tol, "a quarter of the way");
    /* non-finite uv read as (0, 0): the four corner texels' mean */
    vkrt_texture_sample(&set, t, NAN, INFINITY, got);
    expected_texel(0, 0, a);
    expected_texel(W - 1, 0, b);
    expected_texel(0, H - 1, c);
    expected_texel(W - 1, H - 1, d);
    for (int k = 0; k < 4; k++)
        want[k] = 0.25 * (a[k] + b[k] + c[k] + d[k]);
    assert_rgba_near(got, want, tol, "non-finite uv");
    /* texel reads wrap in both directions, far out too */
    vkrt_texture_texel(&set, t, -1, -1, got);
    expected_texel(W - 1, H - 1, want);
    assert_rgba_near(got, want, tol, "texel (-1, -1)");
    vkrt_texture_texel(&set, t, W * 1000 + 2, -H * 77 + 1, got);
    expected_texel(2, 1, want);
    assert_rgba_near(got, want, tol, "texel far out");
    vkrt_texture_texel(&set, t, INT32_MIN, INT32_MIN, got);
    expected_texel((int)(((int64_t)INT32_MIN % W + W) % W), (int)(((int64_t)INT32_MIN % H + H) % H),
                   want);
    assert_rgba_near(got, want, tol, "texel at INT_MIN");
    /* an index past the set gives 0 */
    vkrt_texture_sample(&set, 5, 0.5f, 0.5f, got);
    const double zero[4] = {0, 0, 0, 0};
    assert_rgba_near(got, zero, 0, "index past the set");
    vkrt_texture_set_free(&set);
}

/* The mean of a texture as the kernels read it (sRGB decoded for colour maps), and which images
 * read as normal maps: bluish ones about (0.5, 0.5, 1), not grey or colour height maps. */
static void mean_and_which_images_are_normal_maps(void **state)
{
    temp_dir *fx = *state;
    const unsigned char flat[2][3] = {{128, 128, 255}, {128, 128, 255}};
    const unsigned char tilted[2][3] = {{166, 107, 232}, {90, 150, 240}};
    const unsigned char white[2][3] = {{255, 255, 255}, {200, 200, 200}};
    const unsigned char grey_bluish[2][3] = {{150, 150, 190}, {150, 150, 190}};
    const unsigned char half[2][3] = {{0, 0, 0}, {255, 255, 255}};
    vkrt_texture_set set = {0};
    uint32_t t_flat = add_ok(&set, write_png(fx, "flat.png", 2, 1, 3, &flat[0][0]),
                             VKRT_TEXTURE_DATA);
    uint32_t t_tilted = add_ok(&set, write_png(fx, "tilted.png", 2, 1, 3, &tilted[0][0]),
                               VKRT_TEXTURE_DATA);
    uint32_t t_white = add_ok(&set, write_png(fx, "white.png", 2, 1, 3, &white[0][0]),
                              VKRT_TEXTURE_DATA);
    uint32_t t_bluish = add_ok(&set, write_png(fx, "bluish.png", 2, 1, 3, &grey_bluish[0][0]),
                               VKRT_TEXTURE_DATA);
    uint32_t t_half = add_ok(&set, write_png(fx, "half.png", 2, 1, 3, &half[0][0]),
                             VKRT_TEXTURE_COLOUR);
    assert_true(vkrt_texture_is_normal_map(&set, t_flat));
    assert_true(vkrt_texture_is_normal_map(&set, t_tilted));
    assert_false(vkrt_texture_is_normal_map(&set, t_white));
    assert_false(vkrt_texture_is_normal_map(&set, t_bluish));
    float mean[4];
    vkrt_texture_mean(&set, t_half, mean);
    for (int k = 0; k < 3; k++)
        assert_float_equal(mean[k], 0.5f, 1e-6f);
    vkrt_texture_mean(&set, t_white, mean); /* data: (255 + 200) / 2 / 255, no decoding */
    assert_float_equal(mean[0], (1.0f + 200.0f / 255.0f) / 2.0f, 1e-6f);
    vkrt_texture_set_free(&set);
}

/* ALPHA: the alpha channel where the image has one that is not opaque everywhere, else its first
 * channel, in all four (an RGBA mask with alpha 255 throughout carries coverage in its colour). */
static void alpha_usage_picks_the_channel(void **state)
{
    temp_dir *fx = *state;
    const unsigned char grey[2] = {10, 200};
    const unsigned char grey_alpha[2][2] = {{10, 77}, {200, 3}};
    const unsigned char rgb[2][3] = {{30, 40, 50}, {60, 70, 80}};
    const unsigned char rgba[2][4] = {{30, 40, 50, 99}, {60, 70, 80, 250}};
    const unsigned char rgba_opaque[2][4] = {{0, 0, 0, 255}, {255, 255, 255, 255}};
    const unsigned char grey_opaque[2][2] = {{20, 255}, {220, 255}};
    struct {
        const char *name;
        int comp;
        const unsigned char *px;
        unsigned char want[2];
    } cases[] = {
        {"grey.png", 1, grey, {10, 200}},
        {"grey_alpha.png", 2, &grey_alpha[0][0], {77, 3}},
        {"rgb.png", 3, &rgb[0][0], {30, 60}},
        {"rgba.png", 4, &rgba[0][0], {99, 250}},
        {"rgba_opaque.png", 4, &rgba_opaque[0][0], {0, 255}},
        {"grey_opaque.png", 2, &grey_opaque[0][0], {20, 220}},
    };
    vkrt_texture_set set = {0};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        uint32_t t = add_ok(&set, write_png(fx, cases[i].name, 2, 1, cases[i].comp, cases[i].px),
                            VKRT_TEXTURE_ALPHA);
        assert_int_equal(set.info[t].flags, VKRT_TEXTURE_LEVELS(1u)); /* coverage is linear */
        for (int x = 0; x < 2; x++) {
            assert_int_equal(set.texels[set.info[t].offset + (uint32_t)x],
                             cases[i].want[x] * 0x01010101u);
            float got[4];
            vkrt_texture_texel(&set, t, x, 0, got);
            double v = cases[i].want[x] / 255.0;
            const double want[4] = {v, v, v, v};
            assert_rgba_near(got, want, 1e-7, cases[i].name);
        }
    }
    /* a grey image as a colour map expands to grey RGB, opaque */
    uint32_t c = add_ok(&set, temp_dir_path(fx, "grey.png"), VKRT_TEXTURE_COLOUR);
    assert_int_equal(set.texels[set.info[c].offset + 1], 0xFFC8C8C8u);
    vkrt_texture_set_free(&set);
}

/* ------------------------------------------------------------------------ paths */

static void same_file_same_usage_is_loaded_once(void **state)
{
    temp_dir *fx = *state;
    fill_test_rgb();
    char path[512], other[700];
    snprintf(path, sizeof path, "%s", write_png(fx, "tex.png", W, H, 3, &test_rgb[0][0][0]));
    vkrt_texture_set set = {0};
    assert_int_equal(add_ok(&set, path, VKRT_TEXTURE_COLOUR), 0);
    assert_int_equal(add_ok(&set, path, VKRT_TEXTURE_COLOUR), 0);
    snprintf(other, sizeof other, "%s/./tex.png", fx->dir);
    assert_int_equal(add_ok(&set, other, VKRT_TEXTURE_COLOUR), 0);
    assert_int_equal(mkdir(temp_dir_path(fx, "sub"), 0700), 0);
    snprintf(other, sizeof other, "%s/sub/../tex.png", fx->dir);
    assert_int_equal(add_ok(&set, other, VKRT_TEXTURE_COLOUR), 0);
    snprintf(other, sizeof other, "%s/TEX.PNG", fx->dir); /* found ignoring case: the same file */
    assert_int_equal(add_ok(&set, other, VKRT_TEXTURE_COLOUR), 0);
    assert_int_equal(set.count, 1);
    assert_int_equal(set.texel_words, vkrt_texture_words_with_levels(W, H, 1));
    /* another usage is another texture */
    assert_int_equal(add_ok(&set, path, VKRT_TEXTURE_ALPHA), 1);
    assert_int_equal(add_ok(&set, other, VKRT_TEXTURE_ALPHA), 1);
    assert_int_equal(set.count, 2);
    vkrt_texture_set_free(&set);
}

static void file_name_case_and_backslashes(void **state)
{
    temp_dir *fx = *state;
    const unsigned char px[4] = {1, 2, 3, 4};
    char path[700];
    write_png(fx, "sp_luk.JPG.png", 1, 1, 4, px);
    vkrt_texture_set set = {0};
    vkrt_error err = {{0}};
    uint32_t index = 99;
    /* the Windows spelling of the name (as dabrovic-sponza's .mtl has it) */
    snprintf(path, sizeof path, "%s/SP_LUK.JPG.PNG", fx->dir);
    assert_true(vkrt_texture_set_add(&set, path, VKRT_TEXTURE_COLOUR, "x.mtl:1", &index, &err));
    assert_int_equal(index, 0);
    assert_non_null(strstr(set.paths[0], "/sp_luk.JPG.png"));
    /* a backslash as folder separator, and the name's case wrong too */
    assert_int_equal(mkdir(temp_dir_path(fx, "maps"), 0700), 0);
    write_png(fx, "maps/Wall.png", 1, 1, 4, px);
    snprintf(path, sizeof path, "%s/maps\\WALL.png", fx->dir);
    assert_true(vkrt_texture_set_add(&set, path, VKRT_TEXTURE_COLOUR, "x.mtl:2", &index, &err));
    assert_int_equal(index, 1);
    assert_non_null(strstr(set.paths[1], "/maps/Wall.png"));
    /* two files that match ignoring case: no guess */
    write_png(fx, "amb.png", 1, 1, 4, px);
    write_png(fx, "AMB.png", 1, 1, 4, px);
    snprintf(path, sizeof path, "%s/Amb.png", fx->dir);
    add_fails(&set, path, VKRT_TEXTURE_COLOUR,
              "not found, and 2 files match its name ignoring case");
    /* the folders themselves must be spelt right */
    snprintf(path, sizeof path, "%s/MAPS/Wall.png", fx->dir);
    add_fails(&set, path, VKRT_TEXTURE_COLOUR, "cannot open: No such file or directory");
    assert_int_equal(set.count, 2);
    vkrt_texture_set_free(&set);
}

/* ------------------------------------------------------------------------ errors */

static void errors_name_referrer_and_path(void **state)
{
    temp_dir *fx = *state;
    const unsigned char px[4] = {1, 2, 3, 4};
    vkrt_texture_set set = {0};
    /* start from a set with one texture: failures must leave it as it was */
    add_ok(&set, write_png(fx, "ok.png", 1, 1, 4, px), VKRT_TEXTURE_COLOUR);

    add_fails(&set, temp_dir_path(fx, "missing.png"), VKRT_TEXTURE_COLOUR,
              "cannot open: No such file or directory");
    add_fails(&set, temp_dir_write(fx, "garbage.png", "this is not an image at all\n", 28),
              VKRT_TEXTURE_COLOUR, "not an image vkrt can read (stb_image: ");
    add_fails(&set, temp_dir_write(fx, "empty.png", "", 0), VKRT_TEXTURE_COLOUR,
              "the file is empty");
    add_fails(&set, fx->dir, VKRT_TEXTURE_COLOUR, "not a regular file");
    /* a PNG header claiming a width of 0 (stb_image refuses it itself) */
    const unsigned char zero_width[] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n', 0, 0, 0,
                                        13,   'I', 'H', 'D', 'R',  0,    0,    0,    0, 0, 0,
                                        0,    1,   8,   0,   0,    0,    0,    0,    0, 0, 0};
    add_fails(&set, temp_dir_write(fx, "zero.png", zero_width, sizeof zero_width),
              VKRT_TEXTURE_COLOUR, "not an image vkrt can read");
    /* a real PNG cut short: the header reads, the pixels do not */
    static unsigned char big[64][64][3];
    for (int i = 0; i < 64 * 64 * 3; i++)
        (&big[0][0][0])[i] = (unsigned char)(i * 7919 % 251);
    write_png(fx, "big.png", 64, 64, 3, &big[0][0][0]);
    FILE *f = fopen(fx->path, "rb");
    assert_non_null(f);
    static unsigned char bytes[1 << 16];
    size_t n = fread(bytes, 1, sizeof bytes, f);
    fclose(f);
    assert_true(n > 200);
    /* stb_image's own reason is empty here (it reads zeros past the end): the message says where
     * the file ends and which chunk it cuts */
    char cut_reason[200];
    snprintf(cut_reason, sizeof cut_reason,
             "cannot decode the image: the PNG file is cut short: it has %zu bytes, but its IDAT "
             "chunk at byte 33 runs to byte %zu",
             n / 2, n - 12);
    add_fails(&set, temp_dir_write(fx, "cut.png", bytes, n / 2), VKRT_TEXTURE_COLOUR, cut_reason);
    vkrt_texture_set fresh = {0}; /* the room reserved for the texels is given back */
    add_fails(&fresh, fx->path, VKRT_TEXTURE_COLOUR, cut_reason);
    assert_null(fresh.texels);
    vkrt_texture_set_free(&fresh);
    /* cut at the end of a chunk, where the next chunk header should start */
    char ends_reason[200];
    snprintf(ends_reason, sizeof ends_reason,
             "cannot decode the image: the PNG file is cut short: it ends at byte %zu, before its "
             "IEND chunk",
             n - 12);
    add_fails(&set, temp_dir_write(fx, "no_iend.png", bytes, n - 12), VKRT_TEXTURE_COLOUR,
              ends_reason);
    /* one texel wider than allowed */
    static unsigned char row[VKRT_TEXTURE_MAX_SIZE + 1];
    add_fails(&set, write_png(fx, "wide.png", VKRT_TEXTURE_MAX_SIZE + 1, 1, 1, row),
              VKRT_TEXTURE_COLOUR,
              "image is 16385x1; textures must be 1 to 16384 texels wide and tall");
    add_fails(&set, write_png(fx, "tall.png", 1, VKRT_TEXTURE_MAX_SIZE + 1, 1, row),
              VKRT_TEXTURE_DATA, "image is 1x16385;");
    /* no referrer: the message starts at "texture" */
    vkrt_error err = {{0}};
    uint32_t index;
    assert_false(vkrt_texture_set_add(&set, temp_dir_path(fx, "missing.png"), VKRT_TEXTURE_DATA,
                                      NULL, &index, &err));
    char want[700];
    snprintf(want, sizeof want, "texture '%s': cannot open: No such file or directory", fx->path);
    assert_string_equal(err.msg, want);

    assert_int_equal(set.count, 1);
    assert_int_equal(set.texel_words, 1);
    assert_int_equal(set.texels[0], 0x04030201u);
    vkrt_texture_set_free(&set);
}

static void size_limit_is_reported_in_mib(void **state)
{
    temp_dir *fx = *state;
    static unsigned char px[512][512];
    char first[512], second[512]; /* 1 MiB of texels each, 4/3 MiB with their levels */
    snprintf(first, sizeof first, "%s", write_png(fx, "grey512.png", 512, 512, 1, &px[0][0]));
    snprintf(second, sizeof second, "%s", write_png(fx, "grey512b.png", 512, 512, 1, &px[0][0]));
    vkrt_texture_set set = {.max_texel_bytes = 3 << 19}; /* 1.5 MiB */
    add_ok(&set, first, VKRT_TEXTURE_COLOUR);
    add_ok(&set, first, VKRT_TEXTURE_COLOUR); /* a repeat costs nothing */
    add_fails(
        &set, second, VKRT_TEXTURE_COLOUR,
        "this 512x512 texture takes 1.3 MiB; with the 1 textures before it the textures would take "
        "2.7 MiB, over the limit of 1.5 MiB"); /* with their mipmap levels: a third more */
    vkrt_texture_set_free(&set);
    assert_int_equal(set.max_texel_bytes, 3 << 19); /* free keeps the limit */
    /* exactly at the limit is fine */
    size_t both = 2 * vkrt_texture_words_with_levels(512, 512, 1) * 4;
    set.max_texel_bytes = both;
    add_ok(&set, first, VKRT_TEXTURE_COLOUR);
    add_ok(&set, second, VKRT_TEXTURE_COLOUR);
    assert_int_equal(set.texel_words * 4, both);
    vkrt_texture_set_free(&set);
}

/* Adds each of paths (an "embedded:" prefix: the bytes of the file after it, through
 * add_memory) as usage[i], recording each add's index or error message. */
static void add_all(vkrt_texture_set *set, const char *const *paths, const vkrt_texture_usage *usage,
                    const unsigned char *bytes, size_t size, int count, uint32_t *index,
                    char (*msg)[1024])
{
    for (int i = 0; i < count; i++) {
        vkrt_error err = {{0}};
        bool ok = strncmp(paths[i], "embedded:", 9) == 0
                      ? vkrt_texture_set_add_memory(set, bytes, size, paths[i], usage[i],
                                                    "test.gltf", &index[i], &err)
                      : vkrt_texture_set_add(set, paths[i], usage[i], "test.mtl:3", &index[i],
                                             &err);
        snprintf(msg[i], sizeof msg[i], "%s", ok ? "" : err.msg);
    }
}

/* Decoding ahead on several threads, then adding, gives the set that adding alone gives: the
 * same entries in the same order, the same texels, the same errors (a missing file, an image
 * past max_texel_bytes), whatever order the images were decoded in. */
static void decoding_ahead_changes_nothing(void **state)
{
    temp_dir *fx = *state;
    enum { AW = 37, AH = 23, N = 8 };
    static unsigned char rgba[AH][AW][4], grey[AH][AW][2];
    for (int y = 0; y < AH; y++)
        for (int x = 0; x < AW; x++) {
            for (int c = 0; c < 4; c++)
                rgba[y][x][c] = (unsigned char)(x * 7 + y * 13 + c * 61);
            grey[y][x][0] = (unsigned char)(x * y);
            grey[y][x][1] = (unsigned char)(255 - x);
        }
    char colour[512], mask[512], big[512], missing[600];
    snprintf(colour, sizeof colour, "%s", write_png(fx, "ahead-rgba.png", AW, AH, 4, &rgba[0][0][0]));
    snprintf(mask, sizeof mask, "%s", write_png(fx, "ahead-grey.png", AW, AH, 2, &grey[0][0][0]));
    static unsigned char large[256][256];
    snprintf(big, sizeof big, "%s", write_png(fx, "ahead-big.png", 256, 256, 1, &large[0][0]));
    snprintf(missing, sizeof missing, "%s/ahead-none.png", fx->dir);
    FILE *f = fopen(colour, "rb");
    assert_non_null(f);
    static unsigned char bytes[1 << 16];
    size_t size = fread(bytes, 1, sizeof bytes, f);
    fclose(f);
    const char *paths[N] = {colour, mask, "embedded:image 0", colour, missing, mask, big,
                            "embedded:image 0"};
    const vkrt_texture_usage usage[N] = {VKRT_TEXTURE_COLOUR, VKRT_TEXTURE_ALPHA,
                                         VKRT_TEXTURE_DATA,   VKRT_TEXTURE_DATA,
                                         VKRT_TEXTURE_COLOUR, VKRT_TEXTURE_DATA,
                                         VKRT_TEXTURE_COLOUR, VKRT_TEXTURE_DATA};
    /* Room for the small ones, not for the 256 x 256 one after them. */
    size_t limit = 6 * vkrt_texture_words_with_levels(AW, AH, 1) * 4 + 1000;
    vkrt_texture_set alone = {.max_texel_bytes = limit}, ahead = {.max_texel_bytes = limit};
    uint32_t index_alone[N], index_ahead[N];
    char msg_alone[N][1024], msg_ahead[N][1024];
    add_all(&alone, paths, usage, bytes, size, N, index_alone, msg_alone);

    vkrt_texture_source sources[N];
    for (int i = 0; i < N; i++) { /* backwards: the order of decoding is not the adds' */
        int k = N - 1 - i;
        bool embedded = strncmp(paths[k], "embedded:", 9) == 0;
        sources[i] = (vkrt_texture_source){paths[k], embedded ? bytes : NULL,
                                           embedded ? size : 0, usage[k]};
    }
    setenv("VKRT_TEXTURE_THREADS", "4", 1);
    vkrt_texture_set_decode_ahead(&ahead, sources, N);
    unsetenv("VKRT_TEXTURE_THREADS");
    /* Decoded ahead: the five small images (the embedded one, mask as data and as coverage,
     * colour as data and as colour); not the missing file, nor the big one, past the limit. */
    assert_int_equal(ahead.ahead_count, 5);
    assert_int_equal(ahead.count, 0);
    add_all(&ahead, paths, usage, bytes, size, N, index_ahead, msg_ahead);

    assert_int_equal(ahead.count, alone.count);
    assert_int_equal(ahead.texel_words, alone.texel_words);
    assert_memory_equal(ahead.texels, alone.texels, alone.texel_words * 4);
    assert_memory_equal(ahead.info, alone.info, alone.count * sizeof *alone.info);
    assert_memory_equal(ahead.usages, alone.usages, alone.count * sizeof *alone.usages);
    for (uint32_t i = 0; i < alone.count; i++)
        assert_string_equal(ahead.paths[i], alone.paths[i]);
    for (int i = 0; i < N; i++) {
        assert_string_equal(msg_ahead[i], msg_alone[i]);
        if (!msg_alone[i][0])
            assert_int_equal(index_ahead[i], index_alone[i]);
    }
    assert_non_null(strstr(msg_alone[4], "cannot open"));      /* missing */
    assert_non_null(strstr(msg_alone[6], "over the limit of")); /* big */
    vkrt_texture_set_free(&ahead);
    assert_int_equal(ahead.ahead_count, 0);
    vkrt_texture_set_free(&alone);
}

/* ------------------------------------------------------------------------ shared scenes */

static const char *scenes_dir(void)
{
    const char *dir = getenv("VKRT_SCENES_DIR");
    struct stat st;
    if (!dir || !*dir || stat(dir, &st) != 0 || !S_ISDIR(st.st_mode)) {
        printf("VKRT_SCENES_DIR %s; skipping shared-scene tests\n",
               dir ? "is not a folder" : "unset");
        return NULL;
    }
    return dir;
}

/* Loads every base colour (map_Kd) and coverage (map_d) map of the scene's OBJ as the scene loader does,
 * the referrer being the .mtl line that names it; all must load. */
static void load_scene_textures(const char *scene, const char *obj, uint32_t want_count)
{
    const char *dir = scenes_dir();
    if (!dir)
        skip();
    char path[1024];
    snprintf(path, sizeof path, "%s/%s/%s", dir, scene, obj);
    vkrt_model model = {0};
    vkrt_error err = {{0}};
    if (!vkrt_obj_load(path, &model, &err))
        fail_msg("%s", err.msg);
    vkrt_texture_set set = {0};
    uint32_t requests = 0;
    for (uint32_t i = 0; i < model.material_count; i++) {
        const vkrt_material *m = &model.materials[i];
        const vkrt_texture_ref *maps[2] = {&m->maps[VKRT_MAP_BASE_COLOUR],
                                           &m->maps[VKRT_MAP_COVERAGE]};
        for (int k = 0; k < 2; k++) {
            if (!maps[k]->path)
                continue;
            assert_true(maps[k]->line > 0);
            char referrer[1100];
            snprintf(referrer, sizeof referrer, "%s:%d", m->file, maps[k]->line);
            uint32_t index;
            if (!vkrt_texture_set_add(&set, maps[k]->path, maps[k]->space, referrer, &index,
                                      &err))
                fail_msg("%s", err.msg);
            requests++;
        }
    }
    printf("%s: %u texture statements, %u textures, %.1f MiB of texels\n", scene, requests,
           set.count, (double)set.texel_words * 4 / (1024.0 * 1024.0));
    assert_int_equal(set.count, want_count);
    vkrt_texture_set_free(&set);
    vkrt_model_free(&model);
}

static void dabrovic_sponza_textures(void **state)
{
    (void)state;
    load_scene_textures("dabrovic-sponza", "sponza.obj", 12);
}

static void sibenik_cathedral_textures(void **state)
{
    (void)state;
    load_scene_textures("sibenik-cathedral", "sibenik.obj", 3);
}

static void lost_empire_textures(void **state)
{
    (void)state;
    load_scene_textures("lost-empire", "lost_empire.obj", 3);
}

/* ------------------------------------------------------------------------ samplers, transforms */

/* An image of w x h texels, each unique: red 3 + 30 x, green 3 + 30 y (x from the left, y from the
 * top row), blue 200, alpha 255 - x - 4 y; stored as data, so texels read as byte / 255. */
static uint32_t add_unique_image(temp_dir *fx, vkrt_texture_set *set, int w, int h)
{
    unsigned char px[8 * 8 * 4];
    assert_true(w <= 8 && h <= 8);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            unsigned char *p = &px[4 * (y * w + x)];
            p[0] = (unsigned char)(3 + 30 * x);
            p[1] = (unsigned char)(3 + 30 * y);
            p[2] = 200;
            p[3] = (unsigned char)(255 - x - 4 * y);
        }
    char name[32];
    snprintf(name, sizeof name, "unique%dx%d.png", w, h);
    return add_ok(set, write_png(fx, name, w, h, 4, px), VKRT_TEXTURE_DATA);
}

static void unique_texel(int x, int y, double out[4])
{
    out[0] = (3 + 30 * x) / 255.0;
    out[1] = (3 + 30 * y) / 255.0;
    out[2] = 200 / 255.0;
    out[3] = (255 - x - 4 * y) / 255.0;
}

static uint32_t view_ok(vkrt_texture_set *set, uint32_t base, uint32_t flags,
                        const float matrix[4], const float offset[2])
{
    static const float identity[4] = {1, 0, 0, 1}, zero[2] = {0, 0};
    uint32_t index = 12345;
    vkrt_error err = {{0}};
    if (!vkrt_texture_set_view(set, base, flags, matrix ? matrix : identity,
                               offset ? offset : zero, &index, &err))
        fail_msg("view 0x%x of texture %u failed: %s", flags, base, err.msg);
    return index;
}

/* The texel (x, y) a sample must give, to 1e-6. */
static void assert_sample_is_texel(const vkrt_texture_set *set, uint32_t tex, float u, float v,
                                   int x, int y)
{
    float got[4];
    double want[4];
    vkrt_texture_sample(set, tex, u, v, got);
    unique_texel(x, y, want);
    char what[96];
    snprintf(what, sizeof what, "texture %u at (%g, %g), want texel (%d, %d)", tex, (double)u,
             (double)v, x, y);
    assert_rgba_near(got, want, 1e-6, what);
}

#define BOTH(mode) (VKRT_TEXTURE_WRAP_U(mode) | VKRT_TEXTURE_WRAP_V(mode))

/* Nearest filtering under each wrap mode at uv whose texels are worked out by hand for a 4 x 3
 * image: image coordinates (s, t) = (u, 1 - v); repeat takes the fraction, clamp the edge, mirror
 * reflects every other period (s in [1, 2) reads 2 - s); texel floor(s * 4), floor(t * 3). */
static void wrap_modes_nearest(void **state)
{
    temp_dir *fx = *state;
    vkrt_texture_set set = {0};
    uint32_t image = add_unique_image(fx, &set, 4, 3);
    uint32_t repeat = view_ok(&set, image, VKRT_TEXTURE_NEAREST, NULL, NULL);
    uint32_t clamp = view_ok(&set, image, VKRT_TEXTURE_NEAREST | BOTH(VKRT_TEXTURE_CLAMP), NULL, NULL);
    uint32_t mirror = view_ok(&set, image, VKRT_TEXTURE_NEAREST | BOTH(VKRT_TEXTURE_MIRROR), NULL, NULL);
    uint32_t mixed = view_ok(&set, image,
                             VKRT_TEXTURE_NEAREST | VKRT_TEXTURE_WRAP_U(VKRT_TEXTURE_CLAMP) |
                                 VKRT_TEXTURE_WRAP_V(VKRT_TEXTURE_MIRROR),
                             NULL, NULL);
    /* s 1.1 -> 0.1 -> 0; t 0.1 -> 0. s -0.1 -> 0.9 -> 3; t -0.5 -> 0.5 -> 1. */
    assert_sample_is_texel(&set, repeat, 1.1f, 0.9f, 0, 0);
    assert_sample_is_texel(&set, repeat, -0.1f, 1.5f, 3, 1);
    /* s 1.1 -> the right edge, 3; s -0.1 -> 0; t -0.5 -> 0; t 4 -> the bottom row, 2. */
    assert_sample_is_texel(&set, clamp, 1.1f, 0.9f, 3, 0);
    assert_sample_is_texel(&set, clamp, -0.1f, 1.5f, 0, 0);
    assert_sample_is_texel(&set, clamp, 0.6f, -3.0f, 2, 2);
    /* s 1.1 reads 0.9 -> 3; s -0.1 reads 0.1 -> 0; t -0.5 reads 0.5 -> 1; s 2.3 reads 0.3 -> 1,
     * t 0.8 -> 2; s 1.6 reads 0.4 -> 1, t 1.4 reads 0.6 -> 1. */
    assert_sample_is_texel(&set, mirror, 1.1f, 0.9f, 3, 0);
    assert_sample_is_texel(&set, mirror, -0.1f, 1.5f, 0, 1);
    assert_sample_is_texel(&set, mirror, 2.3f, 0.2f, 1, 2);
    assert_sample_is_texel(&set, mirror, 1.6f, -0.4f, 1, 1);
    /* Across clamps, down mirrors: s 1.1 -> 3, t -0.5 reads 0.5 -> 1. */
    assert_sample_is_texel(&set, mixed, 1.1f, 1.5f, 3, 1);
    /* Texel addresses as Vulkan's samplers wrap them: mirror 0..3, 3..0; clamp to the edge. */
    static const struct {
        int x, repeat, clamp, mirror;
    } columns[] = {{-1, 3, 0, 0}, {4, 0, 3, 3}, {5, 1, 3, 2}, {8, 0, 3, 0},
                   {-5, 3, 0, 3}, {-9, 3, 0, 0}, {INT32_MIN, 0, 0, 0}, {INT32_MAX, 3, 3, 0}};
    for (size_t i = 0; i < sizeof columns / sizeof columns[0]; i++) {
        float got[4];
        double want[4];
        uint32_t views[3] = {repeat, clamp, mirror};
        int expect[3] = {columns[i].repeat, columns[i].clamp, columns[i].mirror};
        for (int k = 0; k < 3; k++) {
            vkrt_texture_texel(&set, views[k], columns[i].x, 1, got);
            unique_texel(expect[k], 1, want);
            assert_rgba_near(got, want, 1e-6, "texel address under a wrap mode");
        }
    }
    vkrt_texture_set_free(&set);
}

/* The blend half of texel (xa, y) and half of texel (xb, y). */
static void midway(int xa, int xb, int y, double want[4])
{
    double a[4], b[4];
    unique_texel(xa, y, a);
    unique_texel(xb, y, b);
    for (int k = 0; k < 4; k++)
        want[k] = 0.5 * (a[k] + b[k]);
}

/* Bilinear filtering at the image's edges, where the modes differ: at s = 0, halfway between the
 * centres of texel -1 and texel 0, repeat blends the last column with the first, clamp and mirror
 * read the first alone; at s = 1.125 (a texel centre one period on) repeat reads column 0, clamp
 * and mirror column 3. t = 0.5 is the centre of row 1. */
static void wrap_modes_bilinear_at_edges(void **state)
{
    temp_dir *fx = *state;
    vkrt_texture_set set = {0};
    uint32_t image = add_unique_image(fx, &set, 4, 3);
    uint32_t clamp = view_ok(&set, image, BOTH(VKRT_TEXTURE_CLAMP), NULL, NULL);
    uint32_t mirror = view_ok(&set, image, BOTH(VKRT_TEXTURE_MIRROR), NULL, NULL);
    float got[4];
    double want[4];
    midway(3, 0, 1, want);
    vkrt_texture_sample(&set, image, 0.0f, 0.5f, got);
    assert_rgba_near(got, want, 1e-6, "repeat at s = 0");
    vkrt_texture_sample(&set, image, 1.0f, 0.5f, got);
    assert_rgba_near(got, want, 1e-6, "repeat at s = 1");
    assert_sample_is_texel(&set, clamp, 0.0f, 0.5f, 0, 1);
    assert_sample_is_texel(&set, mirror, 0.0f, 0.5f, 0, 1);
    assert_sample_is_texel(&set, clamp, -7.0f, 0.5f, 0, 1);
    assert_sample_is_texel(&set, clamp, 1.0f, 0.5f, 3, 1);
    assert_sample_is_texel(&set, mirror, 1.0f, 0.5f, 3, 1);
    assert_sample_is_texel(&set, image, 1.125f, 0.5f, 0, 1);
    assert_sample_is_texel(&set, clamp, 1.125f, 0.5f, 3, 1);
    assert_sample_is_texel(&set, mirror, 1.125f, 0.5f, 3, 1);
    /* Between the centres of columns 1 and 2 every mode blends them equally. */
    midway(1, 2, 1, want);
    uint32_t views[3] = {image, clamp, mirror};
    for (int k = 0; k < 3; k++) {
        vkrt_texture_sample(&set, views[k], 0.5f, 0.5f, got);
        assert_rgba_near(got, want, 1e-6, "between columns 1 and 2");
    }
    vkrt_texture_set_free(&set);
}

/* A one-number map's channel goes to all four components; views share the image's texels, the
 * same view is made once, and a view of a view is refused. */
static void channels_and_views_share_texels(void **state)
{
    temp_dir *fx = *state;
    vkrt_texture_set set = {0};
    uint32_t image = add_unique_image(fx, &set, 4, 3);
    size_t words = set.texel_words;
    assert_int_equal(view_ok(&set, image, 0, NULL, NULL), image);
    uint32_t green = view_ok(&set, image, VKRT_TEXTURE_CHANNEL(1u), NULL, NULL);
    uint32_t blue = view_ok(&set, image, VKRT_TEXTURE_CHANNEL(2u), NULL, NULL);
    uint32_t alpha = view_ok(&set, image, VKRT_TEXTURE_CHANNEL(3u), NULL, NULL);
    assert_int_equal(view_ok(&set, image, VKRT_TEXTURE_CHANNEL(1u), NULL, NULL), green);
    assert_int_equal(set.count, 4);
    assert_int_equal(set.texel_words, words);
    assert_int_equal(set.info[green].offset, set.info[image].offset);
    assert_string_equal(set.paths[green], set.paths[image]);
    /* Adding the file again gives the image, not a view of it. */
    assert_int_equal(add_ok(&set, set.paths[image], VKRT_TEXTURE_DATA), image);
    double texel[4];
    unique_texel(2, 1, texel); /* centre of texel (2, 1): s = 2.5 / 4, t = 1.5 / 3 */
    uint32_t views[3] = {green, blue, alpha};
    for (int c = 1; c <= 3; c++) {
        float got[4];
        double want[4] = {texel[c], texel[c], texel[c], texel[c]};
        vkrt_texture_sample(&set, views[c - 1], 0.625f, 0.5f, got);
        assert_rgba_near(got, want, 1e-6, "one channel in all four");
    }
    uint32_t index = 777;
    vkrt_error err = {{0}};
    assert_false(vkrt_texture_set_view(&set, green, VKRT_TEXTURE_NEAREST, NULL, NULL, &index, &err));
    assert_false(vkrt_texture_set_view(&set, 99, VKRT_TEXTURE_NEAREST, NULL, NULL, &index, &err));
    assert_false(vkrt_texture_set_view(&set, image, VKRT_TEXTURE_SRGB, NULL, NULL, &index, &err));
    assert_int_equal(index, 777);
    assert_int_equal(set.count, 4);
    vkrt_texture_set_free(&set);
}

/* (s, t) through a uv_matrix and uv_offset. */
static void apply(const float m[4], const float o[2], double s, double t, double out[2])
{
    out[0] = m[0] * s + m[1] * t + o[0];
    out[1] = m[2] * s + m[3] * t + o[1];
}

/* vkrt_texture_uv_transform against the extension's own examples, and a transformed entry's
 * samples against the plain image sampled where the closed form puts them:
 *     s' = o_s + cos r k_s s + sin r k_t t,   t' = o_t - sin r k_s s + cos r k_t t. */
static void uv_transform_closed_form(void **state)
{
    temp_dir *fx = *state;
    float m[4], o[2];
    double p[2];
    /* "Only the lower left quadrant of the source image, rotated clockwise 90 degrees":
     * offset (0, 1), rotation pi/2, scale 0.5. The corners of the uv square land on the
     * corners of that quarter. */
    assert_false(vkrt_texture_uv_transform((float[]){0, 1}, (float[]){0.5f, 0.5f},
                                           1.57079632679f, m, o));
    static const double corners[4][4] = {
        {0, 0, 0, 1}, {1, 0, 0, 0.5}, {0, 1, 0.5, 1}, {1, 1, 0.5, 0.5}};
    for (int i = 0; i < 4; i++) {
        apply(m, o, corners[i][0], corners[i][1], p);
        assert_near(p[0], corners[i][2], 1e-6, "quarter example, s");
        assert_near(p[1], corners[i][3], 1e-6, "quarter example, t");
    }
    /* "Inverts the T axis": offset (0, 1), scale (1, -1). */
    assert_false(vkrt_texture_uv_transform((float[]){0, 1}, (float[]){1, -1}, 0, m, o));
    apply(m, o, 0.25, 0.125, p);
    assert_near(p[0], 0.25, 0, "flip, s");
    assert_near(p[1], 0.875, 0, "flip, t");
    assert_true(vkrt_texture_uv_transform((float[]){0, 0}, (float[]){1, 1}, 0, m, o));

    vkrt_texture_set set = {0};
    uint32_t image = add_unique_image(fx, &set, 5, 3);
    uint32_t seed = 99;
    for (int trial = 0; trial < 20; trial++) {
        float offset[2], scale[2], rotation;
        float r[8];
        for (int k = 0; k < 8; k++) {
            seed = seed * 1664525u + 1013904223u;
            r[k] = (float)(seed >> 8) / 16777216.0f; /* [0, 1) */
        }
        offset[0] = 4 * r[0] - 2;
        offset[1] = 4 * r[1] - 2;
        scale[0] = 3 * r[2] - 1.5f;
        scale[1] = 3 * r[3] - 1.5f;
        rotation = 8 * r[4] - 4;
        assert_false(vkrt_texture_uv_transform(offset, scale, rotation, m, o));
        uint32_t view = view_ok(&set, image, VKRT_TEXTURE_TRANSFORM, m, o);
        double u = 3 * r[5] - 1, v = 3 * r[6] - 1, s = u, t = 1 - v;
        double s2 = offset[0] + cos(rotation) * scale[0] * s + sin(rotation) * scale[1] * t;
        double t2 = offset[1] - sin(rotation) * scale[0] * s + cos(rotation) * scale[1] * t;
        float got[4], want[4];
        vkrt_texture_sample(&set, view, (float)u, (float)v, got);
        vkrt_texture_sample(&set, image, (float)s2, (float)(1 - t2), want);
        double wantd[4] = {want[0], want[1], want[2], want[3]};
        assert_rgba_near(got, wantd, 1e-4, "transformed sample against the closed form");
    }
    vkrt_texture_set_free(&set);
}

/* Khronos' TextureTransformTest in small: known offsets, rotations and scales give known texels of
 * an 8 x 8 image under a clamping, nearest sampler (the sample model's). Points are glTF uv (a, b),
 * v pointing down, which vkrt's loader stores as (a, 1 - b); the expected texels are worked out
 * by hand from the closed form above, and differ from those of a transform left out or rotated
 * the wrong way. */
static void texture_transform_test_in_small(void **state)
{
    temp_dir *fx = *state;
    vkrt_texture_set set = {0};
    uint32_t image = add_unique_image(fx, &set, 8, 8);
    uint32_t base = VKRT_TEXTURE_NEAREST | BOTH(VKRT_TEXTURE_CLAMP);
    static const struct {
        float offset[2], scale[2], rotation;
        float a, b; /* glTF uv */
        int x, y;   /* the texel it must read */
    } cases[] = {
        /* Offsets: uv (0.25, 0.25), the middle of a quad spanning uv 0 to 0.5, reads the
         * quarter the offset names: none (3/8 of 8 = 2), s + 0.5, t + 0.5, both. */
        {{0, 0}, {1, 1}, 0, 0.25f, 0.25f, 2, 2},
        {{0.5f, 0}, {1, 1}, 0, 0.25f, 0.25f, 6, 2},
        {{0, 0.5f}, {1, 1}, 0, 0.25f, 0.25f, 2, 6},
        {{0.5f, 0.5f}, {1, 1}, 0, 0.25f, 0.25f, 6, 6},
        /* Rotation 22.5 degrees of (0.8, 0.3): s' = 0.8 cos + 0.3 sin = 0.854 -> 6, t' = -0.8 sin
         * + 0.3 cos = -0.029, clamped -> 0. The wrong way round gives (4, 4); none (6, 2). */
        {{0, 0}, {1, 1}, 0.392699f, 0.8f, 0.3f, 6, 0},
        /* Scale 1.5 of (0.5, 0.5): (0.75, 0.75) -> 6; unscaled it would be 4. */
        {{0, 0}, {1.5f, 1.5f}, 0, 0.5f, 0.5f, 6, 6},
        /* All: offset (-0.2, -0.1), rotation 0.3, scale (1.5, 1.2) of (0.4, 0.6):
         * s' = -0.2 + 0.9553 * 0.6 + 0.2955 * 0.72 = 0.586 -> 4,
         * t' = -0.1 - 0.2955 * 0.6 + 0.9553 * 0.72 = 0.411 -> 3. */
        {{-0.2f, -0.1f}, {1.5f, 1.2f}, 0.3f, 0.4f, 0.6f, 4, 3},
        /* The extension's example, the lower left quarter turned: (0.1, 0.1) -> (0.05, 0.95),
         * (0.9, 0.1) -> (0.05, 0.55), (0.1, 0.9) -> (0.45, 0.95). */
        {{0, 1}, {0.5f, 0.5f}, 1.57079632679f, 0.1f, 0.1f, 0, 7},
        {{0, 1}, {0.5f, 0.5f}, 1.57079632679f, 0.9f, 0.1f, 0, 4},
        {{0, 1}, {0.5f, 0.5f}, 1.57079632679f, 0.1f, 0.9f, 3, 7},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        float m[4], o[2];
        bool identity = vkrt_texture_uv_transform(cases[i].offset, cases[i].scale,
                                                  cases[i].rotation, m, o);
        uint32_t view =
            view_ok(&set, image, base | (identity ? 0u : VKRT_TEXTURE_TRANSFORM), m, o);
        assert_sample_is_texel(&set, view, cases[i].a, 1.0f - cases[i].b, cases[i].x, cases[i].y);
    }
    vkrt_texture_set_free(&set);
}

/* ------------------------------------------------------------------------- mipmap levels */

/* A 2 x 2 colour checker of sRGB 0 and 255 averages, in light, to linear 0.5: its 1 x 1 level is
 * sRGB 188 (0.5 encoded is 187.5), not the 128 of averaging the codes; alpha (linear) stays 255. */
static void levels_average_srgb_in_light(void **state)
{
    temp_dir *fx = *state;
    const unsigned char px[2][2][3] = {{{0, 0, 0}, {255, 255, 255}}, {{255, 255, 255}, {0, 0, 0}}};
    vkrt_texture_set set = {0};
    uint32_t t = add_ok(&set, write_png(fx, "checker.png", 2, 2, 3, &px[0][0][0]),
                        VKRT_TEXTURE_COLOUR);
    assert_int_equal(VKRT_TEXTURE_LEVELS_OF(set.info[t].flags), 1);
    assert_int_equal(set.texel_words, 5);
    uint32_t level = set.texels[set.info[t].offset + 4];
    assert_int_equal(level, 188u | 188u << 8 | 188u << 16 | 255u << 24);
    /* The same image as data is averaged as it is stored: 127.5 rounds to 128. */
    uint32_t d = add_ok(&set, fx->path, VKRT_TEXTURE_DATA);
    assert_int_equal(set.texels[set.info[d].offset + 4] & 0xFFu, 128u);
    vkrt_texture_set_free(&set);
}

/* The mean of a w x h image's texels (red of data, 0..255) over the area [x0, x1) x [y0, y1) of
 * texel units, by summing a 64 x 64 grid of points per texel: the box filter's reference,
 * knowing nothing of its weights. */
static double area_mean(const uint32_t *texels, int w, double x0, double x1, double y0, double y1)
{
    double sum = 0;
    int n = 0;
    for (double y = y0 + 1.0 / 128; y < y1; y += 1.0 / 64)
        for (double x = x0 + 1.0 / 128; x < x1; x += 1.0 / 64, n++)
            sum += (double)(texels[(int)y * w + (int)x] & 0xFFu);
    return sum / n;
}

/* Odd sizes: a 5 x 3 image's levels are 2 x 1 and 1 x 1, each texel the mean of the area it
 * covers (2.5 x 3 texels, then 5 x 3), so the levels keep the image's mean. */
static void levels_of_odd_sizes_are_exact_boxes(void **state)
{
    (void)state;
    enum { IW = 5, IH = 3 };
    assert_int_equal(vkrt_texture_level_count(IW, IH), 2);
    assert_int_equal(vkrt_texture_level_count(1, 1), 0);
    assert_int_equal(vkrt_texture_level_count(16384, 3), 14);
    uint32_t lw, lh;
    assert_int_equal(vkrt_texture_level_at(IW, IH, 1, 1, &lw, &lh), IW * IH);
    assert_int_equal(lw, 2);
    assert_int_equal(lh, 1);
    assert_int_equal(vkrt_texture_level_at(IW, IH, 1, 2, &lw, &lh), IW * IH + 2);
    assert_int_equal(lw * lh, 1);
    assert_int_equal(vkrt_texture_words_with_levels(IW, IH, 1), IW * IH + 2 + 1);
    assert_int_equal(vkrt_texture_words_with_levels(IW, IH, 2), 2 * (IW * IH + 2 + 1));
    uint32_t texels[IW * IH + 3];
    for (int i = 0; i < IW * IH; i++) {
        uint32_t v = (uint32_t)(i * 37 % 251);
        texels[i] = v | v << 8 | v << 16 | 255u << 24;
    }
    assert_true(vkrt_texture_build_levels(texels, IW, IH, 0));
    for (int x = 0; x < 2; x++) {
        double want = area_mean(texels, IW, 2.5 * x, 2.5 * (x + 1), 0, IH);
        assert_true(fabs((double)(texels[IW * IH + x] & 0xFFu) - want) <= 0.5 + 1e-9);
    }
    double mean = area_mean(texels, IW, 0, IW, 0, IH);
    assert_true(fabs((double)(texels[IW * IH + 2] & 0xFFu) - mean) <= 1.0);
    /* Half floats: a 3 x 1 row of 1, 2 and 6 gives a 1 x 1 level of their mean, 3. */
    uint32_t hdr[2 * (3 + 1)];
    const float row[3] = {1, 2, 6};
    for (int i = 0; i < 3; i++) {
        hdr[2 * i] = vkrt_half_from_float(row[i]) | (uint32_t)vkrt_half_from_float(row[i]) << 16;
        hdr[2 * i + 1] = vkrt_half_from_float(row[i]) | 0x3C00u << 16;
    }
    assert_true(vkrt_texture_build_levels(hdr, 3, 1, VKRT_TEXTURE_HALF));
    assert_true(fabsf(vkrt_half_to_float(hdr[6] & 0xFFFFu) - 3.0f) < 1e-3f);
    assert_true(fabsf(vkrt_half_to_float(hdr[7] >> 16) - 1.0f) < 1e-6f);
}

/* `textures bilinear` leaves the levels unread, `nearest` reads the nearest texel of the image. */
static void filter_modes_set_the_flags(void **state)
{
    (void)state;
    vkrt_texture_info info[2] = {
        {.flags = VKRT_TEXTURE_SRGB | VKRT_TEXTURE_LEVELS(7u)},
        {.flags = VKRT_TEXTURE_LEVELS(3u) | VKRT_TEXTURE_CHANNEL(2u)},
    };
    vkrt_texture_set set = {.info = info, .count = 2};
    vkrt_texture_set_filter(&set, VKRT_TEXTURE_FILTER_CONE);
    assert_int_equal(info[0].flags, VKRT_TEXTURE_SRGB | VKRT_TEXTURE_LEVELS(7u));
    vkrt_texture_set_filter(&set, VKRT_TEXTURE_FILTER_BILINEAR);
    assert_int_equal(info[0].flags, VKRT_TEXTURE_SRGB);
    assert_int_equal(info[1].flags, VKRT_TEXTURE_CHANNEL(2u));
    vkrt_texture_set_filter(&set, VKRT_TEXTURE_FILTER_NEAREST);
    assert_int_equal(info[1].flags, VKRT_TEXTURE_CHANNEL(2u) | VKRT_TEXTURE_NEAREST);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        temp_dir_test(png_texel_words_and_flags),
        temp_dir_test(levels_average_srgb_in_light),
        cmocka_unit_test(levels_of_odd_sizes_are_exact_boxes),
        cmocka_unit_test(filter_modes_set_the_flags),
        temp_dir_test(srgb_decoding_matches_closed_form),
        temp_dir_test(tga_is_lossless_and_jpeg_close),
        temp_dir_test(hdr_becomes_half_floats),
        temp_dir_test(bilinear_sample_and_wrap),
        temp_dir_test(alpha_usage_picks_the_channel),
        temp_dir_test(mean_and_which_images_are_normal_maps),
        temp_dir_test(same_file_same_usage_is_loaded_once),
        temp_dir_test(file_name_case_and_backslashes),
        temp_dir_test(errors_name_referrer_and_path),
        temp_dir_test(size_limit_is_reported_in_mib),
        temp_dir_test(decoding_ahead_changes_nothing),
        temp_dir_test(wrap_modes_nearest),
        temp_dir_test(wrap_modes_bilinear_at_edges),
        temp_dir_test(channels_and_views_share_texels),
        temp_dir_test(uv_transform_closed_form),
        temp_dir_test(texture_transform_test_in_small),
        cmocka_unit_test(dabrovic_sponza_textures),
        cmocka_unit_test(sibenik_cathedral_textures),
        cmocka_unit_test(lost_empire_textures),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
