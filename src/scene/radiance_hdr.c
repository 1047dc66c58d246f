/*
 * radiance_hdr.c: Radiance HDR images read from memory (radiance_hdr.h).
 *
 * The format is Greg Ward's (Radiance's color.c, and "Real Pixels", Graphics Gems II): a text
 * header, then scanlines of RGBE pixels, each channel a byte of mantissa and E a shared exponent.
 * A scanline of the newer format starts with the bytes 2, 2 and its width (high bit clear), then
 * holds each of the four components in turn as runs: a count above 128 repeats the next byte
 * count - 128 times, a count of 1 to 128 is followed by that many bytes. Widths below 8 or above
 * 32767 cannot be encoded so and are always flat, as are scanlines without the marker.
 */
#include "radiance_hdr.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Run-length encoding needs a width the marker's 15 bits hold, and at least 8 (Radiance's
 * MINELEN); other widths are written flat. */
#define RLE_MIN_WIDTH 8u
#define RLE_MAX_WIDTH 32767u

/* The longest header line looked at; longer ones are skipped (they are comments to us). */
#define HEADER_LINE_BYTES 1024

bool vkrt_radiance_is(const unsigned char *bytes, size_t size)
{
    return size >= 2 && bytes[0] == '#' && bytes[1] == '?';
}

/* The next line from *at (without its '\n' or a '\r' before it) into line, cut to line_size - 1
 * bytes; false at the end of the bytes without a '\n'. */
static bool next_line(const unsigned char *bytes, size_t size, size_t *at, char *line,
                      size_t line_size)
{
    const unsigned char *nl = memchr(bytes + *at, '\n', size - *at);
    if (!nl)
        return false;
    size_t len = (size_t)(nl - (bytes + *at));
    size_t kept = len < line_size - 1 ? len : line_size - 1;
    memcpy(line, bytes + *at, kept);
    line[kept] = '\0';
    if (kept > 0 && line[kept - 1] == '\r')
        line[kept - 1] = '\0';
    *at += len + 1;
    return true;
}

/* Reads "<sign><axis> <number>" at *s: a positive number below 2^31. */
static bool read_axis(const char **s, const char *expected, uint32_t *out)
{
    while (**s == ' ' || **s == '\t')
        ++*s;
    if (strncmp(*s, expected, 2) != 0 || ((*s)[2] != ' ' && (*s)[2] != '\t'))
        return false;
    *s += 3;
    while (**s == ' ' || **s == '\t')
        ++*s;
    if (**s < '0' || **s > '9')
        return false;
    char *end;
    errno = 0;
    long long v = strtoll(*s, &end, 10);
    if (errno || v <= 0 || v > INT_MAX)
        return false;
    *s = end;
    *out = (uint32_t)v;
    return true;
}

bool vkrt_radiance_header(const unsigned char *bytes, size_t size, vkrt_radiance_info *info,
                          char *why, size_t why_size)
{
    memset(info, 0, sizeof *info);
    char line[HEADER_LINE_BYTES];
    size_t at = 0;
    if (!vkrt_radiance_is(bytes, size) || !next_line(bytes, size, &at, line, sizeof line)) {
        snprintf(why, why_size, "not a Radiance HDR file (no \"#?RADIANCE\" line first)");
        return false;
    }
    for (;;) {
        if (!next_line(bytes, size, &at, line, sizeof line)) {
            snprintf(why, why_size,
                     "the Radiance HDR header is cut short: the file ends at byte %zu, before "
                     "the empty line that closes the header",
                     size);
            return false;
        }
        if (!line[0])
            break;
        if (strncmp(line, "FORMAT=", 7) == 0 && strcmp(line + 7, "32-bit_rle_rgbe") != 0) {
            snprintf(why, why_size, "the Radiance HDR format is %.60s; only 32-bit_rle_rgbe is read",
                     line + 7);
            return false;
        }
    }
    bool have_line = next_line(bytes, size, &at, line, sizeof line);
    const char *s = line;
    uint32_t w = 0, h = 0;
    if (!have_line || !read_axis(&s, "-Y", &h) || !read_axis(&s, "+X", &w) ||
        s[strspn(s, " \t")] != '\0') {
        snprintf(why, why_size,
                 "the Radiance HDR resolution line is %s%.60s%s; vkrt reads \"-Y HEIGHT +X "
                 "WIDTH\" (top row first) with sizes from 1 to 2147483647",
                 have_line ? "\"" : "", have_line ? line : "missing", have_line ? "\"" : "");
        return false;
    }
    *info = (vkrt_radiance_info){.width = w, .height = h, .data_offset = at};
    return true;
}

