/*
 * test_image_write.c: unit tests for src/output/image_write.c.
 *
 * PNG output is read back with stb_image and checked against the sRGB curve computed here,
 * independently of the writer; EXR output is read back with OpenEXRCore's own read API and
 * checked bit for bit. The failure tests check the promise that matters most in a long render:
 * a failed write leaves neither a partial image nor a temporary file, and never damages the
 * file that was already there.
 */
#define _POSIX_C_SOURCE 200809L

#include <setjmp.h> /* cmocka needs these before its header */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <openexr.h>
#include <stb_image.h>

#include "output/image_write.h"
#include "output/temporary.h"
#include "temp_dir.h"

/* ---------------------------------------------------------------------------------------------
 * Fixture: a fresh temporary folder per test
 * ------------------------------------------------------------------------------------------- */

/* The folder comes from temp_dir.h; the buffers are this file's own. */
typedef struct fixture {
    temp_dir *tmp;
    void *buffers[2]; /* freed by the teardown, whether the test passed or not */
} fixture;

static int make_fixture(void **state)
{
    fixture *fx = calloc(1, sizeof *fx);
    void *tmp = NULL;
    if (!fx || temp_dir_make(&tmp) != 0) {
        free(fx);
        return -1;
    }
    fx->tmp = tmp;
    *state = fx;
    return 0;
}

static int remove_fixture(void **state)
{
    fixture *fx = *state;
    void *tmp = fx->tmp;
    temp_dir_remove(&tmp);
    free(fx->buffers[0]);
    free(fx->buffers[1]);
    free(fx);
    return 0;
}

/* The names in dir, sorted and joined with spaces, so a test can compare the whole listing
 * (which catches stray temp files whatever they are called). */
static void list_dir(const char *dir, char *out, size_t out_size)
{
    struct dirent **entries = NULL;
    int n = scandir(dir, &entries, NULL, alphasort);
    out[0] = '\0';
    for (int i = 0; i < n; i++) {
        const char *name = entries[i]->d_name;
        if (strcmp(name, ".") != 0 && strcmp(name, "..") != 0) {
            if (out[0] != '\0')
                strncat(out, " ", out_size - strlen(out) - 1);
            strncat(out, name, out_size - strlen(out) - 1);
        }
        free(entries[i]);
    }
    free(entries);
}

static void assert_file_contains(const char *path, const char *expected)
{
    char buf[256] = {0};
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    assert_int_equal(n, strlen(expected));
    assert_string_equal(buf, expected);
}

/* ---------------------------------------------------------------------------------------------
 * PNG
 * ------------------------------------------------------------------------------------------- */

/* The reference: exact sRGB OETF in double, written from the standard, not from the writer. */
static int expected_srgb8(double linear)
{
    if (isnan(linear) || linear <= 0.0)
        return 0;
    if (linear >= 1.0)
        return 255;
    double encoded = linear < 0.0031308 ? 12.92 * linear : 1.055 * pow(linear, 1.0 / 2.4) - 0.055;
    return (int)lround(encoded * 255.0);
}

enum { GRADIENT_W = 7, GRADIENT_H = 5 };

/* Values the PNG path must handle: the curve's ends and its kink, overrange, NaN, +-inf,
 * negatives and a ramp in between. Each channel starts at a different place in the list. */
static void fill_gradient(float *rgb)
{
    static const float specials[] = {0.0f,  0.0031308f, 0.5f,   1.0f,    2.0f,     NAN,
                                     -1.0f, INFINITY,   -INFINITY, 0.001f, 0.2140f, 0.75f};
    const size_t special_count = sizeof specials / sizeof specials[0];
    for (size_t i = 0; i < (size_t)GRADIENT_W * GRADIENT_H * 3; i++) {
        size_t pixel = i / 3, channel = i % 3;
        if (pixel < special_count)
            rgb[i] = specials[(pixel + channel * 4) % special_count];
        else
            rgb[i] = (float)(pixel * 3 + channel) / (GRADIENT_W * GRADIENT_H * 3.0f);
    }
}

static unsigned char *load_png(const char *path, int expect_w, int expect_h)
{
    int w = 0, h = 0, channels = 0;
    unsigned char *pixels = stbi_load(path, &w, &h, &channels, 3);
    assert_non_null(pixels);
    assert_int_equal(w, expect_w);
    assert_int_equal(h, expect_h);
    assert_int_equal(channels, 3); /* what the file holds: RGB, no alpha */
    return pixels;
}

