/*
 * radiance_hdr.h: Radiance HDR images (.hdr, RGBE), read whole from memory. Pure CPU.
 *
 * Our own reader rather than stb_image's, for two reasons a user meets: stb_image reads past the
 * end of a file as zeros, so a file cut short decoded as flat colour where its pixels were
 * missing; and it sizes its float output in an int, so maps larger than about 13377 x 13377 (of
 * the 16384 x 16384 the docs allow) were refused as "too large". This reader checks that the
 * pixel data covers the declared size before allocating anything, and says by how many bytes it
 * falls short. Pixels decode to the floats stb_image gives (c * 2^(e - 136), 0 where e is 0), so
 * maps that loaded before load bit for bit the same.
 *
 * What is read: a first line "#?<program>" (Radiance writes "#?RADIANCE"), header lines up to an
 * empty one (FORMAT=32-bit_rle_rgbe, or none; EXPOSURE and the rest are ignored, as stb_image
 * ignores them), the resolution line "-Y HEIGHT +X WIDTH" (top row first, the orientation every
 * tool writes), then per scanline either the run-length encoding of Radiance's newer format
 * (2, 2, width's two bytes, then each of R, G, B, E encoded in runs) or width flat 4-byte pixels.
 */
#ifndef VKRT_RADIANCE_HDR_H
#define VKRT_RADIANCE_HDR_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* A header read by vkrt_radiance_header: the size it declares and where the pixels start. */
typedef struct vkrt_radiance_info {
    uint32_t width, height;
    size_t data_offset;
} vkrt_radiance_info;

/* Whether bytes start as a Radiance file does ("#?"). */
bool vkrt_radiance_is(const unsigned char *bytes, size_t size);

/* Reads the header. False with the reason in why (a sentence without the file's name) for a
 * header without its closing empty line, another FORMAT (32-bit_rle_xyze), a resolution line
 * that is not "-Y H +X W", or a size of 0 or above 2^31. */
bool vkrt_radiance_header(const unsigned char *bytes, size_t size, vkrt_radiance_info *info,
                          char *why, size_t why_size);

/* Whether the pixel data after the header covers every scanline, walking the run lengths without
 * decoding. False with why, e.g. "the Radiance HDR file is cut short: it has 69 bytes, but its
 * pixels end in scanline 1 of 16384 (a 16384x16384 image needs at least 2097221)", or for a
 * run that overflows its scanline. Allocates nothing. */
bool vkrt_radiance_check(const unsigned char *bytes, size_t size, const vkrt_radiance_info *info,
                         char *why, size_t why_size);

/* Decodes a file that vkrt_radiance_check passed into out: width * height pixels of channels
 * floats (3: RGB; 4: RGB and alpha 1), the top row first. False only when the scanline buffer
 * (width * 4 bytes) cannot be allocated. */
bool vkrt_radiance_decode(const unsigned char *bytes, size_t size, const vkrt_radiance_info *info,
                          unsigned channels, float *out);

#endif
