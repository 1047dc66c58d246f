/*
 * texture_levels.c: mipmap levels made at load (texture_levels.h), and the half floats HDR texels
 * are kept in.
 *
 * Each level is made from the one before, a row at a time: the one or more source rows a
 * destination row covers are decoded to linear floats, weighed by the share of them it covers,
 * and summed into one row of floats, which is then encoded. Re-encoding each level before the
 * next is made from it rounds once per level (half an 8-bit step), which no level shows.
 */
#include "texture_levels.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "../../glsl/shared.h"

uint16_t vkrt_half_from_float(float f)
{
    if (f != f)
        return 0;
    f = fminf(fmaxf(f, -65504.0f), 65504.0f);
    uint32_t x;
    memcpy(&x, &f, sizeof x);
    uint32_t sign = (x >> 16) & 0x8000u;
    uint32_t magnitude = x & 0x7FFFFFFFu;
    if (magnitude < 0x38800000u) { /* below 2^-14, the smallest normal half: subnormal or zero */
        float a;
        memcpy(&a, &magnitude, sizeof a);
        return (uint16_t)(sign |
                          (uint32_t)lrintf(a * 16777216.0f)); /* units of 2^-24, exact scale */
    }
    uint32_t h =
        (magnitude - 0x38000000u) >> 13; /* exponent rebiased 127 -> 15, 10 mantissa bits */
    uint32_t rest = magnitude & 0x1FFFu;
    if (rest > 0x1000u || (rest == 0x1000u && (h & 1u)))
        h++;
    return (uint16_t)(sign | h);
}

float vkrt_half_to_float(uint32_t h)
{
    uint32_t exponent = (h >> 10) & 0x1Fu, mantissa = h & 0x3FFu;
    float f;
    if (exponent == 0)
        f = ldexpf((float)mantissa, -24);
    else if (exponent == 31)
        f = mantissa ? NAN : INFINITY;
    else
        f = ldexpf((float)(mantissa | 0x400u), (int)exponent - 25);
    return (h & 0x8000u) ? -f : f;
}

uint32_t vkrt_texture_level_count(uint32_t w, uint32_t h)
{
    uint32_t n = 0;
    for (uint32_t m = w > h ? w : h; m > 1; m >>= 1)
        n++;
    return n;
}

size_t vkrt_texture_level_at(uint32_t w, uint32_t h, uint32_t words_per_texel, uint32_t level,
                             uint32_t *lw, uint32_t *lh)
{
    size_t at = 0;
    for (uint32_t k = 0; k < level; k++) {
        at += (size_t)w * h * words_per_texel;
        w = w > 1 ? w >> 1 : 1;
        h = h > 1 ? h >> 1 : 1;
    }
    *lw = w;
    *lh = h;
    return at;
}

size_t vkrt_texture_words_with_levels(uint32_t w, uint32_t h, uint32_t words_per_texel)
{
    uint32_t lw, lh;
    return vkrt_texture_level_at(w, h, words_per_texel, vkrt_texture_level_count(w, h) + 1, &lw,
                                 &lh);
}

/* The exact sRGB curves (IEC 61966-2-1), as the kernels decode. */
static float srgb_to_linear(float c)
{
    return c <= 0.04045f ? c / 12.92f : powf((c + 0.055f) / 1.055f, 2.4f);
}

static float linear_to_srgb(float c)
{
    return c <= 0.0031308f ? c * 12.92f : 1.055f * powf(c, 1.0f / 2.4f) - 0.055f;
}

/* The source texels destination texel x of a level n wide covers in one of m (m = n or
 * n = max(1, m / 2)): the span [x m / n, (x + 1) m / n), at most 3 texels, each weighed by the
 * share of the span it covers. */
typedef struct box_tap {
    uint32_t first, count;
    float weight[3];
} box_tap;

static box_tap box_tap_of(uint32_t x, uint32_t m, uint32_t n)
{
    /* In units of 1 / n of a source texel: the span is [x m, (x + 1) m), texel i is
     * [i n, (i + 1) n). */
    uint64_t lo = (uint64_t)x * m, hi = lo + m;
    box_tap t = {.first = (uint32_t)(lo / n), .count = 0};
    for (uint64_t i = t.first; i * n < hi && t.count < 3; i++) {
        uint64_t a = lo > i * n ? lo : i * n, b = hi < (i + 1) * n ? hi : (i + 1) * n;
        t.weight[t.count++] = (float)(b - a) / (float)m;
    }
    return t;
}

