/*
 * test_denoise.c: src/output/denoise.c and the finish stage's denoise pass, on the CPU.
 *
 * Without Open Image Denoise (CI installs no .venv) only the message test runs; the others skip,
 * saying why. With it: images of known content plus Gaussian noise of known sigma, denoised,
 * must come back much closer to the clean image than the noisy one was (mean squared error
 * against the truth, which the test made); an albedo and a normal must help where the albedo has
 * edges the noise hides; an EXR written with --denoise's finish holds the denoised beauty and,
 * as layer "noisy", exactly the radiance given.
 */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h> /* cmocka needs these before its header */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <openexr.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "output/denoise.h"
#include "output/image_write.h"
#include "temp_dir.h"

enum { W = 96, H = 80, CELL = 8 };
static const double sigma = 0.1; /* the noise's standard deviation, per channel */

/* A test image: the truth, a noisy copy, and the aux buffers the denoiser may get. */
typedef struct picture {
    float clean[W * H * 3], noisy[W * H * 3], albedo[W * H * 3], normal[W * H * 3];
    float out[W * H * 3];
} picture;

/* One standard normal deviate from a xorshift64 state (Box-Muller): the same noise every run. */
static double gaussian(uint64_t *state)
{
    double u[2];
    for (int i = 0; i < 2; ++i) {
        *state ^= *state << 13;
        *state ^= *state >> 7;
        *state ^= *state << 17;
        u[i] = ((double)(*state >> 11) + 0.5) / 9007199254740992.0; /* (0, 1) */
    }
    return sqrt(-2.0 * log(u[0])) * cos(6.283185307179586 * u[1]);
}

/* Radiance = albedo x smooth shading. checker: the albedo alternates 0.2 / 0.8 in CELL-pixel
 * squares (edges the denoiser must keep), else it is a constant 0.5 (a smooth gradient alone).
 * The normal faces the camera everywhere. */
static picture *picture_make(bool checker)
{
    picture *p = malloc(sizeof *p);
    assert_non_null(p);
    uint64_t state = 0x9e3779b97f4a7c15ull;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            float a = checker ? ((x / CELL + y / CELL) % 2 ? 0.8f : 0.2f) : 0.5f;
            float shade = 0.4f + 0.8f * (float)x / W + 0.3f * (float)y / H;
            for (int c = 0; c < 3; ++c) {
                size_t i = ((size_t)y * W + x) * 3 + c;
                p->albedo[i] = a;
                p->normal[i] = c == 2 ? 1.0f : 0.0f;
                p->clean[i] = a * shade * (0.8f + 0.2f * c);
                p->noisy[i] = p->clean[i] + (float)(sigma * gaussian(&state));
            }
        }
    return p;
}

static double mse(const float *a, const float *b)
{
    double sum = 0;
    for (size_t i = 0; i < (size_t)W * H * 3; ++i)
        sum += ((double)a[i] - b[i]) * ((double)a[i] - b[i]);
    return sum / ((double)W * H * 3);
}

/* The denoiser, or a skip that says why there is none. */
static vkrt_denoiser *denoiser_or_skip(void)
{
    vkrt_error err = {{0}};
    vkrt_denoiser *d = NULL;
    if (!vkrt_denoise_library_check(&err)) {
        print_message("skipped: %s\n", err.msg);
        skip();
    }
    assert_true(vkrt_denoiser_create(&d, &(vkrt_denoiser_desc){0}, &err));
    print_message("%s\n", vkrt_denoiser_describe(d));
    return d;
}

/* A library named by VKRT_OIDN_LIBRARY that is not there: the message names the option and the
 * two ways to get the library, and no denoiser is made. */