static void test_png_matches_srgb_curve(void **state)
{
    fixture *fx = *state;
    const char *path = temp_dir_path(fx->tmp, "gradient.png");
    float rgb[GRADIENT_W * GRADIENT_H * 3];
    fill_gradient(rgb);

    vkrt_error err = {{0}};
    assert_true(vkrt_image_write(path, GRADIENT_W, GRADIENT_H, rgb, 0.0f, &err));

    unsigned char *pixels = load_png(path, GRADIENT_W, GRADIENT_H);
    for (size_t i = 0; i < (size_t)GRADIENT_W * GRADIENT_H * 3; i++) {
        int expected = expected_srgb8(rgb[i]);
        /* One code value of slack: the writer may compute in float where this reference uses
         * double, which can flip a value that lands within rounding error of x.5. The exact
         * anchors (0, 1, overrange, NaN, inf) are checked without slack below. */
        if (abs((int)pixels[i] - expected) > 1)
            fail_msg("byte %zu: linear %g gave %d, expected %d", i, (double)rgb[i], pixels[i],
                     expected);
        if (isnan(rgb[i]) || rgb[i] <= 0.0f || rgb[i] >= 1.0f)
            assert_int_equal(pixels[i], expected);
    }
    stbi_image_free(pixels);

    char listing[256];
    list_dir(fx->tmp->dir, listing, sizeof listing);
    assert_string_equal(listing, "gradient.png");
}

static void test_png_exposure_plus_one_doubles(void **state)
{
    fixture *fx = *state;
    char half_path[256]; /* a copy: temp_dir_path keeps only the path it made last */
    snprintf(half_path, sizeof half_path, "%s", temp_dir_path(fx->tmp, "half.png"));
    const char *quarter_path = temp_dir_path(fx->tmp, "quarter.png");
    float half[4 * 3], quarter[4 * 3];
    for (size_t i = 0; i < 12; i++) {
        half[i] = 0.05f * (float)(i + 1);
        quarter[i] = half[i] * 0.5f; /* exact in binary floating point */
    }

    vkrt_error err = {{0}};
    assert_true(vkrt_image_write(half_path, 2, 2, half, 0.0f, &err));
    assert_true(vkrt_image_write(quarter_path, 2, 2, quarter, 1.0f, &err));

    unsigned char *a = load_png(half_path, 2, 2);
    unsigned char *b = load_png(quarter_path, 2, 2);
    for (size_t i = 0; i < 12; i++) {
        assert_int_equal(a[i], b[i]);
        assert_true(abs((int)a[i] - expected_srgb8(half[i])) <= 1);
    }
    stbi_image_free(a);
    stbi_image_free(b);
}

/* ---------------------------------------------------------------------------------------------
 * EXR
 * ------------------------------------------------------------------------------------------- */

/* Distinct, recognisable values per channel and position: R in the thousands, G negative,
 * B fractional, so a swapped channel or a flipped row cannot go unnoticed. A few specials
 * check that values pass through unchanged, bit for bit. */
static void fill_exr_pattern(float *rgb, uint32_t w, uint32_t h)
{
    for (uint32_t y = 0; y < h; y++) {
        for (uint32_t x = 0; x < w; x++) {
            float *p = rgb + ((size_t)y * w + x) * 3;
            p[0] = 1000.0f + (float)(y * 100 + x);
            p[1] = -(float)(y * 100 + x) - 0.25f;
            p[2] = (float)y + (float)x / 1024.0f + 0.5f;
        }
    }
    rgb[0] = 0.0f;
    rgb[4] = NAN;
    rgb[5] = INFINITY;
    rgb[6] = 1e-40f; /* subnormal */
    rgb[7] = 65504.5f;
}

/* The channel names of path's first part, in the file's order, joined with spaces. */
static void exr_channel_names(const char *path, char *out, size_t size)
{
    exr_context_t ctxt = NULL;
    assert_int_equal(exr_start_read(&ctxt, path, NULL), EXR_ERR_SUCCESS);
    const exr_attr_chlist_t *channels = NULL;
    assert_int_equal(exr_get_channels(ctxt, 0, &channels), EXR_ERR_SUCCESS);
    out[0] = '\0';
    for (int c = 0; c < channels->num_channels; c++) {
        assert_int_equal(channels->entries[c].pixel_type, EXR_PIXEL_FLOAT);
        snprintf(out + strlen(out), size - strlen(out), "%s%s", c ? " " : "",
                 channels->entries[c].name.str);
    }
    assert_int_equal(exr_finish(&ctxt), EXR_ERR_SUCCESS);
}

/* Reads channels names[0 .. count - 1] of a float EXR of w x h pixels into out, count floats a
 * pixel in that order, with OpenEXRCore's decode API; the file's other channels are skipped. */
