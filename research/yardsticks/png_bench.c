/*
 * png_bench.c: PNG encoders timed on real frames (issue 22's writer): for each 8-bit RGB image
 * given, the encode time (best of RUNS, in memory, no file) and the size of stb_image_write at
 * its default level 8 and at levels 1-3; our PNG container (src/output/png_encode.h's filters)
 * over zlib, libdeflate and ISA-L at several levels with one filter for the whole image (Up,
 * Paeth) or stb's per-row choice; libspng's and libpng's own writers. Every encoding is decoded
 * again with stb_image and compared to the input, so a fast but wrong encoder shows.
 *
 *   png-bench [--runs N] FRAME.png...
 *
 * Built by meson when zlib, libdeflate, ISA-L, libspng and libpng are all installed (the
 * product needs only ISA-L); research/journal.md holds what it printed.
 */
#define _POSIX_C_SOURCE 200809L
#include <isa-l/igzip_lib.h>
#include <libdeflate.h>
#include <png.h>
#include <spng.h>
#include <stb_image.h>
#include <stb_image_write.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "clock.h"
#include "output/png_encode.h"
#include "output/srgb8.h"

/* A growing byte buffer that every encoder writes into. */
typedef struct bytes {
    uint8_t *data;
    size_t size, capacity;
} bytes;

static void bytes_append(bytes *b, const void *data, size_t size)
{
    if (b->size + size > b->capacity) {
        b->capacity = (b->size + size) * 2;
        b->data = realloc(b->data, b->capacity);
        if (!b->data) {
            fputs("png-bench: out of memory\n", stderr);
            exit(1);
        }
    }
    memcpy(b->data + b->size, data, size);
    b->size += size;
}

static bool bytes_sink(void *context, const void *data, size_t size)
{
    bytes_append(context, data, size);
    return true;
}

typedef struct image {
    const char *name;
    int width, height;
    const uint8_t *rgb;
} image;

/* ------------------------------------------------------------------ our container, 3 deflaters */

typedef enum deflater { ZLIB, LIBDEFLATE, ISAL } deflater;
static const char *const deflater_names[] = {"zlib", "libdeflate", "isa-l"};

/* Deflates filtered (size bytes) into a zlib stream. */
static void deflate_with(deflater d, int level, const uint8_t *filtered, size_t size, bytes *out)
{
    if (d == ZLIB) {
        uLongf bound = compressBound(size);
        uint8_t *z = malloc(bound);
        if (!z || compress2(z, &bound, filtered, size, level) != Z_OK)
            exit(1);
        bytes_append(out, z, bound);
        free(z);
    } else if (d == LIBDEFLATE) {
        struct libdeflate_compressor *c = libdeflate_alloc_compressor(level);
        size_t bound = libdeflate_zlib_compress_bound(c, size);
        uint8_t *z = malloc(bound);
        size_t n = z ? libdeflate_zlib_compress(c, filtered, size, z, bound) : 0;
        if (!n)
            exit(1);
        bytes_append(out, z, n);
        free(z);
        libdeflate_free_compressor(c);
    } else {
        static const uint32_t level_buf_size[] = {ISAL_DEF_LVL0_DEFAULT, ISAL_DEF_LVL1_DEFAULT,
                                                  ISAL_DEF_LVL2_DEFAULT, ISAL_DEF_LVL3_DEFAULT};
        struct isal_zstream s;
        isal_deflate_init(&s);
        s.level = (uint32_t)level;
        s.level_buf_size = level_buf_size[level];
        s.level_buf = malloc(s.level_buf_size);
        s.gzip_flag = IGZIP_ZLIB;
        s.end_of_stream = 1;
        s.flush = NO_FLUSH;
        size_t bound = size + size / 8 + 1024;
        uint8_t *z = malloc(bound);
        s.next_in = (uint8_t *)filtered;
        s.avail_in = (uint32_t)size;
        s.next_out = z;
        s.avail_out = (uint32_t)bound;
        if (!z || !s.level_buf || isal_deflate(&s) != COMP_OK || s.avail_in != 0 ||
            s.internal_state.state != ZSTATE_END)
            exit(1);
        bytes_append(out, z, bound - s.avail_out);
        free(z);
        free(s.level_buf);
    }
}

