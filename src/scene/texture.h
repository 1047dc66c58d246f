/*
 * texture.h: the scene's textures, decoded into the one texel buffer the kernels read.
 *
 * Images are read with stb_image (PNG, JPEG, TGA and Radiance HDR; whatever else stb_image
 * decodes, such as BMP, is accepted too). Every texture of a scene lives in one array of uints
 * that the renderer uploads as-is, with a TextureInfo per texture saying where it starts, because
 * a device without descriptor indexing cannot bind an array of images. The layout is fixed by
 * TextureInfo in glsl/shared.h: rows top first as the file stores them, one uint per texel (RGBA8,
 * r in the low byte) or, for HDR images, two (RGBA as half floats, flag VKRT_TEXTURE_HALF).
 * glsl/lib/texture.glsl samples them; vkrt_texture_sample is its reference on the CPU.
 *
 * Pure CPU, no Vulkan.
 */
#ifndef VKRT_TEXTURE_H
#define VKRT_TEXTURE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "../error.h"

/* Widest and tallest image accepted: more is a mistake (or an attack) rather than a texture. */
#define VKRT_TEXTURE_MAX_SIZE 16384u

/* What a texture is used for, which decides how its texels are stored. */
typedef enum vkrt_texture_usage {
    VKRT_TEXTURE_COLOUR, /* colour map (map_Kd): 8-bit images are sRGB-encoded, flagged
                            VKRT_TEXTURE_SRGB so that sampling decodes them to linear */
    VKRT_TEXTURE_DATA,   /* linear values (parameters, normal-like data), stored as they are */
    VKRT_TEXTURE_ALPHA,  /* coverage (map_d): the image's alpha channel if it has one, else its
                            first channel, stored in all four channels, linear */
} vkrt_texture_usage;

/* The same bytes as TextureInfo in glsl/shared.h, whose VKRT_TEXTURE_* flags it carries
 * (texture.c checks the layout). */
typedef struct vkrt_texture_info {
    uint32_t offset; /* index of the texture's first uint in texels */
    uint32_t width, height;
    uint32_t flags;     /* VKRT_TEXTURE_SRGB, _HALF: the image's; VKRT_TEXTURE_WRAP_U/_V,
                           _NEAREST, _TRANSFORM, _CHANNEL: how a map reads it (glsl/shared.h) */
    float uv_matrix[4]; /* with VKRT_TEXTURE_TRANSFORM: (s, t) -> (m0 s + m1 t + o0, */
    float uv_offset[4]; /*                                m2 s + m3 t + o1); o2, o3 unused */
} vkrt_texture_info;

/* All textures of a scene. Zero-initialise it, set max_texel_bytes if the device has a limit,
 * then add textures. info, paths and usages have count entries; texels has texel_words. */
typedef struct vkrt_texture_set {
    vkrt_texture_info *info;
    char **paths;     /* the file each texture was read from, canonical (realpath), or an
                         embedded image's name */
    uint32_t *usages; /* vkrt_texture_usage of each texture */
    uint32_t count;
    uint32_t *texels; /* every texture's texels, one after the other */
    size_t texel_words;
    size_t max_texel_bytes; /* the most texels may take in bytes (the storage buffer's range);
                               0: no limit beyond 32-bit offsets */
    struct vkrt_texture_ahead *ahead; /* images decoded ahead, waiting for their adds */
    uint32_t ahead_count;
} vkrt_texture_set;

/* Adds the image at path for the given usage and returns its index in *index. An image already in
 * the set with the same usage (same file after resolving the path) is not read again: its index
 * is returned. referrer names where the texture was asked for ("scenes/x/x.mtl:12", "mats.txt:3";
 * NULL leaves it out). On failure returns false, leaves the set's contents as they were, and sets
 * err to "<referrer>: texture '<path>': <reason>": the file is missing, not an image stb_image
 * can decode (its reason is quoted and said in words; a PNG cut short says where it ends), empty,
 * 0 or more than VKRT_TEXTURE_MAX_SIZE wide or tall, or
 * the set would grow past max_texel_bytes (the message gives the sizes in MiB).
 *
 * Finding the file: when path does not exist as written, backslashes are read as '/' (Windows
 * exporters write "maps\wall.jpg"), and then the file name (not its folders) is matched ignoring
 * case in its folder, because scenes made on Windows name "SP_LUK.JPG" for a file "sp_luk.JPG".
 * Only a unique match is taken, silently; several matches are an error that lists them. */
bool vkrt_texture_set_add(vkrt_texture_set *set, const char *path, vkrt_texture_usage usage,
                          const char *referrer, uint32_t *index, vkrt_error *err);

/* Adds an image held in memory as its file's encoded bytes (a glTF's embedded image), with the
 * same decoding, checks and messages as vkrt_texture_set_add; name stands for the path in them
 * and identifies the image: one already in the set with the same name and usage is returned, not
 * decoded again, so a loader gives each image a name of its own ("model.glb: image 3"). The set
 * keeps no pointer to bytes. */
bool vkrt_texture_set_add_memory(vkrt_texture_set *set, const void *bytes, size_t size,
                                 const char *name, vkrt_texture_usage usage,
                                 const char *referrer, uint32_t *index, vkrt_error *err);

/* An image a scene is about to add, named as its vkrt_texture_set_add (path; bytes NULL) or
 * vkrt_texture_set_add_memory (path the name; bytes and size the encoded image) will name it. */
typedef struct vkrt_texture_source {
    const char *path;
    const void *bytes;
    size_t size;
    vkrt_texture_usage usage;
} vkrt_texture_source;