static void missing_library_says_how_to_get_it(void **state)
{
    (void)state;
    const char *before = getenv("VKRT_OIDN_LIBRARY");
    char *saved = before ? strdup(before) : NULL;
    setenv("VKRT_OIDN_LIBRARY", "/nonexistent/libOpenImageDenoise.so.2", 1);
    vkrt_error err = {{0}};
    bool found = vkrt_denoise_library_check(&err);
    vkrt_denoiser *d = (vkrt_denoiser *)&err; /* any non-NULL value: create must clear it */
    vkrt_error create_err = {{0}};
    bool made = vkrt_denoiser_create(&d, &(vkrt_denoiser_desc){0}, &create_err);
    if (saved)
        setenv("VKRT_OIDN_LIBRARY", saved, 1);
    else
        unsetenv("VKRT_OIDN_LIBRARY");
    free(saved);
    assert_false(found);
    assert_false(made);
    assert_null(d);
    print_message("%s\n", err.msg);
    assert_non_null(strstr(err.msg, "--denoise"));
    assert_non_null(strstr(err.msg, "VKRT_OIDN_LIBRARY=/nonexistent/libOpenImageDenoise.so.2"));
    assert_non_null(strstr(err.msg, "tools/setup-python"));
    assert_string_equal(err.msg, create_err.msg);
}

/* A smooth gradient under noise of sigma 0.1: the noisy image's error is sigma^2; denoised
 * without aux it must drop at least 10-fold. */
static void gradient_noise_drops(void **state)
{
    (void)state;
    vkrt_denoiser *d = denoiser_or_skip();
    picture *p = picture_make(false);
    vkrt_error err = {{0}};
    bool ok = vkrt_denoiser_run(d, &(vkrt_denoise_input){.width = W, .height = H, .rgb = p->noisy},
                                p->out, &err);
    double before = mse(p->noisy, p->clean), after = mse(p->out, p->clean);
    print_message("gradient: mse %.3g noisy, %.3g denoised (%.0fx less)\n", before, after,
                  before / after);
    vkrt_denoiser_destroy(d);
    assert_true(ok);
    assert_true(fabs(before - sigma * sigma) < 0.05 * sigma * sigma);
    assert_true(after < before / 10);
    free(p);
}

/* A checker albedo under noise: without aux the filter keeps only part of the edges the noise
 * hides (about half the noise's error is left); with the albedo and normal it must be at least
 * twice as close to the truth as without them and 10-fold closer than the noise. The same
 * denoiser serves frames of different inputs (its filter made again for each shape). */
static void albedo_and_normal_keep_edges(void **state)
{
    (void)state;
    vkrt_denoiser *d = denoiser_or_skip();
    picture *p = picture_make(true);
    vkrt_error err = {{0}};
    vkrt_denoise_input in = {.width = W, .height = H, .rgb = p->noisy};
    assert_true(vkrt_denoiser_run(d, &in, p->out, &err));
    double before = mse(p->noisy, p->clean), plain = mse(p->out, p->clean);
    in.albedo = p->albedo;
    in.normal = p->normal;
    in.clean_aux = true;
    bool ok = vkrt_denoiser_run(d, &in, p->out, &err);
    double with_aux = mse(p->out, p->clean);
    print_message("checker: mse %.3g noisy, %.3g denoised, %.3g with albedo and normal\n", before,
                  plain, with_aux);
    vkrt_denoiser_destroy(d);
    assert_true(ok);
    assert_true(plain < before); /* edges the noise hides are lost without the albedo */
    assert_true(with_aux < before / 10);
    assert_true(with_aux < 0.5 * plain);
    free(p);
}