static void chunk(bytes *out, const char type[4], const uint8_t *data, size_t size)
{
    uint8_t head[8] = {(uint8_t)(size >> 24), (uint8_t)(size >> 16), (uint8_t)(size >> 8),
                       (uint8_t)size,         (uint8_t)type[0],      (uint8_t)type[1],
                       (uint8_t)type[2],      (uint8_t)type[3]};
    bytes_append(out, head, 8);
    bytes_append(out, data, size);
    uint32_t crc = (uint32_t)crc32(crc32(0, head + 4, 4), data, (uInt)size);
    uint8_t tail[4] = {(uint8_t)(crc >> 24), (uint8_t)(crc >> 16), (uint8_t)(crc >> 8),
                       (uint8_t)crc};
    bytes_append(out, tail, 4);
}

static void encode_ours(const image *im, png_filter_choice filter, deflater d, int level,
                        bytes *out)
{
    size_t size = png_filtered_size((uint32_t)im->width, (uint32_t)im->height);
    uint8_t *filtered = malloc(size);
    if (!filtered)
        exit(1);
    if (!png_filter_rows(im->rgb, (uint32_t)im->width, 0, (uint32_t)im->height, filter, filtered))
        exit(1);
    bytes z = {0};
    deflate_with(d, level, filtered, size, &z);
    free(filtered);
    static const uint8_t signature[8] = {137, 80, 78, 71, 13, 10, 26, 10};
    bytes_append(out, signature, 8);
    uint8_t ihdr[13] = {(uint8_t)(im->width >> 24),
                        (uint8_t)(im->width >> 16),
                        (uint8_t)(im->width >> 8),
                        (uint8_t)im->width,
                        (uint8_t)(im->height >> 24),
                        (uint8_t)(im->height >> 16),
                        (uint8_t)(im->height >> 8),
                        (uint8_t)im->height,
                        8,
                        2,
                        0,
                        0,
                        0};
    chunk(out, "IHDR", ihdr, sizeof ihdr);
    chunk(out, "IDAT", z.data, z.size);
    chunk(out, "IEND", NULL, 0);
    free(z.data);
}

/* ------------------------------------------------------------------ the libraries' writers */

static void stb_sink(void *context, void *data, int size)
{
    bytes_append(context, data, (size_t)size);
}

static void encode_stb(const image *im, int level, bytes *out)
{
    stbi_write_png_compression_level = level;
    if (!stbi_write_png_to_func(stb_sink, out, im->width, im->height, 3, im->rgb, im->width * 3))
        exit(1);
    stbi_write_png_compression_level = 8;
}

static void encode_spng(const image *im, bytes *out)
{
    spng_ctx *ctx = spng_ctx_new(SPNG_CTX_ENCODER);
    spng_set_option(ctx, SPNG_ENCODE_TO_BUFFER, 1);
    struct spng_ihdr ihdr = {.width = (uint32_t)im->width,
                             .height = (uint32_t)im->height,
                             .bit_depth = 8,
                             .color_type = SPNG_COLOR_TYPE_TRUECOLOR};
    spng_set_ihdr(ctx, &ihdr);
    size_t size = (size_t)im->width * im->height * 3;
    int rc = spng_encode_image(ctx, im->rgb, size, SPNG_FMT_PNG, SPNG_ENCODE_FINALIZE);
    size_t n = 0;
    void *png = rc ? NULL : spng_get_png_buffer(ctx, &n, &rc);
    if (!png)
        exit(1);
    bytes_append(out, png, n);
    free(png);
    spng_ctx_free(ctx);
}

static void libpng_sink(png_structp p, png_bytep data, png_size_t size)
{
    bytes_append(png_get_io_ptr(p), data, size);
}