/* Texel i of a level as linear RGBA. */
static void decode_texel(const uint32_t *level, size_t i, uint32_t flags, const float *srgb,
                         float rgba[4])
{
    if (flags & VKRT_TEXTURE_HALF) {
        uint32_t a = level[2 * i], b = level[2 * i + 1];
        rgba[0] = vkrt_half_to_float(a & 0xFFFFu);
        rgba[1] = vkrt_half_to_float(a >> 16);
        rgba[2] = vkrt_half_to_float(b & 0xFFFFu);
        rgba[3] = vkrt_half_to_float(b >> 16);
        return;
    }
    uint32_t t = level[i];
    for (int k = 0; k < 4; k++) {
        uint32_t code = (t >> (8 * k)) & 0xFFu;
        rgba[k] = k < 3 && (flags & VKRT_TEXTURE_SRGB) ? srgb[code] : (float)code / 255.0f;
    }
}

static uint32_t byte_of(float c)
{
    c = fminf(fmaxf(c, 0.0f), 1.0f);
    return (uint32_t)lrintf(c * 255.0f);
}

static void encode_texel(uint32_t *level, size_t i, uint32_t flags, const float rgba[4])
{
    if (flags & VKRT_TEXTURE_HALF) {
        level[2 * i] = vkrt_half_from_float(rgba[0]) | (uint32_t)vkrt_half_from_float(rgba[1]) << 16;
        level[2 * i + 1] =
            vkrt_half_from_float(rgba[2]) | (uint32_t)vkrt_half_from_float(rgba[3]) << 16;
        return;
    }
    uint32_t t = 0;
    for (int k = 0; k < 4; k++) {
        float c = rgba[k];
        if (k < 3 && (flags & VKRT_TEXTURE_SRGB))
            c = linear_to_srgb(fminf(fmaxf(c, 0.0f), 1.0f));
        t |= byte_of(c) << (8 * k);
    }
    level[i] = t;
}

/* Level dst (n_w x n_h) as the box filter of src (m_w x m_h), a row of floats at a time. */
static void filter_level(const uint32_t *src, uint32_t m_w, uint32_t m_h, uint32_t *dst,
                         uint32_t n_w, uint32_t n_h, uint32_t flags, const float *srgb,
                         float *row)
{
    for (uint32_t y = 0; y < n_h; y++) {
        box_tap ty = box_tap_of(y, m_h, n_h);
        memset(row, 0, (size_t)n_w * 4 * sizeof *row);
        for (uint32_t r = 0; r < ty.count; r++) {
            size_t source_row = (size_t)(ty.first + r) * m_w;
            for (uint32_t x = 0; x < n_w; x++) {
                box_tap tx = box_tap_of(x, m_w, n_w);
                for (uint32_t c = 0; c < tx.count; c++) {
                    float t[4];
                    decode_texel(src, source_row + tx.first + c, flags, srgb, t);
                    float weight = ty.weight[r] * tx.weight[c];
                    for (int k = 0; k < 4; k++)
                        row[4 * x + k] += weight * t[k];
                }
            }
        }
        for (uint32_t x = 0; x < n_w; x++)
            encode_texel(dst, (size_t)y * n_w + x, flags, &row[4 * x]);
    }
}

bool vkrt_texture_build_levels(uint32_t *texels, uint32_t w, uint32_t h, uint32_t flags)
{
    float srgb[256];
    for (int i = 0; i < 256; i++)
        srgb[i] = srgb_to_linear((float)i / 255.0f);
    uint32_t words = (flags & VKRT_TEXTURE_HALF) ? 2 : 1;
    uint32_t levels = vkrt_texture_level_count(w, h);
    float *row = malloc((size_t)(w > 1 ? w / 2 : 1) * 4 * sizeof *row);
    if (!row)
        return false;
    uint32_t *src = texels;
    for (uint32_t k = 1; k <= levels; k++) {
        uint32_t n_w = w > 1 ? w >> 1 : 1, n_h = h > 1 ? h >> 1 : 1;
        uint32_t *dst = src + (size_t)w * h * words;
        filter_level(src, w, h, dst, n_w, n_h, flags, srgb, row);
        src = dst;
        w = n_w;
        h = n_h;
    }
    free(row);
    return true;
}
