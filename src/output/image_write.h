/*
 * image_write.h: writing rendered frames to files.
 *
 * Pixels arrive as linear radiance, 3 floats (RGB) per pixel, the top row first, and pass through
 * the finish stage (finish.h) for the file's format, which comes from its extension: ".png" is
 * 8-bit sRGB (radiance times 2^exposure, through the tone curve or clamped, then the sRGB curve),
 * ".exr" is 32-bit float linear RGB, written with OpenEXR's C API (OpenEXRCore). Every file is
 * written to a temporary name beside the target and renamed when complete, so a failed run never
 * leaves a truncated image.
 */
#ifndef VKRT_IMAGE_WRITE_H
#define VKRT_IMAGE_WRITE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "../error.h"
#include "finish.h"

typedef enum vkrt_image_format {
    VKRT_IMAGE_UNKNOWN = 0,
    VKRT_IMAGE_PNG,
    VKRT_IMAGE_EXR,
} vkrt_image_format;

/* The format for a path's extension (case-insensitive), or VKRT_IMAGE_UNKNOWN. */
vkrt_image_format vkrt_image_format_of(const char *path);

/* Writes width x height pixels of rgb to path, finished as finish describes for the path's
 * format. Returns false with err naming the path on any failure; then no file is left at path (an
 * existing file there is left untouched) and no temporary file remains. */
bool vkrt_image_write_frame(const char *path, uint32_t width, uint32_t height, const float *rgb,
                            const vkrt_finish_desc *finish, vkrt_error *err);

/* vkrt_image_write_frame with a finish of exposure alone (stops; it scales the PNG only). */
bool vkrt_image_write(const char *path, uint32_t width, uint32_t height, const float *rgb,
                      float exposure, vkrt_error *err);

/* Writes width x height pixels already encoded as 8-bit sRGB (rgb: 3 bytes per pixel, the top
 * row first) to path, a .png, the same way: a temporary file renamed when complete. For what the
 * viewer's window shows. */
bool vkrt_image_write_png8(const char *path, uint32_t width, uint32_t height, const uint8_t *rgb,
                           vkrt_error *err);

/* Expands a frame pattern: the first printf-style integer conversion in pattern ("%d", "%04d")
 * receives frame; "%%" is a literal percent. A pattern without a conversion is copied unchanged.
 * Any other conversion, or a result longer than out_size, is an error. */
bool vkrt_frame_path(char *out, size_t out_size, const char *pattern, uint32_t frame,
                     vkrt_error *err);

/* True if pattern holds an integer conversion that numbers frames. */
bool vkrt_frame_pattern_has_number(const char *pattern);

#endif
