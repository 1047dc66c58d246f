/*
 * texture_file.h: the file side of a texture (texture.c's helpers): finding the image a scene
 * names, and saying in words why stb_image could not decode one. Pure CPU.
 */
#ifndef VKRT_TEXTURE_FILE_H
#define VKRT_TEXTURE_FILE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include "../error.h"

/* The file path names, in *found (malloc'd; NULL when path itself exists as written): when it
 * does not, backslashes are read as '/' and then the file name alone is matched ignoring case in
 * its folder (a unique match only; several are an error that lists them). False with err set to
 * "<referrer>: texture '<path>': <reason>" when there is no such regular file. */
bool vkrt_texture_find_file(const char *path, const char *referrer, char **found, vkrt_error *err);

/* Why stb_image failed on the open image f, in words, into why (call it right after the failed
 * decode: it reads stb_image's reason first); a PNG cut short says where it ends. */
void vkrt_texture_decode_failure(FILE *f, char *why, size_t size);

#endif