static void read_exr_channels(const char *path, uint32_t w, uint32_t h,
                              const char *const *names, int count, float *out)
{
    exr_context_t ctxt = NULL;
    assert_int_equal(exr_start_read(&ctxt, path, NULL), EXR_ERR_SUCCESS);

    exr_attr_box2i_t dw;
    assert_int_equal(exr_get_data_window(ctxt, 0, &dw), EXR_ERR_SUCCESS);
    assert_int_equal(dw.min.x, 0);
    assert_int_equal(dw.min.y, 0);
    assert_int_equal(dw.max.x, (int)w - 1);
    assert_int_equal(dw.max.y, (int)h - 1);

    exr_compression_t compression;
    assert_int_equal(exr_get_compression(ctxt, 0, &compression), EXR_ERR_SUCCESS);
    assert_int_equal(compression, EXR_COMPRESSION_ZIP);

    int32_t lines_per_chunk = 0;
    assert_int_equal(exr_get_scanlines_per_chunk(ctxt, 0, &lines_per_chunk), EXR_ERR_SUCCESS);
    for (int y = dw.min.y; y <= dw.max.y; y += lines_per_chunk) {
        exr_chunk_info_t chunk;
        assert_int_equal(exr_read_scanline_chunk_info(ctxt, 0, y, &chunk), EXR_ERR_SUCCESS);
        exr_decode_pipeline_t decoder = EXR_DECODE_PIPELINE_INITIALIZER;
        assert_int_equal(exr_decoding_initialize(ctxt, 0, &chunk, &decoder), EXR_ERR_SUCCESS);
        for (int c = 0; c < decoder.channel_count; c++) {
            exr_coding_channel_info_t *ch = &decoder.channels[c];
            int offset = -1;
            for (int k = 0; k < count; k++)
                if (strcmp(ch->channel_name, names[k]) == 0)
                    offset = k;
            ch->decode_to_ptr =
                offset < 0 ? NULL
                           : (uint8_t *)(out + (size_t)(chunk.start_y - dw.min.y) * w * count +
                                         offset);
            ch->user_data_type = EXR_PIXEL_FLOAT;
            ch->user_bytes_per_element = 4;
            ch->user_pixel_stride = count * 4;
            ch->user_line_stride = (int32_t)(w * count * 4);
        }
        assert_int_equal(exr_decoding_choose_default_routines(ctxt, 0, &decoder),
                         EXR_ERR_SUCCESS);
        assert_int_equal(exr_decoding_run(ctxt, 0, &decoder), EXR_ERR_SUCCESS);
        assert_int_equal(exr_decoding_destroy(ctxt, &decoder), EXR_ERR_SUCCESS);
    }
    assert_int_equal(exr_finish(&ctxt), EXR_ERR_SUCCESS);
}

/* Reads an RGB float EXR, B, G and R alone, back into an interleaved buffer. */
static void read_exr(const char *path, uint32_t w, uint32_t h, float *rgb)
{
    char names[256];
    exr_channel_names(path, names, sizeof names);
    assert_string_equal(names, "B G R");
    read_exr_channels(path, w, h, (const char *const[]){"R", "G", "B"}, 3, rgb);
}

static void check_exr_roundtrip(fixture *fx, uint32_t w, uint32_t h)
{
    const char *path = temp_dir_path(fx->tmp, "frame.exr");
    size_t count = (size_t)w * h * 3;
    /* owned by the fixture, so a failed assertion (a longjmp) does not leak them */
    float *written = fx->buffers[0] = malloc(count * sizeof(float));
    float *read_back = fx->buffers[1] = malloc(count * sizeof(float));
    assert_non_null(written);
    assert_non_null(read_back);
    fill_exr_pattern(written, w, h);
    for (size_t i = 0; i < count; i++)
        read_back[i] = -12345.0f; /* anything the decoder fails to fill will stand out */

    vkrt_error err = {{0}};
    if (!vkrt_image_write(path, w, h, written, 3.0f, &err))
        fail_msg("write failed: %s", err.msg);
    read_exr(path, w, h, read_back);

    /* bit comparison: NaN != NaN, and "unchanged" means the same bits */
    for (size_t i = 0; i < count; i++) {
        if (memcmp(&written[i], &read_back[i], sizeof(float)) != 0)
            fail_msg("%ux%u: value %zu (row %zu, channel %zu): wrote %g, read %g", w, h, i,
                     i / 3 / w, i % 3, (double)written[i], (double)read_back[i]);
    }
    /* spelled out at pixel (1, 1) and the bottom-left one: top row first, R is R, B is B */
    const float *p11 = read_back + ((size_t)w + 1) * 3;
    assert_true(p11[0] == 1101.0f);
    assert_true(p11[2] == 1.5f + 1.0f / 1024.0f);
    assert_true(read_back[((size_t)(h - 1) * w) * 3 + 0] == 1000.0f + (float)((h - 1) * 100));

    char listing[256];
    list_dir(fx->tmp->dir, listing, sizeof listing);
    assert_string_equal(listing, "frame.exr");
}