static void libpng_flush(png_structp p)
{
    (void)p;
}

/* level < 0: libpng's defaults (zlib 6, its adaptive filter choice); else that level, Up. */
static void encode_libpng(const image *im, int level, bytes *out)
{
    png_structp p = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(p);
    if (setjmp(png_jmpbuf(p)))
        exit(1);
    png_set_write_fn(p, out, libpng_sink, libpng_flush);
    png_set_IHDR(p, info, (png_uint_32)im->width, (png_uint_32)im->height, 8, PNG_COLOR_TYPE_RGB,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    if (level >= 0) {
        png_set_compression_level(p, level);
        png_set_filter(p, 0, PNG_FILTER_UP);
    }
    png_write_info(p, info);
    for (int y = 0; y < im->height; ++y)
        png_write_row(p, im->rgb + (size_t)y * im->width * 3);
    png_write_end(p, info);
    png_destroy_write_struct(&p, &info);
}

/* ------------------------------------------------------------------ the table */

typedef struct method {
    const char *name;
    int kind; /* 0 ours, 1 stb, 2 spng, 3 libpng, 4 vkrt's png_encode_rgb8 */
    png_filter_choice filter;
    deflater d;
    int level;
} method;

static void encode(const method *m, const image *im, bytes *out)
{
    out->size = 0;
    switch (m->kind) {
    case 0:
        encode_ours(im, m->filter, m->d, m->level, out);
        break;
    case 1:
        encode_stb(im, m->level, out);
        break;
    case 2:
        encode_spng(im, out);
        break;
    case 3:
        encode_libpng(im, m->level, out);
        break;
    default:
        if (png_encode_rgb8(im->rgb, (uint32_t)im->width, (uint32_t)im->height, bytes_sink, out) !=
            PNG_ENCODE_OK)
            exit(1);
    }
}

static bool decodes_to(const bytes *png, const image *im)
{
    int w, h, n;
    uint8_t *rgb = stbi_load_from_memory(png->data, (int)png->size, &w, &h, &n, 3);
    bool same =
        rgb && w == im->width && h == im->height && memcmp(rgb, im->rgb, (size_t)w * h * 3) == 0;
    stbi_image_free(rgb);
    return same;
}

int main(int argc, char **argv)
{
    int runs = 3, first = 1;
    if (argc > 2 && strcmp(argv[1], "--runs") == 0) {
        runs = atoi(argv[2]);
        first = 3;
    }
    if (first >= argc || runs < 1) {
        fputs("usage: png-bench [--runs N] FRAME.png...\n", stderr);
        return 2;
    }
    static const char *const filter_names[] = {"none", "sub", "up", "avg", "paeth", "per-row"};
    method methods[64];
    int count = 0;
    methods[count++] = (method){"stb 8 (vkrt before)", 1, 0, 0, 8};
    for (int level = 1; level <= 3; ++level)
        methods[count++] = (method){"stb", 1, 0, 0, level};
    static const png_filter_choice filters[] = {PNG_FILTER_CHOICE_UP, PNG_FILTER_CHOICE_PAETH,
                                                PNG_FILTER_CHOICE_PER_ROW};
    for (int d = ZLIB; d <= ISAL; ++d)
        for (size_t f = 0; f < sizeof filters / sizeof filters[0]; ++f) {
            static const int zlib_levels[] = {1, 3, 6}, isal_levels[] = {1, 2, 3};
            for (int l = 0; l < 3; ++l)
                methods[count++] = (method){deflater_names[d], 0, filters[f], (deflater)d,
                                            d == ISAL ? isal_levels[l] : zlib_levels[l]};
        }
    methods[count++] = (method){"libspng (zlib 6, its filters)", 2, 0, 0, 6};
    methods[count++] = (method){"libpng (zlib 6, its filters)", 3, 0, 0, -1};
    methods[count++] = (method){"libpng up", 3, 0, 0, 1};
    methods[count++] = (method){"vkrt now (png_encode_rgb8)", 4, PNG_FILTER_CHOICE_UP, ISAL, 1};

    for (int a = first; a < argc; ++a) {
        image im = {.name = argv[a]};
        int n;
        uint8_t *rgb = stbi_load(argv[a], &im.width, &im.height, &n, 3);
        if (!rgb) {
            fprintf(stderr, "png-bench: %s: cannot read\n", argv[a]);
            return 1;
        }
        im.rgb = rgb;
        double raw = (double)im.width * im.height * 3;
        printf("%s: %dx%d, %.2f MB raw; best of %d runs\n", im.name, im.width, im.height, raw / 1e6,
               runs);
        printf("  %-30s %-8s %5s %9s %9s %7s %6s\n", "encoder", "filter", "level", "ms", "MB",
               "MB/s", "vs stb");
        bytes out = {0};
        size_t stb_size = 0;
        for (int i = 0; i < count; ++i) {
            const method *m = &methods[i];
            double best = 1e30;
            for (int r = 0; r < runs; ++r) {
                double t0 = vkrt_clock_ms();
                encode(m, &im, &out);
                double t = vkrt_clock_ms() - t0;
                best = t < best ? t : best;
            }
            if (i == 0)
                stb_size = out.size;
            bool ok = decodes_to(&out, &im);
            printf("  %-30s %-8s %5d %9.1f %9.3f %7.0f %6.3f%s\n", m->name,
                   m->kind == 0 || m->kind == 4 ? filter_names[m->filter] : "its own", m->level,
                   best, out.size / 1e6, raw / 1e3 / best, (double)out.size / (double)stb_size,
                   ok ? "" : "  DECODES WRONG");
            if (!ok)
                return 1;
        }
        /* The whole of a frame's PNG from the renderer's floats: the sRGB curve, then the
         * encoder; before, srgb8_encode per value (a pow each) and stb; now the table and
         * png_encode_rgb8. The floats are the frame's codes taken back to linear. */
        size_t values = (size_t)im.width * im.height * 3;
        float *linear = malloc(values * sizeof *linear);
        uint8_t *codes = malloc(values);
        srgb8_table *table = malloc(sizeof *table);
        if (!linear || !codes || !table)
            return 1;
        for (size_t i = 0; i < values; ++i) {
            double v = (rgb[i] + 0.25) / 255.0; /* inside the code's interval, not at its edge */
            linear[i] = (float)(v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4));
        }
        double best_before = 1e30, best_after = 1e30, best_table = 1e30;
        for (int r = 0; r < runs; ++r) {
            double t0 = vkrt_clock_ms();
            for (size_t i = 0; i < values; ++i)
                codes[i] = srgb8_encode(linear[i]);
            image coded = im;
            coded.rgb = codes;
            encode(&methods[0], &coded, &out);
            double t2 = vkrt_clock_ms();
            srgb8_table_init(table);
            srgb8_encode_array(table, linear, 1.0f, values, codes);
            double t3 = vkrt_clock_ms();
            encode(&methods[count - 1], &coded, &out);
            double t4 = vkrt_clock_ms();
            best_before = t2 - t0 < best_before ? t2 - t0 : best_before;
            best_after = t4 - t2 < best_after ? t4 - t2 : best_after;
            best_table = t3 - t2 < best_table ? t3 - t2 : best_table;
            if (r == 0 && memcmp(codes, rgb, values) != 0) {
                fputs("png-bench: the sRGB table gave other codes than the frame's\n", stderr);
                return 1;
            }
        }
        printf("  floats to PNG bytes: before (pow per value, stb 8) %.1f ms; now (table %.1f ms, "
               "png_encode_rgb8) %.1f ms: %.1fx\n",
               best_before, best_table, best_after, best_before / best_after);
        free(table);
        free(codes);
        free(linear);
        free(out.data);
        stbi_image_free(rgb);
    }
    return 0;
}
