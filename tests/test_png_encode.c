/*
 * test_png_encode.c: src/output/png_encode.c and src/output/srgb8.c.
 *
 * The encoder's files are decoded by stb_image (another implementation, which unfilters and
 * inflates on its own) and must give back the exact pixels, as stb_image_write's files of the
 * same pixels do: odd widths, one row, one column, several row blocks and several IDAT chunks.
 * Every chunk's CRC is checked with a bitwise CRC-32 written here from the standard, since
 * stb_image does not check them. Each filter type is undone by an unfilter written here from
 * the standard. The sRGB table is held to the exact encoding on a sample of all 2^32 floats
 * and around every code value's start (research/yardsticks/srgb8_check.c checks all of them).
 */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h> /* cmocka needs these before its header */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <stb_image.h>
#include <stb_image_write.h>

#include "output/png_encode.h"
#include "output/srgb8.h"

/* A growing buffer the encoder's sink fills; stop_after > 0 makes the sink fail after that many
 * calls. */
typedef struct bytes {
    uint8_t *data;
    size_t size, capacity;
    int calls, stop_after;
} bytes;

static bool bytes_sink(void *context, const void *data, size_t size)
{
    bytes *b = context;
    if (b->stop_after && ++b->calls > b->stop_after)
        return false;
    if (b->size + size > b->capacity) {
        b->capacity = 2 * (b->size + size);
        b->data = realloc(b->data, b->capacity);
        assert_non_null(b->data);
    }
    memcpy(b->data + b->size, data, size);
    b->size += size;
    return true;
}

/* Pixels that exercise the filters: smooth ramps, hard edges and, where noise is set, bytes
 * from a fixed generator that deflate cannot shrink. */
static uint8_t *make_pixels(uint32_t w, uint32_t h, bool noise)
{
    uint8_t *rgb = malloc((size_t)w * h * 3);
    assert_non_null(rgb);
    uint32_t state = 12345;
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x)
            for (uint32_t c = 0; c < 3; ++c) {
                state = state * 1664525u + 1013904223u;
                uint8_t *p = &rgb[((size_t)y * w + x) * 3 + c];
                *p = noise ? (uint8_t)(state >> 24)
                           : (uint8_t)((x * (c + 1) + y * 3) ^ ((x / 7 + y / 5) & 1 ? 0x80 : 0));
            }
    return rgb;
}

