/*
 * texture_levels.h: the mipmap levels of a texture (texture.c's helper), made when the image is
 * loaded, and the half floats HDR texels are kept in. Pure CPU.
 *
 * Level k of a w x h image is max(1, w >> k) x max(1, h >> k) texels, stored right after level
 * k - 1 in the image's texel format (VKRT_TEXTURE_LEVELS in glsl/shared.h), down to 1 x 1: an
 * image takes about a third more words with its levels. Each level is the box filter of the one
 * before: a texel is the mean of the area it covers there, counted exactly where a size is odd (a
 * level of 5 texels to 2 weighs 1, 1, 0.5 and 0.5, 1, 1), so every level keeps the mean of the
 * image. The filtering is done on linear values: sRGB-encoded colour (VKRT_TEXTURE_SRGB) is
 * decoded first and encoded again after, since the mean of encoded values is too dark (the mean
 * of sRGB 0 and 255 is linear 0.5, sRGB 188, not 128).
 */
#ifndef VKRT_TEXTURE_LEVELS_H
#define VKRT_TEXTURE_LEVELS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* The levels after the image a w x h image gets: floor(log2(max(w, h))); 0 for 1 x 1. */
uint32_t vkrt_texture_level_count(uint32_t w, uint32_t h);

/* Level `level` (0: the image) of a w x h image of words_per_texel words a texel (1: RGBA8, 2:
 * half floats): the words before it, from the image's first, and its size in *lw, *lh. With
 * level = vkrt_texture_level_count(w, h) + 1 it gives the words of the image with all its
 * levels. */
size_t vkrt_texture_level_at(uint32_t w, uint32_t h, uint32_t words_per_texel, uint32_t level,
                             uint32_t *lw, uint32_t *lh);

/* The words of a w x h image with all its levels. */
size_t vkrt_texture_words_with_levels(uint32_t w, uint32_t h, uint32_t words_per_texel);

/* Fills the levels after the w x h image at texels (flags: its VKRT_TEXTURE_SRGB and
 * VKRT_TEXTURE_HALF; the array has room for vkrt_texture_words_with_levels), each the box filter
 * of the one before, in linear values, rounded to the nearest 8-bit code or half float. Needs
 * memory for one row of floats only; false when even that is not to be had (the levels are then
 * not made). */
bool vkrt_texture_build_levels(uint32_t *texels, uint32_t w, uint32_t h, uint32_t flags);

/* IEEE half floats, rounding to nearest even. Values beyond the half range clamp to its largest
 * finite value rather than become infinity, so one bright pixel of an HDR image cannot turn a
 * filtered sample into inf; NaN becomes 0. */
uint16_t vkrt_half_from_float(float f);
float vkrt_half_to_float(uint32_t h);

#endif
