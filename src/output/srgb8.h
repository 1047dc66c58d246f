/*
 * srgb8.h: linear radiance to 8-bit sRGB code values, as PNG output stores them.
 *
 * srgb8_encode is the definition: clamp to [0, 1], the exact sRGB curve in double precision
 * (IEC 61966-2-1), round to nearest; NaN is black. It costs a pow() per value, more than
 * compressing the frame, so frames go through a table: the float where each code value begins,
 * found with srgb8_encode itself, and per slice of the float's bits the code at the slice's
 * start. The table's result equals srgb8_encode's for every float (all 2^32 bit patterns were
 * compared).
 */
#ifndef VKRT_SRGB8_H
#define VKRT_SRGB8_H

#include <stddef.h>
#include <stdint.h>

/* One float's code value, the slow and obvious way. */
uint8_t srgb8_encode(float linear);

/* A float's bits shifted right by this many select its slice: slices 2^-7 of an octave wide,
 * in which the curve rises by less than one code value (at most 0.88, near 1). */
enum { SRGB8_SLICE_SHIFT = 16, SRGB8_SLICES = (0x3f800000 >> SRGB8_SLICE_SHIFT) + 1 };

typedef struct srgb8_table {
    uint8_t code[SRGB8_SLICES]; /* the code value at the slice's first float */
    float next[SRGB8_SLICES];   /* where the slice's values reach code + 1 (above the slice if
                                   they never do) */
} srgb8_table;

/* Fills the table (about 8,000 calls of srgb8_encode: under a millisecond). */
void srgb8_table_init(srgb8_table *table);

/* count linear values times scale to code values, through the table. */
void srgb8_encode_array(const srgb8_table *table, const float *linear, float scale, size_t count,
                        uint8_t *codes);

#endif