static uint32_t read_u32(const uint8_t *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

/* CRC-32 of ISO 3309 (PNG's, section 5.5), bit by bit: slow and obvious. */
static uint32_t crc32_bitwise(const uint8_t *data, size_t size)
{
    uint32_t crc = 0xffffffffu;
    for (size_t i = 0; i < size; ++i) {
        crc ^= data[i];
        for (int k = 0; k < 8; ++k)
            crc = crc & 1 ? (crc >> 1) ^ 0xedb88320u : crc >> 1;
    }
    return crc ^ 0xffffffffu;
}

/* Walks the file's chunks: the signature, IHDR first with the size and RGB8, IDATs of at most
 * 1 MiB together, IEND last, every CRC right. Returns the number of IDAT chunks. */
static int check_chunks(const bytes *png, uint32_t w, uint32_t h)
{
    static const uint8_t signature[8] = {137, 80, 78, 71, 13, 10, 26, 10};
    assert_true(png->size > 8 && memcmp(png->data, signature, 8) == 0);
    size_t at = 8;
    int index = 0, idats = 0;
    bool ended = false;
    while (at < png->size) {
        assert_false(ended);
        assert_true(png->size - at >= 12);
        uint32_t length = read_u32(png->data + at);
        assert_true(png->size - at - 12 >= length);
        const uint8_t *type = png->data + at + 4;
        uint32_t crc = read_u32(png->data + at + 8 + length);
        assert_int_equal(crc, crc32_bitwise(type, 4 + length));
        if (index == 0) {
            assert_memory_equal(type, "IHDR", 4);
            assert_int_equal(length, 13);
            assert_int_equal(read_u32(type + 4), w);
            assert_int_equal(read_u32(type + 8), h);
            assert_memory_equal(type + 12, ((const uint8_t[]){8, 2, 0, 0, 0}), 5);
        } else if (memcmp(type, "IDAT", 4) == 0) {
            assert_true(length > 0 && length <= (1u << 20));
            ++idats;
        } else {
            assert_memory_equal(type, "IEND", 4);
            assert_int_equal(length, 0);
            ended = true;
        }
        at += 12 + length;
        ++index;
    }
    assert_true(ended);
    return idats;
}

static uint8_t *decode(const uint8_t *data, size_t size, uint32_t w, uint32_t h)
{
    int dw = 0, dh = 0, channels = 0;
    uint8_t *pixels = stbi_load_from_memory(data, (int)size, &dw, &dh, &channels, 3);
    assert_non_null(pixels);
    assert_int_equal(dw, w);
    assert_int_equal(dh, h);
    assert_int_equal(channels, 3);
    return pixels;
}

static void stb_sink(void *context, void *data, int size)
{
    bytes_sink(context, data, (size_t)size);
}

/* Encodes w x h pixels and checks the file; returns its IDAT chunk count. */
static int check_roundtrip(uint32_t w, uint32_t h, bool noise)
{
    uint8_t *rgb = make_pixels(w, h, noise);
    bytes png = {0};
    assert_int_equal(png_encode_rgb8(rgb, w, h, bytes_sink, &png), PNG_ENCODE_OK);
    int idats = check_chunks(&png, w, h);
    uint8_t *ours = decode(png.data, png.size, w, h);
    if (memcmp(ours, rgb, (size_t)w * h * 3) != 0)
        fail_msg("%ux%u: the decoded pixels differ from the encoded ones", w, h);
    /* stb_image_write, vkrt's writer before, on the same pixels: the same picture comes back. */
    bytes stb = {0};
    assert_true(stbi_write_png_to_func(stb_sink, &stb, (int)w, (int)h, 3, rgb, (int)w * 3));
    uint8_t *theirs = decode(stb.data, stb.size, w, h);
    assert_memory_equal(ours, theirs, (size_t)w * h * 3);
    stbi_image_free(ours);
    stbi_image_free(theirs);
    free(stb.data);
    free(png.data);
    free(rgb);
    return idats;
}

static void decodes_to_its_pixels(void **state)
{
    (void)state;
    static const uint32_t sizes[][2] = {{1, 1},  {1, 7},    {5, 1},   {3, 2},
                                        {17, 5}, {101, 67}, {333, 41}};
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; ++i) {
        check_roundtrip(sizes[i][0], sizes[i][1], false);
        check_roundtrip(sizes[i][0], sizes[i][1], true);
    }
}

static void large_files_take_several_idat_chunks(void **state)
{
    (void)state;
    /* 1.5 MB of noise: more than one 1 MiB chunk, and rows across several blocks. */
    assert_true(check_roundtrip(707, 709, true) >= 2);
}

static void a_failing_sink_stops_the_encoding(void **state)
{
    (void)state;
    uint8_t *rgb = make_pixels(400, 300, true);
    for (int after = 1; after <= 3; ++after) {
        bytes png = {.stop_after = after};
        assert_int_equal(png_encode_rgb8(rgb, 400, 300, bytes_sink, &png), PNG_ENCODE_SINK_FAILED);
        assert_int_equal(png.calls, after + 1); /* nothing more after the refusal */
        free(png.data);
    }
    free(rgb);
}

/* Undoes filter row by row, written from the PNG specification (section 9.2) apart from the
 * encoder; prior is NULL for the first row. */
static void unfilter_row(uint8_t *row, const uint8_t *prior, const uint8_t *filtered, size_t n)
{
    int type = filtered[0];
    const uint8_t *f = filtered + 1;
    for (size_t i = 0; i < n; ++i) {
        int a = i >= 3 ? row[i - 3] : 0, b = prior ? prior[i] : 0;
        int c = prior && i >= 3 ? prior[i - 3] : 0;
        int p = a + b - c, pa = abs(p - a), pb = abs(p - b), pc = abs(p - c);
        int predictor = type == 0              ? 0
                        : type == 1            ? a
                        : type == 2            ? b
                        : type == 3            ? (a + b) / 2
                        : pa <= pb && pa <= pc ? a
                        : pb <= pc             ? b
                                               : c;
        row[i] = (uint8_t)(f[i] + predictor);
    }
}