static void test_exr_roundtrip_small(void **state)
{
    check_exr_roundtrip(*state, GRADIENT_W, GRADIENT_H);
}

/* ZIP packs 16 lines per chunk: 37 rows make two full chunks and a partial one. */
static void test_exr_roundtrip_several_chunks(void **state)
{
    check_exr_roundtrip(*state, 3, 37);
}

/* ---------------------------------------------------------------------------------------------
 * AOVs: layers of an EXR, files beside a PNG
 * ------------------------------------------------------------------------------------------- */

enum { AOV_W = 3, AOV_H = 37 }; /* several ZIP chunks */

/* A frame whose beauty and AOVs all differ: value k of pixel i of buffer b is b * 1000 + i +
 * k / 4, but for a depth of +inf (a pixel that saw nothing) and the normal's, in [-1, 1]. */
typedef struct aov_buffers {
    float rgb[AOV_W * AOV_H * 3], albedo[AOV_W * AOV_H * 3], normal[AOV_W * AOV_H * 3],
        depth[AOV_W * AOV_H], position[AOV_W * AOV_H * 3];
} aov_buffers;

static vkrt_frame_image fill_aov_frame(aov_buffers *b)
{
    float *with_three[] = {b->rgb, b->albedo, b->position};
    for (int k = 0; k < 3; ++k)
        for (int i = 0; i < AOV_W * AOV_H * 3; ++i)
            with_three[k][i] = (float)(k * 1000 + i / 3) + (float)(i % 3) / 4.0f;
    for (int i = 0; i < AOV_W * AOV_H * 3; ++i)
        b->normal[i] = (float)((i * 37) % 201 - 100) / 100.0f;
    for (int i = 0; i < AOV_W * AOV_H; ++i)
        b->depth[i] = i == 4 ? INFINITY : 0.5f + (float)i;
    return (vkrt_frame_image){.width = AOV_W, .height = AOV_H, .rgb = b->rgb,
                              .albedo = b->albedo, .normal = b->normal, .depth = b->depth,
                              .position = b->position};
}

/* Reads layer `names` of path and compares it bit for bit with want (count floats a pixel). */
static void check_layer(const char *path, const char *const *names, int count, const float *want)
{
    float got[AOV_W * AOV_H * 3];
    read_exr_channels(path, AOV_W, AOV_H, names, count, got);
    for (int i = 0; i < AOV_W * AOV_H * count; i++)
        if (memcmp(&got[i], &want[i], sizeof *got) != 0)
            fail_msg("%s: %s value %d: wrote %g, read %g", path, names[i % count], i,
                     (double)want[i], (double)got[i]);
}

/* The EXR holds the beauty as R, G, B and each AOV as a layer named as Nuke and Blender read
 * them, every value as written; the exposure (PNG only) changes nothing. */
static void test_exr_aov_layers(void **state)
{
    fixture *fx = *state;
    aov_buffers *b = fx->buffers[0] = calloc(1, sizeof *b);
    assert_non_null(b);
    vkrt_frame_image frame = fill_aov_frame(b);
    const char *path = temp_dir_path(fx->tmp, "layers.exr");
    vkrt_error err = {{0}};
    if (!vkrt_image_write_layers(path, &frame, &(vkrt_finish_desc){.exposure = 2}, &err))
        fail_msg("write failed: %s", err.msg);
    char names[512];
    exr_channel_names(path, names, sizeof names);
    assert_string_equal(names, "B G R albedo.B albedo.G albedo.R depth.Z normal.X normal.Y "
                               "normal.Z position.X position.Y position.Z");
    check_layer(path, (const char *const[]){"R", "G", "B"}, 3, b->rgb);
    check_layer(path, (const char *const[]){"albedo.R", "albedo.G", "albedo.B"}, 3, b->albedo);
    check_layer(path, (const char *const[]){"normal.X", "normal.Y", "normal.Z"}, 3, b->normal);
    check_layer(path, (const char *const[]){"depth.Z"}, 1, b->depth);
    check_layer(path, (const char *const[]){"position.X", "position.Y", "position.Z"}, 3,
                b->position);
    char listing[256];
    list_dir(fx->tmp->dir, listing, sizeof listing);
    assert_string_equal(listing, "layers.exr");
}

