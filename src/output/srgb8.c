/*
 * srgb8.c: the sRGB encoding of PNG output, exact and through a table (srgb8.h).
 */
#include "srgb8.h"

#include <math.h>
#include <string.h>

/* Exact sRGB OETF (IEC 61966-2-1), on a value already clamped to [0, 1]. */
static double srgb_curve(double linear)
{
    if (linear < 0.0031308)
        return 12.92 * linear;
    return 1.055 * pow(linear, 1.0 / 2.4) - 0.055;
}

/* NaN maps to black so a single bad sample cannot poison a frame (or reach the cast, where
 * converting NaN to an integer would be undefined behaviour). */
uint8_t srgb8_encode(float linear)
{
    if (isnan(linear))
        return 0;
    double clamped = linear < 0.0f ? 0.0 : linear > 1.0f ? 1.0 : (double)linear;
    return (uint8_t)(srgb_curve(clamped) * 255.0 + 0.5);
}

static float float_of_bits(uint32_t bits)
{
    float f;
    memcpy(&f, &bits, sizeof f);
    return f;
}

/* The bits of 1.0f: every float from 0 to 1 has bits below it, in the order of its value. */
static const uint32_t ONE_BITS = 0x3f800000u;

/* The smallest float in [0, 1] whose code value is at least code (1 to 255), by bisection over
 * the floats' bits, which order non-negative floats as their values do. */
static float code_start(int code)
{
    uint32_t lo = 0, hi = ONE_BITS; /* srgb8_encode(1) = 255 >= code */
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (srgb8_encode(float_of_bits(mid)) >= code)
            hi = mid;
        else
            lo = mid + 1;
    }
    return float_of_bits(lo);
}

void srgb8_table_init(srgb8_table *table)
{
    float start[257];
    start[0] = 0.0f;
    for (int code = 1; code <= 255; ++code)
        start[code] = code_start(code);
    start[256] = INFINITY;
    int code = 0;
    for (uint32_t s = 0; s < SRGB8_SLICES; ++s) {
        float first = float_of_bits(s << SRGB8_SLICE_SHIFT);
        while (code < 255 && start[code + 1] <= first)
            ++code;
        table->code[s] = (uint8_t)code;
        table->next[s] = start[code + 1];
    }
}

void srgb8_encode_array(const srgb8_table *table, const float *linear, float scale, size_t count,
                        uint8_t *codes)
{
    for (size_t i = 0; i < count; ++i) {
        float x = linear[i] * scale;
        uint32_t bits;
        memcpy(&bits, &x, sizeof bits);
        if (bits < ONE_BITS) {
            uint32_t s = bits >> SRGB8_SLICE_SHIFT;
            codes[i] = (uint8_t)(table->code[s] + (x >= table->next[s]));
        } else {
            /* 1 to +infinity: white; NaN (positive bits above infinity's) and everything with
             * the sign bit (negative numbers, -0, negative NaN): black. */
            codes[i] = bits <= 0x7f800000u ? 255 : 0;
        }
    }
}
