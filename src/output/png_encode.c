/*
 * png_encode.c: PNG's row filters (ISO/IEC 15948, section 9) on 8-bit RGB, and the file's bytes:
 * signature, IHDR, IDAT chunks holding the zlib stream of the filtered rows, IEND. Rows are
 * filtered and deflated a block at a time and the chunks handed on as they fill, so the memory
 * an encoding takes does not grow with the image.
 */
#include "png_encode.h"

#include <stdlib.h>
#include <string.h>

#include <isa-l/crc.h>
#include <isa-l/igzip_lib.h>

enum { BYTES_PER_PIXEL = 3 };

size_t png_filtered_size(uint32_t width, uint32_t height)
{
    return ((size_t)width * BYTES_PER_PIXEL + 1) * height;
}

/* The Paeth predictor: of left, up and up-left, the one closest to left + up - up-left. */
static uint8_t paeth(int a, int b, int c)
{
    int p = a + b - c;
    int pa = abs(p - a), pb = abs(p - b), pc = abs(p - c);
    if (pa <= pb && pa <= pc)
        return (uint8_t)a;
    return (uint8_t)(pb <= pc ? b : c);
}

/* The first row of an image, whose prior row is all zeros as the standard says: Up is None,
 * Paeth (left, up and up-left being left, 0 and 0) is Sub, and Average halves the left byte. */
static void filter_first_row(const uint8_t *row, size_t n, int type, uint8_t *out)
{
    const size_t bpp = BYTES_PER_PIXEL;
    memcpy(out, row, n < bpp ? n : bpp);
    for (size_t i = bpp; i < n; ++i) {
        int left = row[i - bpp];
        out[i] = (uint8_t)(type == PNG_FILTER_CHOICE_SUB || type == PNG_FILTER_CHOICE_PAETH
                               ? row[i] - left
                           : type == PNG_FILTER_CHOICE_AVERAGE ? row[i] - (left >> 1)
                                                               : row[i]);
    }
}

/* Filters one row of n bytes with filter type (0-4) into out; prior is the row above, NULL for
 * the first row. */
static void filter_row(const uint8_t *row, const uint8_t *prior, size_t n, int type, uint8_t *out)
{
    const size_t bpp = BYTES_PER_PIXEL;
    if (!prior) {
        filter_first_row(row, n, type, out);
        return;
    }
    switch (type) {
    case PNG_FILTER_CHOICE_NONE:
        memcpy(out, row, n);
        break;
    case PNG_FILTER_CHOICE_SUB:
        memcpy(out, row, bpp);
        for (size_t i = bpp; i < n; ++i)
            out[i] = (uint8_t)(row[i] - row[i - bpp]);
        break;
    case PNG_FILTER_CHOICE_UP:
        for (size_t i = 0; i < n; ++i)
            out[i] = (uint8_t)(row[i] - prior[i]);
        break;
    case PNG_FILTER_CHOICE_AVERAGE:
        for (size_t i = 0; i < bpp; ++i)
            out[i] = (uint8_t)(row[i] - (prior[i] >> 1));
        for (size_t i = bpp; i < n; ++i)
            out[i] = (uint8_t)(row[i] - ((row[i - bpp] + prior[i]) >> 1));
        break;
    default: /* Paeth */
        for (size_t i = 0; i < bpp; ++i)
            out[i] = (uint8_t)(row[i] - prior[i]); /* left and up-left are 0: Paeth is Up */
        for (size_t i = bpp; i < n; ++i)
            out[i] = (uint8_t)(row[i] - paeth(row[i - bpp], prior[i], prior[i - bpp]));
        break;
    }
}

/* The sum of the filtered bytes' magnitudes as signed values: the smaller, the better the
 * row usually deflates (the heuristic of the PNG specification's section 12.8). */
static uint64_t row_cost(const uint8_t *filtered, size_t n)
{
    uint64_t sum = 0;
    for (size_t i = 0; i < n; ++i)
        sum += (uint64_t)abs((int)(int8_t)filtered[i]);
    return sum;
}