/* Beside a PNG: the albedo as the beauty would be encoded (sRGB, but no exposure), the normal as
 * 0.5 n + 0.5 in 8 bits, depth and position as float EXRs with the layers' channel names. */
static void test_png_aovs_beside(void **state)
{
    fixture *fx = *state;
    aov_buffers *b = fx->buffers[0] = calloc(1, sizeof *b);
    assert_non_null(b);
    vkrt_frame_image frame = fill_aov_frame(b);
    for (int i = 0; i < AOV_W * AOV_H * 3; ++i)
        b->albedo[i] = (float)((i * 13) % 101) / 100.0f;
    vkrt_error err = {{0}};
    const char *path = temp_dir_path(fx->tmp, "shot.png");
    if (!vkrt_image_write_layers(path, &frame, &(vkrt_finish_desc){.exposure = 2}, &err))
        fail_msg("write failed: %s", err.msg);
    char listing[256];
    list_dir(fx->tmp->dir, listing, sizeof listing);
    assert_string_equal(listing,
                        "shot.albedo.png shot.depth.exr shot.normal.png shot.png shot.position.exr");
    /* The albedo's PNG is the PNG of a beauty of those values at exposure 0. */
    const char *reference = temp_dir_path(fx->tmp, "albedo-as-beauty.png");
    if (!vkrt_image_write(reference, AOV_W, AOV_H, b->albedo, 0, &err))
        fail_msg("write failed: %s", err.msg);
    int w, h, n, rw, rh, rn;
    unsigned char *albedo = stbi_load(temp_dir_path(fx->tmp, "shot.albedo.png"), &w, &h, &n, 3);
    unsigned char *as_beauty = stbi_load(reference, &rw, &rh, &rn, 3);
    unsigned char *normal = stbi_load(temp_dir_path(fx->tmp, "shot.normal.png"), &w, &h, &n, 3);
    assert_non_null(albedo);
    assert_non_null(as_beauty);
    assert_non_null(normal);
    assert_int_equal(w, AOV_W);
    assert_int_equal(h, AOV_H);
    assert_memory_equal(albedo, as_beauty, AOV_W * AOV_H * 3);
    for (int i = 0; i < AOV_W * AOV_H * 3; ++i) {
        long want = lrint(255.0 * (0.5 * b->normal[i] + 0.5));
        if (normal[i] != want)
            fail_msg("normal value %d: %g as code %d, expected %ld", i, (double)b->normal[i],
                     normal[i], want);
    }
    stbi_image_free(albedo);
    stbi_image_free(as_beauty);
    stbi_image_free(normal);
    const char *depth = temp_dir_path(fx->tmp, "shot.depth.exr");
    char names[256];
    exr_channel_names(depth, names, sizeof names);
    assert_string_equal(names, "depth.Z");
    check_layer(depth, (const char *const[]){"depth.Z"}, 1, b->depth);
    const char *position = temp_dir_path(fx->tmp, "shot.position.exr");
    exr_channel_names(position, names, sizeof names);
    assert_string_equal(names, "position.X position.Y position.Z");
    check_layer(position, (const char *const[]){"position.X", "position.Y", "position.Z"}, 3,
                b->position);
}

/* ---------------------------------------------------------------------------------------------
 * Failures leave nothing behind
 * ------------------------------------------------------------------------------------------- */

static void check_missing_folder(const fixture *fx, const char *name)
{
    char expected[512];
    const char *path = temp_dir_path(fx->tmp, name);
    float rgb[3] = {0.5f, 0.5f, 0.5f};
    vkrt_error err = {{0}};
    assert_false(vkrt_image_write(path, 1, 1, rgb, 0.0f, &err));
    snprintf(expected, sizeof expected, "%s: cannot write: No such file or directory", path);
    assert_string_equal(err.msg, expected);

    char listing[256];
    list_dir(fx->tmp->dir, listing, sizeof listing);
    assert_string_equal(listing, "");
}

static void test_missing_folder_fails_cleanly(void **state)
{
    check_missing_folder(*state, "missing/x.png");
    check_missing_folder(*state, "missing/x.exr");
}

/* rename() cannot replace a directory with a file, so this fails after the temp file was
 * fully written: the temp file must be removed and the directory left as it was. */
static void check_path_is_directory(const fixture *fx, const char *name)
{
    const char *path = temp_dir_path(fx->tmp, name);
    assert_int_equal(mkdir(path, 0755), 0);
    float rgb[2 * 2 * 3] = {0};
    vkrt_error err = {{0}};
    assert_false(vkrt_image_write(path, 2, 2, rgb, 0.0f, &err));
    assert_non_null(strstr(err.msg, path));
    assert_non_null(strstr(err.msg, "cannot write"));

    struct stat st;
    assert_int_equal(stat(path, &st), 0);
    assert_true(S_ISDIR(st.st_mode));
    char listing[256];
    list_dir(fx->tmp->dir, listing, sizeof listing);
    assert_string_equal(listing, name);
    assert_int_equal(rmdir(path), 0);
}

