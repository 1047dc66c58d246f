/*
 * image_write.h: writing rendered frames to files.
 *
 * Pixels arrive as linear radiance, 3 floats (RGB) per pixel, the top row first, and pass through
 * the finish stage (finish.h) for the file's format, which comes from its extension: ".png" is
 * 8-bit sRGB (radiance times 2^exposure, through the tone curve or clamped, then the sRGB curve),
 * ".exr" is 32-bit float linear RGB, written with OpenEXR's C API (OpenEXRCore); with a denoiser
 * in the finish (--denoise) its R, G, B are the denoised radiance and the rendered one is kept
 * beside them as layer "noisy" (channels noisy.R, noisy.G, noisy.B). Every file is written to a
 * temporary name beside the target and renamed when complete, so a failed run never leaves a
 * truncated image.
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

/* A finished frame as the writers get it: the beauty, linear RGB radiance (3 floats a pixel, the
 * top row first), and its AOVs (--aov), each NULL when not asked for, as
 * vkrt_renderer_read_aovs (render/renderer.h) gives them, anti-aliased as the beauty is:
 *   albedo    3 floats a pixel in [0, 1], at each sample's first non-delta hit
 *   normal    3 floats a pixel in [-1, 1], the world-space shading normal there
 *   depth     1 float a pixel, the camera ray's hit distance (+inf where nothing was hit)
 *   position  3 floats a pixel, its world-space hit point (0 where nothing was hit)
 * What a pass on the finished frame (a denoiser's albedo and normal guides) reads. */
typedef struct vkrt_frame_image {
    uint32_t width, height;
    const float *rgb;
    const float *albedo, *normal, *depth, *position;
    /* The denoiser's guides (finish.h) where the albedo and normal are not written themselves
     * (--denoise without --aov): handed to the finish stage, never written. */
    const float *guide_albedo, *guide_normal;
} vkrt_frame_image;

/* Writes frame to path as vkrt_image_write_frame writes its rgb, with its AOVs:
 *   .exr: one scanline part whose channels are the beauty's R, G, B and a layer per AOV, named as
 *         Nuke reads layers (layer.channel) and Blender passes: albedo.R/G/B, normal.X/Y/Z,
 *         depth.Z, position.X/Y/Z (float, linear; the finish stage touches the beauty only);
 *   .png: a file per AOV beside it, path's extension replaced: NAME.albedo.png (sRGB, as the
 *         beauty without its exposure), NAME.normal.png (0.5 n + 0.5 in 8 bits, no curve),
 *         NAME.depth.exr and NAME.position.exr (float, channels named as in the EXR: 8 bits
 *         hold no distances). They are written before the beauty, each complete or not at all,
 *         so a complete beauty (what --resume checks) has its AOVs complete beside it.
 * False with err naming the file that failed; then the beauty is left as vkrt_image_write_frame
 * leaves it on failure. */
bool vkrt_image_write_layers(const char *path, const vkrt_frame_image *frame,
                             const vkrt_finish_desc *finish, vkrt_error *err);

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