/* Every float channel of an EXR's first part into planes[c] (W x H each), named in names[c]. */
static int read_exr_planes(const char *path, char names[][16], float *planes[], int most)
{
    exr_context_t ctxt = NULL;
    assert_int_equal(exr_start_read(&ctxt, path, NULL), EXR_ERR_SUCCESS);
    const exr_attr_chlist_t *channels = NULL;
    assert_int_equal(exr_get_channels(ctxt, 0, &channels), EXR_ERR_SUCCESS);
    assert_true(channels->num_channels <= most);
    for (int c = 0; c < channels->num_channels; ++c)
        snprintf(names[c], 16, "%s", channels->entries[c].name.str);
    int32_t lines = 0;
    assert_int_equal(exr_get_scanlines_per_chunk(ctxt, 0, &lines), EXR_ERR_SUCCESS);
    for (int y = 0; y < H; y += lines) {
        exr_chunk_info_t chunk;
        assert_int_equal(exr_read_scanline_chunk_info(ctxt, 0, y, &chunk), EXR_ERR_SUCCESS);
        exr_decode_pipeline_t decoder = EXR_DECODE_PIPELINE_INITIALIZER;
        assert_int_equal(exr_decoding_initialize(ctxt, 0, &chunk, &decoder), EXR_ERR_SUCCESS);
        for (int c = 0; c < decoder.channel_count; ++c) {
            exr_coding_channel_info_t *ch = &decoder.channels[c];
            ch->decode_to_ptr = (uint8_t *)(planes[c] + (size_t)chunk.start_y * W);
            ch->user_data_type = EXR_PIXEL_FLOAT;
            ch->user_bytes_per_element = sizeof(float);
            ch->user_pixel_stride = sizeof(float);
            ch->user_line_stride = W * sizeof(float);
        }
        assert_int_equal(exr_decoding_choose_default_routines(ctxt, 0, &decoder), EXR_ERR_SUCCESS);
        assert_int_equal(exr_decoding_run(ctxt, 0, &decoder), EXR_ERR_SUCCESS);
        assert_int_equal(exr_decoding_destroy(ctxt, &decoder), EXR_ERR_SUCCESS);
    }
    int count = channels->num_channels;
    assert_int_equal(exr_finish(&ctxt), EXR_ERR_SUCCESS);
    return count;
}

/* --denoise's EXR: B, G, R the denoiser's output (as the denoiser gives it for the same input),
 * noisy.B, noisy.G, noisy.R the radiance given, bit for bit (so the finish stage did not
 * denoise its input in place). */
static void exr_keeps_the_noisy_layer(void **state)
{
    temp_dir *fx = *state;
    vkrt_denoiser *d = denoiser_or_skip();
    picture *p = picture_make(true);
    vkrt_error err = {{0}};
    vkrt_finish_desc finish = {.denoiser = d};
    const char *path = temp_dir_path(fx, "denoised.exr");
    bool written = vkrt_image_write_frame(path, W, H, p->noisy, &finish, &err);
    bool ran = vkrt_denoiser_run(d, &(vkrt_denoise_input){.width = W, .height = H, .rgb = p->noisy},
                                 p->out, &err);
    vkrt_denoiser_destroy(d);
    assert_true(written);
    assert_true(ran);

    enum { MOST = 8 };
    char names[MOST][16];
    float *planes[MOST];
    for (int c = 0; c < MOST; ++c)
        planes[c] = malloc((size_t)W * H * sizeof(float));
    int count = read_exr_planes(path, names, planes, MOST);
    assert_int_equal(count, 6);
    static const char *const expected[] = {"B", "G", "R", "noisy.B", "noisy.G", "noisy.R"};
    size_t differ_from_noisy = 0;
    for (int c = 0; c < count; ++c) {
        assert_string_equal(names[c], expected[c]);
        bool noisy = c >= 3;
        int rgb = 2 - c % 3; /* B, G, R: offsets 2, 1, 0 */
        const float *want = noisy ? p->noisy : p->out;
        for (size_t i = 0; i < (size_t)W * H; ++i) {
            assert_memory_equal(&planes[c][i], &want[i * 3 + rgb], sizeof(float));
            differ_from_noisy += !noisy && planes[c][i] != p->noisy[i * 3 + rgb];
        }
    }
    assert_true(differ_from_noisy > (size_t)W * H * 3 / 2); /* the beauty is not the input */
    for (int c = 0; c < MOST; ++c)
        free(planes[c]);
    free(p);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(missing_library_says_how_to_get_it),
        cmocka_unit_test(gradient_noise_drops),
        cmocka_unit_test(albedo_and_normal_keep_edges),
        temp_dir_test(exr_keeps_the_noisy_layer),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