static void test_path_is_directory_fails_cleanly(void **state)
{
    check_path_is_directory(*state, "dir.png");
    check_path_is_directory(*state, "dir.exr");
}

/* A write that fails half way (the file-size limit makes write() return EFBIG; permission
 * bits would not stop root) must leave the previous file at path byte for byte. */
static void check_failed_write_keeps_old_file(fixture *fx, const char *name)
{
    const char *path = temp_dir_write_text(fx->tmp, name, "previous frame");

    enum { W = 64, H = 64 };
    free(fx->buffers[0]);
    float *rgb = fx->buffers[0] = malloc(sizeof(float) * W * H * 3);
    assert_non_null(rgb);
    uint32_t noise = 12345u; /* noise compresses badly, so the file is far above the limit */
    for (size_t i = 0; i < (size_t)W * H * 3; i++) {
        noise = noise * 1664525u + 1013904223u;
        rgb[i] = (float)(noise >> 8) / 16777216.0f;
    }

    struct rlimit old_limit;
    assert_int_equal(getrlimit(RLIMIT_FSIZE, &old_limit), 0);
    struct rlimit small_limit = {.rlim_cur = 200, .rlim_max = old_limit.rlim_max};
    struct sigaction ignore = {.sa_handler = SIG_IGN}, old_action;
    sigemptyset(&ignore.sa_mask);
    assert_int_equal(sigaction(SIGXFSZ, &ignore, &old_action), 0);
    assert_int_equal(setrlimit(RLIMIT_FSIZE, &small_limit), 0);

    vkrt_error err = {{0}};
    bool ok = vkrt_image_write(path, W, H, rgb, 0.0f, &err);

    assert_int_equal(setrlimit(RLIMIT_FSIZE, &old_limit), 0);
    assert_int_equal(sigaction(SIGXFSZ, &old_action, NULL), 0);

    assert_false(ok);
    char expected[512];
    snprintf(expected, sizeof expected, "%s: cannot write: %s", path, strerror(EFBIG));
    assert_string_equal(err.msg, expected);
    assert_file_contains(path, "previous frame");
    char listing[256];
    list_dir(fx->tmp->dir, listing, sizeof listing);
    assert_string_equal(listing, name);
    assert_int_equal(unlink(path), 0);
}

static void test_failed_write_keeps_old_file(void **state)
{
    check_failed_write_keeps_old_file(*state, "keep.png");
    check_failed_write_keeps_old_file(*state, "keep.exr");
}

static void test_success_replaces_old_file(void **state)
{
    fixture *fx = *state;
    const char *path = temp_dir_write_text(fx->tmp, "replace.png", "previous frame");
    float rgb[3] = {1.0f, 0.0f, 0.0f};
    vkrt_error err = {{0}};
    assert_true(vkrt_image_write(path, 1, 1, rgb, 0.0f, &err));
    unsigned char *pixels = load_png(path, 1, 1);
    assert_int_equal(pixels[0], 255);
    assert_int_equal(pixels[1], 0);
    assert_int_equal(pixels[2], 0);
    stbi_image_free(pixels);
}

static void test_unknown_extension(void **state)
{
    fixture *fx = *state;
    char expected[512];
    const char *path = temp_dir_path(fx->tmp, "x.jpg");
    float rgb[3] = {0};
    vkrt_error err = {{0}};
    assert_false(vkrt_image_write(path, 1, 1, rgb, 0.0f, &err));
    snprintf(expected, sizeof expected, "%s: unknown image format (use .png or .exr)", path);
    assert_string_equal(err.msg, expected);
    char listing[256];
    list_dir(fx->tmp->dir, listing, sizeof listing);
    assert_string_equal(listing, "");
}

static void test_empty_image_rejected(void **state)
{
    fixture *fx = *state;
    const char *path = temp_dir_path(fx->tmp, "empty.png");
    float rgb[3] = {0};
    vkrt_error err = {{0}};
    assert_false(vkrt_image_write(path, 0, 4, rgb, 0.0f, &err));
    assert_non_null(strstr(err.msg, path));
    assert_false(vkrt_image_write(path, 1, 1, NULL, 0.0f, &err));
}

