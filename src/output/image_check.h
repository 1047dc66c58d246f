/*
 * image_check.h: whether an image file already on disk is a complete frame, for `--resume`.
 */
#ifndef VKRT_IMAGE_CHECK_H
#define VKRT_IMAGE_CHECK_H

#include <stdbool.h>
#include <stdint.h>

/* True if path holds a complete PNG or EXR (by its extension) of width x height pixels: the
 * headers parse, the size matches, and the data runs to the file's end (a PNG ends with its IEND
 * chunk; every chunk of an EXR lies inside the file). A missing, truncated or foreign file is
 * false. vkrt itself never leaves a partial file (it renames complete ones into place), so this
 * guards against files cut short by other tools, full disks or a different resolution. */
bool vkrt_image_is_complete(const char *path, uint32_t width, uint32_t height);

#endif