static void every_filter_undoes(void **state)
{
    (void)state;
    enum { W = 29, H = 11 };
    size_t n = W * 3;
    uint8_t filtered[(W * 3 + 1) * H], back[W * 3 * H];
    for (int case_ = 0; case_ < 2 * (PNG_FILTER_CHOICE_PER_ROW + 1); ++case_) {
        int filter = case_ / 2;
        uint8_t *rgb = make_pixels(W, H, case_ % 2); /* noise makes Paeth's ties */
        /* In two calls, as the encoder's blocks do: rows 4 on read the row above them. */
        assert_true(png_filter_rows(rgb, W, 0, 4, filter, filtered));
        assert_true(png_filter_rows(rgb, W, 4, H - 4, filter, filtered + 4 * (n + 1)));
        for (uint32_t y = 0; y < H; ++y) {
            const uint8_t *f = filtered + y * (n + 1);
            if (filter != PNG_FILTER_CHOICE_PER_ROW)
                assert_int_equal(f[0], filter);
            unfilter_row(back + y * n, y ? back + (y - 1) * n : NULL, f, n);
        }
        if (memcmp(back, rgb, sizeof back) != 0)
            fail_msg("filter %d does not undo", filter);
        free(rgb);
    }
}

/* ------------------------------------------------------------------ the sRGB table */

static float float_of_bits(uint32_t bits)
{
    float f;
    memcpy(&f, &bits, sizeof f);
    return f;
}

/* The table and the exact encoding agree on values (times scale). */
static void check_table(const srgb8_table *table, const float *values, size_t count, float scale)
{
    uint8_t codes[256];
    for (size_t at = 0; at < count; at += 256) {
        size_t n = count - at < 256 ? count - at : 256;
        srgb8_encode_array(table, values + at, scale, n, codes);
        for (size_t i = 0; i < n; ++i)
            if (codes[i] != srgb8_encode(values[at + i] * scale))
                fail_msg("%.9g times %g: table %u, exact %u", (double)values[at + i], (double)scale,
                         codes[i], srgb8_encode(values[at + i] * scale));
    }
}

static void srgb_table_is_exact(void **state)
{
    (void)state;
    srgb8_table *table = malloc(sizeof *table);
    assert_non_null(table);
    srgb8_table_init(table);
    enum { SAMPLE = 4096 };
    float *values = malloc(SAMPLE * sizeof *values);
    assert_non_null(values);
    /* Every 1021st bit pattern of all 2^32 (a prime stride, so every slice and exponent). */
    uint64_t bits = 0;
    while (bits < (1ull << 32)) {
        size_t n = 0;
        for (; n < SAMPLE && bits < (1ull << 32); ++n, bits += 1021)
            values[n] = float_of_bits((uint32_t)bits);
        check_table(table, values, n, 1.0f);
    }
    /* A few floats either side of where each code value begins: the table's edges. */
    size_t n = 0;
    for (int code = 1; code <= 255; ++code) {
        float x = (float)pow(((code - 0.5) / 255.0 + 0.055) / 1.055, 2.4);
        if (code <= 10)
            x = (float)((code - 0.5) / 255.0 / 12.92);
        for (int k = -6; k <= 6; ++k) {
            uint32_t b;
            memcpy(&b, &x, sizeof b);
            values[n++] = float_of_bits(b + (uint32_t)k);
        }
    }
    check_table(table, values, n, 1.0f);
    /* The ends and the odd values, and an exposure's scale on them all. */
    static const float specials[] = {0.0f,     -0.0f,     1.0f,       0.99999994f, 1.0000001f,
                                     1e-45f,   1e-38f,    0.0031308f, -1e-45f,     -1.0f,
                                     INFINITY, -INFINITY, NAN,        -NAN,        3.0e38f};
    check_table(table, specials, sizeof specials / sizeof specials[0], 1.0f);
    check_table(table, specials, sizeof specials / sizeof specials[0], 2.0f);
    check_table(table, values, n, 0.7071068f);
    /* Each slice holds at most one code value's start, which the lookup needs. */
    for (uint32_t s = 0; s + 1 < SRGB8_SLICES; ++s) {
        float next_slice = float_of_bits((s + 1) << SRGB8_SLICE_SHIFT);
        assert_true(table->code[s + 1] <= table->code[s] + 1);
        assert_true(table->code[s + 1] == table->code[s] || table->next[s] <= next_slice);
    }
    free(values);
    free(table);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(decodes_to_its_pixels),
        cmocka_unit_test(large_files_take_several_idat_chunks),
        cmocka_unit_test(a_failing_sink_stops_the_encoding),
        cmocka_unit_test(every_filter_undoes),
        cmocka_unit_test(srgb_table_is_exact),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
