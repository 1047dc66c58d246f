/*
 * png_encode.h: 8-bit RGB pixels to the bytes of a PNG file, in memory (the file is
 * image_write.h's business). PNG's filters are applied here; the filtered rows are deflated by
 * ISA-L's igzip, whose level 1 with the Up filter measured fastest of stb_image_write, zlib,
 * libdeflate, ISA-L, libspng and libpng, its files smaller than stb's (docs/architecture.md,
 * "Writing frames").
 */
#ifndef VKRT_PNG_ENCODE_H
#define VKRT_PNG_ENCODE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* The filter put before each row (PNG's filter types 0-4), or per_row: for each row the one
 * whose bytes have the smallest sum of magnitudes, as stb_image_write and libpng choose. */
typedef enum png_filter_choice {
    PNG_FILTER_CHOICE_NONE = 0,
    PNG_FILTER_CHOICE_SUB,
    PNG_FILTER_CHOICE_UP,
    PNG_FILTER_CHOICE_AVERAGE,
    PNG_FILTER_CHOICE_PAETH,
    PNG_FILTER_CHOICE_PER_ROW,
} png_filter_choice;

/* Bytes of the filtered image: each row's filter byte and its width * 3 bytes. */
size_t png_filtered_size(uint32_t width, uint32_t height);

/* Filters rows first_row to first_row + rows - 1 of rgb (width pixels a row, 3 bytes each, the
 * top row first; the row above first_row is read too) into out (png_filtered_size(width, rows)
 * bytes), each row led by its filter type. False only when per_row finds no memory. */
bool png_filter_rows(const uint8_t *rgb, uint32_t width, uint32_t first_row, uint32_t rows,
                     png_filter_choice filter, uint8_t *out);

/* Where an encoding's bytes go, in order: true if they went, false to stop the encoding. */
typedef bool (*png_sink)(void *context, const void *data, size_t size);

typedef enum png_encode_result {
    PNG_ENCODE_OK = 0,
    PNG_ENCODE_NO_MEMORY,
    PNG_ENCODE_SINK_FAILED,    /* the sink said false (it knows why) */
    PNG_ENCODE_DEFLATE_FAILED, /* igzip refused its arguments: a bug */
} png_encode_result;

/* Encodes rgb (width x height pixels, 3 bytes each, the top row first; both sides 1 to
 * 2^31 - 1, PNG's limits) as a PNG file: 8-bit RGB, not interlaced, every row filtered with Up,
 * deflated by ISA-L's igzip at level 1 into IDAT chunks of at most 1 MiB, each handed to sink as
 * it fills. Memory: a few MiB, whatever the image's size. */
png_encode_result png_encode_rgb8(const uint8_t *rgb, uint32_t width, uint32_t height,
                                  png_sink sink, void *context);

#endif