bool png_filter_rows(const uint8_t *rgb, uint32_t width, uint32_t first_row, uint32_t rows,
                     png_filter_choice filter, uint8_t *out)
{
    size_t n = (size_t)width * BYTES_PER_PIXEL;
    uint8_t *trial = NULL;
    if (filter == PNG_FILTER_CHOICE_PER_ROW && !(trial = malloc(n)))
        return false;
    for (uint32_t i = 0; i < rows; ++i) {
        uint32_t y = first_row + i;
        const uint8_t *row = rgb + (size_t)y * n;
        const uint8_t *prior = y > 0 ? row - n : NULL;
        uint8_t *dest = out + (size_t)i * (n + 1);
        int type = (int)filter;
        if (filter == PNG_FILTER_CHOICE_PER_ROW) {
            uint64_t best = UINT64_MAX;
            for (int t = PNG_FILTER_CHOICE_NONE; t <= PNG_FILTER_CHOICE_PAETH; ++t) {
                filter_row(row, prior, n, t, trial);
                uint64_t cost = row_cost(trial, n);
                if (cost < best) {
                    best = cost;
                    type = t;
                }
            }
        }
        dest[0] = (uint8_t)type;
        filter_row(row, prior, n, type, dest + 1);
    }
    free(trial);
    return true;
}

/* ISA-L's igzip at level 1 with the Up filter: of the encoders measured on rendered frames the
 * fastest, with files smaller than stb_image_write's (docs/architecture.md, "Writing frames"). */
enum { DEFLATE_LEVEL = 1, DEFLATE_LEVEL_BUFFER = ISAL_DEF_LVL1_DEFAULT };

/* Rows filtered at a time: enough bytes to keep igzip's calls few, few enough to stay in cache. */
enum { ROWS_PER_BLOCK = 16 };

/* Compressed bytes per IDAT chunk: the stream is written as it comes, in chunks of this size. */
enum { IDAT_CHUNK_BYTES = 1 << 20 };

enum { CHUNK_HEAD = 8, CHUNK_CRC = 4, IHDR_SIZE = 13 };

static uint8_t *put_u32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)(v >> 24);
    p[1] = (uint8_t)(v >> 16);
    p[2] = (uint8_t)(v >> 8);
    p[3] = (uint8_t)v;
    return p + 4;
}

/* Hands one chunk to the sink: chunk holds CHUNK_HEAD free bytes, then data_size bytes of data,
 * then CHUNK_CRC free bytes, which are filled in here. */
static bool emit_chunk(uint8_t *chunk, const char type[4], size_t data_size, png_sink sink,
                       void *context)
{
    put_u32(chunk, (uint32_t)data_size);
    memcpy(chunk + 4, type, 4);
    /* PNG's CRC is zlib's and gzip's: ISO 3309, reflected, over the type and the data. */
    put_u32(chunk + CHUNK_HEAD + data_size, crc32_gzip_refl(0, chunk + 4, 4 + data_size));
    return sink(context, chunk, CHUNK_HEAD + data_size + CHUNK_CRC);
}

static bool emit_header(uint32_t width, uint32_t height, png_sink sink, void *context)
{
    static const uint8_t signature[8] = {137, 80, 78, 71, 13, 10, 26, 10};
    uint8_t ihdr[CHUNK_HEAD + IHDR_SIZE + CHUNK_CRC];
    uint8_t *p = put_u32(put_u32(ihdr + CHUNK_HEAD, width), height);
    /* bit depth 8, colour type 2 (RGB), deflate, the standard filters, no interlace */
    memcpy(p, (const uint8_t[]){8, 2, 0, 0, 0}, 5);
    return sink(context, signature, sizeof signature) &&
           emit_chunk(ihdr, "IHDR", IHDR_SIZE, sink, context);
}

/* The state of one encoding: igzip's stream, the block of filtered rows it reads, and the IDAT
 * chunk it writes into. */
typedef struct encoder {
    struct isal_zstream stream;
    uint8_t *level_buffer;
    uint8_t *block; /* ROWS_PER_BLOCK filtered rows */
    uint8_t *idat;  /* CHUNK_HEAD + IDAT_CHUNK_BYTES + CHUNK_CRC */
    png_sink sink;
    void *context;
} encoder;