/* Whether scanlines of this width may be run-length encoded. */
static bool may_be_encoded(uint32_t width)
{
    return width >= RLE_MIN_WIDTH && width <= RLE_MAX_WIDTH;
}

/* Whether the scanline at *at starts with the encoded format's marker for width. */
static bool is_encoded(const unsigned char *bytes, size_t size, size_t at, uint32_t width)
{
    return may_be_encoded(width) && size - at >= 4 && bytes[at] == 2 && bytes[at + 1] == 2 &&
           !(bytes[at + 2] & 0x80) && ((uint32_t)bytes[at + 2] << 8 | bytes[at + 3]) == width;
}

/* What a walk over the scanlines found: the first scanline that is not whole (height when all
 * are), and whether it failed by a run past its end rather than by the file ending. */
typedef struct walk_end {
    uint32_t line;
    bool overflow;
} walk_end;

static void put_pixel(const unsigned char rgbe[4], unsigned channels, float *out)
{
    /* stb_image's conversion (no half-step added to the mantissa, as Radiance's own colr_color
     * adds), so that maps decode as they did through it. */
    if (rgbe[3]) {
        float scale = (float)ldexp(1.0f, rgbe[3] - (int)(128 + 8));
        out[0] = rgbe[0] * scale;
        out[1] = rgbe[1] * scale;
        out[2] = rgbe[2] * scale;
    } else {
        out[0] = out[1] = out[2] = 0.0f;
    }
    if (channels == 4)
        out[3] = 1.0f;
}

/* Walks the scanlines after the header; with out (and scanline, width * 4 bytes, for the encoded
 * components), decodes them too. */
static walk_end walk(const unsigned char *bytes, size_t size, const vkrt_radiance_info *info,
                     unsigned channels, float *out, unsigned char *scanline)
{
    size_t at = info->data_offset;
    uint32_t w = info->width;
    for (uint32_t y = 0; y < info->height; y++) {
        float *row = out ? out + (size_t)y * w * channels : NULL;
        if (!is_encoded(bytes, size, at, w)) {
            if (size - at < (size_t)w * 4)
                return (walk_end){y, false};
            for (uint32_t x = 0; row && x < w; x++)
                put_pixel(bytes + at + 4 * (size_t)x, channels, row + (size_t)x * channels);
            at += (size_t)w * 4;
            continue;
        }
        at += 4;
        for (unsigned k = 0; k < 4; k++) {
            for (uint32_t x = 0; x < w;) {
                if (at >= size)
                    return (walk_end){y, false};
                unsigned count = bytes[at++];
                bool run = count > 128;
                if (run)
                    count -= 128;
                if (count == 0 || count > w - x)
                    return (walk_end){y, true};
                size_t need = run ? 1 : count;
                if (size - at < need)
                    return (walk_end){y, false};
                for (unsigned i = 0; scanline && i < count; i++)
                    scanline[4 * (size_t)(x + i) + k] = bytes[at + (run ? 0 : i)];
                at += need;
                x += count;
            }
        }
        for (uint32_t x = 0; row && x < w; x++)
            put_pixel(scanline + 4 * (size_t)x, channels, row + (size_t)x * channels);
    }
    return (walk_end){info->height, false};
}

bool vkrt_radiance_check(const unsigned char *bytes, size_t size, const vkrt_radiance_info *info,
                         char *why, size_t why_size)
{
    walk_end end = walk(bytes, size, info, 3, NULL, NULL);
    if (end.line == info->height)
        return true;
    if (end.overflow) {
        snprintf(why, why_size,
                 "the Radiance HDR pixels are damaged: a run in scanline %u of %u goes past the "
                 "scanline's %u pixels",
                 end.line + 1, info->height, info->width);
        return false;
    }
    /* The fewest bytes a scanline can take: flat, or encoded in runs of 127 (2 bytes a run). */
    uint64_t w = info->width;
    uint64_t flat = 4 * w, encoded = 4 + 4 * 2 * ((w + 126) / 127);
    uint64_t least = may_be_encoded(info->width) && encoded < flat ? encoded : flat;
    snprintf(why, why_size,
             "the Radiance HDR file is cut short: it has %zu bytes, but its pixels end in "
             "scanline %u of %u (a %ux%u image needs at least %llu)",
             size, end.line + 1, info->height, info->width, info->height,
             (unsigned long long)(info->data_offset + least * info->height));
    return false;
}

bool vkrt_radiance_decode(const unsigned char *bytes, size_t size, const vkrt_radiance_info *info,
                          unsigned channels, float *out)
{
    unsigned char *scanline = malloc((size_t)info->width * 4);
    if (!scanline)
        return false;
    walk(bytes, size, info, channels, out, scanline);
    free(scanline);
    return true;
}