/* Decodes the images of sources on every core (up to 32 threads; $VKRT_TEXTURE_THREADS sets the
 * number, and 0 or 1 turns this off), ahead of the adds that will ask for them, since decoding one
 * at a time is most of a textured scene's start-up. It returns when all are decoded, keeping no
 * pointer to sources' bytes. The adds then take the decoded texels instead of decoding: the set
 * they make (order, texels, info, messages) is exactly the one they would make alone, because an
 * image is decoded by the same code either way and appended when its add comes. Nothing here
 * fails: an image that cannot be decoded ahead (missing, damaged, too large, past
 * max_texel_bytes with what comes before it in sources, out of memory) is left to its add, which
 * decodes it and says why. An image decoded ahead that no add asks for is held until
 * vkrt_texture_set_free. */
void vkrt_texture_set_decode_ahead(vkrt_texture_set *set, const vkrt_texture_source *sources,
                                   uint32_t count);

/* A texture of the set as a map reads it: the entry with texture base's image (its texels, not
 * copied) and view_flags (VKRT_TEXTURE_WRAP_U/_V, _NEAREST, _TRANSFORM, _CHANNEL; nothing else),
 * with uv_matrix and uv_offset where view_flags has VKRT_TEXTURE_TRANSFORM (vkrt_texture_uv_
 * transform makes them). view_flags 0 gives base itself; an entry that reads the same image the
 * same way is reused; else one is added, with base's path and usage. False, the set as it was and
 * err set, when base is not an image added by vkrt_texture_set_add or memory runs out. */
bool vkrt_texture_set_view(vkrt_texture_set *set, uint32_t base, uint32_t view_flags,
                           const float uv_matrix[4], const float uv_offset[2], uint32_t *index,
                           vkrt_error *err);

/* KHR_texture_transform's offset, scale and rotation as a TextureInfo's uv_matrix and uv_offset,
 * in image coordinates (s, t): s from the left, t down from the top row, which is glTF's uv:
 *     (s', t') = offset + R (scale_s s, scale_t t),  R = [cos r  sin r; -sin r  cos r]
 * (rows), as the extension's sample viewer and its example (offset (0, 1), rotation pi/2, scale
 * 0.5 reads the image's lower left quarter) have it: counter-clockwise with t pointing down.
 * Returns whether the transform is the identity (offset 0, scale 1, rotation 0), which needs no
 * VKRT_TEXTURE_TRANSFORM. */
bool vkrt_texture_uv_transform(const float offset[2], const float scale[2], float rotation,
                               float uv_matrix[4], float uv_offset[2]);

/* How the kernels filter a scene's textures (scene.cfg's `textures`): by the ray cone's footprint
 * from the mipmap levels (the default), bilinear from the image alone (without mipmaps, as before
 * they were made: a distant texture aliases), or the nearest texel of the image. */
typedef enum vkrt_texture_filter {
    VKRT_TEXTURE_FILTER_CONE = 0,
    VKRT_TEXTURE_FILTER_BILINEAR,
    VKRT_TEXTURE_FILTER_NEAREST,
} vkrt_texture_filter;

/* Makes every entry of the set read as filter says: bilinear leaves the entries' levels unread
 * (VKRT_TEXTURE_LEVELS cleared; the texels stay), nearest also sets VKRT_TEXTURE_NEAREST, cone
 * changes nothing. Call it once the set is complete. */
void vkrt_texture_set_filter(vkrt_texture_set *set, vkrt_texture_filter filter);

/* Frees what the set holds (images decoded ahead too) and zeroes it, keeping max_texel_bytes.
 * Safe on a zeroed set. */
void vkrt_texture_set_free(vkrt_texture_set *set);

/* The CPU reference of texture_sample in glsl/lib/texture.glsl, with the same arithmetic (for
 * tests): the texture's sample at uv as its entry reads it, with uv in the OBJ convention (v = 0 is
 * the bottom row), so image coordinates (s, t) = (u, 1 - v); then the entry's uv transform, wrap
 * modes (repeat, clamp to edge, mirrored repeat), bilinear or nearest filtering and channel, as
 * linear RGBA. Texel centres lie at half-integers, and filtering happens after sRGB decoding.
 * Non-finite coordinates read as 0. An index past the set gives 0. */
void vkrt_texture_sample(const vkrt_texture_set *set, uint32_t index, float u, float v,
                         float rgba[4]);

/* One texel of the texture as linear RGBA, with x and y (x from the left, y from the top row)
 * wrapped into the image by the entry's wrap modes: the CPU reference of texture_texel in
 * glsl/lib/texture.glsl. */
void vkrt_texture_texel(const vkrt_texture_set *set, uint32_t index, int x, int y, float rgba[4]);

/* The mean of the texture's texels as linear RGBA (colour maps decoded from sRGB first, as the
 * kernels read them); 0 for an index past the set. Light sampling weighs an emission map by it. */
void vkrt_texture_mean(const vkrt_texture_set *set, uint32_t index, float rgba[4]);

/* Whether the texture (stored as data) reads as a tangent-space normal map: its mean is near
 * (0.5, 0.5, 1), the unbent normal (red and green within 0.25 of 0.5, blue above 0.8 and 0.2
 * above both), where a height map is grey. Exporters write normal maps as
 * map_Bump (Blender's does), so map_Bump is told apart by its image. */
bool vkrt_texture_is_normal_map(const vkrt_texture_set *set, uint32_t index);

#endif