/* igzip counts its input in 32 bits: a block of very wide rows goes in pieces of this size. */
static const size_t MAX_PIECE = (size_t)1 << 30;

/* Deflates size bytes of filtered rows (the last ones: end), emitting every IDAT chunk that
 * fills. */
static png_encode_result deflate_block(encoder *e, const uint8_t *data, size_t size, bool end)
{
    struct isal_zstream *s = &e->stream;
    for (;;) {
        if (s->avail_in == 0 && size > 0) {
            size_t piece = size < MAX_PIECE ? size : MAX_PIECE;
            s->next_in = (uint8_t *)data;
            s->avail_in = (uint32_t)piece;
            data += piece;
            size -= piece;
        }
        s->end_of_stream = end && size == 0;
        /* With level, buffer and flush set as igzip asks, nothing here fails; a failure would
         * be a bug, reported as such rather than as a corrupt file. */
        if (isal_deflate(s) != COMP_OK)
            return PNG_ENCODE_DEFLATE_FAILED;
        bool finished = s->end_of_stream && s->internal_state.state == ZSTATE_END;
        size_t held = IDAT_CHUNK_BYTES - s->avail_out;
        if (s->avail_out == 0 || (finished && held > 0)) {
            if (!emit_chunk(e->idat, "IDAT", held, e->sink, e->context))
                return PNG_ENCODE_SINK_FAILED;
            s->next_out = e->idat + CHUNK_HEAD;
            s->avail_out = IDAT_CHUNK_BYTES;
            continue; /* igzip may hold more output than fitted */
        }
        if (s->avail_in == 0 && size == 0 && (!end || finished))
            return PNG_ENCODE_OK;
    }
}

static png_encode_result encode_rows(encoder *e, const uint8_t *rgb, uint32_t width,
                                     uint32_t height)
{
    size_t row_bytes = (size_t)width * BYTES_PER_PIXEL + 1;
    png_encode_result result = PNG_ENCODE_OK;
    for (uint32_t y = 0; y < height && result == PNG_ENCODE_OK; y += ROWS_PER_BLOCK) {
        uint32_t rows = height - y < ROWS_PER_BLOCK ? height - y : ROWS_PER_BLOCK;
        png_filter_rows(rgb, width, y, rows, PNG_FILTER_CHOICE_UP, e->block);
        result = deflate_block(e, e->block, rows * row_bytes, y + rows == height);
    }
    return result;
}

png_encode_result png_encode_rgb8(const uint8_t *rgb, uint32_t width, uint32_t height,
                                  png_sink sink, void *context)
{
    encoder e = {.sink = sink, .context = context};
    e.level_buffer = malloc(DEFLATE_LEVEL_BUFFER);
    e.block = malloc(((size_t)width * BYTES_PER_PIXEL + 1) * ROWS_PER_BLOCK);
    e.idat = malloc(CHUNK_HEAD + IDAT_CHUNK_BYTES + CHUNK_CRC);
    png_encode_result result = PNG_ENCODE_NO_MEMORY;
    if (e.level_buffer && e.block && e.idat) {
        isal_deflate_init(&e.stream);
        e.stream.level = DEFLATE_LEVEL;
        e.stream.level_buf = e.level_buffer;
        e.stream.level_buf_size = DEFLATE_LEVEL_BUFFER;
        e.stream.gzip_flag = IGZIP_ZLIB; /* PNG's IDAT is a zlib stream */
        e.stream.flush = NO_FLUSH;
        e.stream.next_out = e.idat + CHUNK_HEAD;
        e.stream.avail_out = IDAT_CHUNK_BYTES;
        result = !emit_header(width, height, sink, context) ? PNG_ENCODE_SINK_FAILED
                                                            : encode_rows(&e, rgb, width, height);
    }
    if (result == PNG_ENCODE_OK) {
        uint8_t iend[CHUNK_HEAD + CHUNK_CRC];
        if (!emit_chunk(iend, "IEND", 0, sink, context))
            result = PNG_ENCODE_SINK_FAILED;
    }
    free(e.idat);
    free(e.block);
    free(e.level_buffer);
    return result;
}