static void test_format_of(void **state)
{
    (void)state;
    assert_int_equal(vkrt_image_format_of("a.png"), VKRT_IMAGE_PNG);
    assert_int_equal(vkrt_image_format_of("out/A.PNG"), VKRT_IMAGE_PNG);
    assert_int_equal(vkrt_image_format_of("b.Exr"), VKRT_IMAGE_EXR);
    assert_int_equal(vkrt_image_format_of("c.png.bak"), VKRT_IMAGE_UNKNOWN);
    assert_int_equal(vkrt_image_format_of("png"), VKRT_IMAGE_UNKNOWN);
    assert_int_equal(vkrt_image_format_of(""), VKRT_IMAGE_UNKNOWN);
    assert_int_equal(vkrt_image_format_of(NULL), VKRT_IMAGE_UNKNOWN);
}

/* ---------------------------------------------------------------------------------------------
 * Frame patterns
 * ------------------------------------------------------------------------------------------- */

static void assert_frame_path(const char *pattern, uint32_t frame, const char *expected)
{
    char out[64];
    vkrt_error err = {{0}};
    if (!vkrt_frame_path(out, sizeof out, pattern, frame, &err))
        fail_msg("\"%s\" rejected: %s", pattern, err.msg);
    assert_string_equal(out, expected);
}

static void assert_frame_pattern_rejected(const char *pattern)
{
    char out[64];
    vkrt_error err = {{0}};
    if (vkrt_frame_path(out, sizeof out, pattern, 7, &err))
        fail_msg("\"%s\" accepted as \"%s\"", pattern, out);
    assert_non_null(strstr(err.msg, "frame pattern"));
}

static void test_frame_path_expands(void **state)
{
    (void)state;
    assert_frame_path("f%04d.png", 7, "f0007.png");
    assert_frame_path("%d", 123, "123");
    assert_frame_path("%d", 4294967295u, "4294967295");
    assert_frame_path("f%04d.png", 123456, "f123456.png"); /* width is a minimum */
    assert_frame_path("%3d|", 7, "  7|");
    assert_frame_path("%%", 7, "%");
    assert_frame_path("100%%_%02d.exr", 5, "100%_05.exr");
    assert_frame_path("out/plain.png", 7, "out/plain.png");
    assert_frame_path("", 7, "");
}

static void test_frame_path_rejects(void **state)
{
    (void)state;
    assert_frame_pattern_rejected("a%s");
    assert_frame_pattern_rejected("%x.png");
    assert_frame_pattern_rejected("%n");
    assert_frame_pattern_rejected("%i");
    assert_frame_pattern_rejected("%ld");
    assert_frame_pattern_rejected("%-4d");
    assert_frame_pattern_rejected("%+d");
    assert_frame_pattern_rejected("%5.2d");
    assert_frame_pattern_rejected("%100d"); /* three-digit width */
    assert_frame_pattern_rejected("%*d");
    assert_frame_pattern_rejected("%0d");
    assert_frame_pattern_rejected("trailing%");
    assert_frame_pattern_rejected("%d_%d"); /* only one frame number */
    assert_frame_pattern_rejected("%d%s");  /* a bad conversion after a good one */
}

static void test_frame_path_too_long(void **state)
{
    (void)state;
    vkrt_error err = {{0}};
    char out[10];
    /* "f0007.png" is 9 characters: fits in 10 with its NUL, not in 9 */
    assert_true(vkrt_frame_path(out, 10, "f%04d.png", 7, &err));
    assert_string_equal(out, "f0007.png");
    assert_false(vkrt_frame_path(out, 9, "f%04d.png", 7, &err));
    assert_non_null(strstr(err.msg, "longer"));
    assert_false(vkrt_frame_path(out, 9, "plain_long.png", 7, &err));
    assert_false(vkrt_frame_path(out, 3, "%d", 1234, &err));
    assert_string_equal(out, ""); /* never a silently cut path */
    assert_false(vkrt_frame_path(out, 0, "x", 1, &err));
}

static void test_frame_pattern_has_number(void **state)
{
    (void)state;
    assert_true(vkrt_frame_pattern_has_number("f%04d.png"));
    assert_true(vkrt_frame_pattern_has_number("%d"));
    assert_true(vkrt_frame_pattern_has_number("100%%_%3d.exr"));
    assert_false(vkrt_frame_pattern_has_number("plain.png"));
    assert_false(vkrt_frame_pattern_has_number("100%%d.png")); /* literal "%" then "d" */
    assert_false(vkrt_frame_pattern_has_number("a%s.png"));
    assert_false(vkrt_frame_pattern_has_number(""));
    assert_false(vkrt_frame_pattern_has_number(NULL));
}

/* The pid of a process that has exited and been reaped: no process has it (until it is reused,
 * which takes the kernel a whole lap of pids). */
static long dead_pid(void)
{
    pid_t child = fork();
    assert_true(child >= 0);
    if (child == 0)
        _exit(0);
    assert_int_equal(waitpid(child, NULL, 0), child);
    return (long)child;
}

/* Every temporary of the pattern's frames whose writer is gone goes, complete frames or not, in
 * both namings; a live writer's, another host's, another pattern's and the frames stay. */
static void test_dead_temporaries_removed(void **state)
{
    fixture *fx = *state;
    char host[300], live_name[400], name[400];
    assert_true(vkrt_temporary_name(live_name, sizeof live_name, "f007.exr"));
    /* "f007.exr.tmp-<host>-<pid>": this process's own */
    snprintf(host, sizeof host, "%.*s", (int)(strrchr(live_name, '-') - live_name - 13),
             live_name + 13);
    long dead = dead_pid();
    const char *made[] = {"f001.exr", "f007.exr", "g001.exr.tmp-1", "f1x.exr.tmp-1", live_name};
    for (size_t i = 0; i < sizeof made / sizeof *made; i++)
        temp_dir_write_text(fx->tmp, made[i], "x");
    static const char *const gone_formats[] = {"f001.exr.tmp-%s-%ld", "f007.exr.tmp-%s-%ld",
                                               "f123456.exr.tmp-%s-%ld", "f001.exr.tmp-%.0s%ld"};
    for (size_t i = 0; i < 4; i++) {
        snprintf(name, sizeof name, gone_formats[i], host, dead);
        temp_dir_write_text(fx->tmp, name, "x");
    }
    snprintf(name, sizeof name, "f002.exr.tmp-other_host-%ld", dead);
    temp_dir_write_text(fx->tmp, name, "x");

    char pattern[600];
    snprintf(pattern, sizeof pattern, "%s/f%%03d.exr", fx->tmp->dir);
    assert_int_equal(vkrt_temporaries_remove_dead(pattern), 4);
    char listing[2048];
    list_dir(fx->tmp->dir, listing, sizeof listing);
    char want[2048];
    snprintf(want, sizeof want, "f001.exr f002.exr.tmp-other_host-%ld f007.exr %s f1x.exr.tmp-1 "
                                "g001.exr.tmp-1", dead, live_name);
    assert_string_equal(listing, want);

    /* One frame's, by its path; a '%' in it is a plain character. */
    snprintf(name, sizeof name, "100%%.exr.tmp-%s-%ld", host, dead);
    temp_dir_write_text(fx->tmp, name, "x");
    snprintf(pattern, sizeof pattern, "%s/100%%.exr", fx->tmp->dir);
    assert_int_equal(vkrt_temporaries_remove_dead_beside(pattern), 1);
    /* A pattern without a number: its one frame. */
    temp_dir_write_text(fx->tmp, name, "x");
    snprintf(pattern, sizeof pattern, "%s/100%%%%.exr", fx->tmp->dir);
    assert_int_equal(vkrt_temporaries_remove_dead(pattern), 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_png_matches_srgb_curve, make_fixture, remove_fixture),
        cmocka_unit_test_setup_teardown(test_png_exposure_plus_one_doubles, make_fixture, remove_fixture),
        cmocka_unit_test_setup_teardown(test_exr_roundtrip_small, make_fixture, remove_fixture),
        cmocka_unit_test_setup_teardown(test_exr_roundtrip_several_chunks, make_fixture, remove_fixture),
        cmocka_unit_test_setup_teardown(test_exr_aov_layers, make_fixture, remove_fixture),
        cmocka_unit_test_setup_teardown(test_png_aovs_beside, make_fixture, remove_fixture),
        cmocka_unit_test_setup_teardown(test_missing_folder_fails_cleanly, make_fixture, remove_fixture),
        cmocka_unit_test_setup_teardown(test_path_is_directory_fails_cleanly, make_fixture, remove_fixture),
        cmocka_unit_test_setup_teardown(test_failed_write_keeps_old_file, make_fixture, remove_fixture),
        cmocka_unit_test_setup_teardown(test_success_replaces_old_file, make_fixture, remove_fixture),
        cmocka_unit_test_setup_teardown(test_unknown_extension, make_fixture, remove_fixture),
        cmocka_unit_test_setup_teardown(test_empty_image_rejected, make_fixture, remove_fixture),
        cmocka_unit_test_setup_teardown(test_dead_temporaries_removed, make_fixture, remove_fixture),
        cmocka_unit_test(test_format_of),
        cmocka_unit_test(test_frame_path_expands),
        cmocka_unit_test(test_frame_path_rejects),
        cmocka_unit_test(test_frame_path_too_long),
        cmocka_unit_test(test_frame_pattern_has_number),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
