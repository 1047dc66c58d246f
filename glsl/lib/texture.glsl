/*
 * texture.glsl: reading the scene's textures from the texel buffer.
 *
 * All textures live in one array of uints described by texture_infos[]: bindings.glsl declares
 * both, and texel_word(i), word i of the array (which reaches its chunks when the array is split
 * over several buffers), before this file is included. Devices without descriptor indexing
 * cannot take an array of sampled images, and the filtering is done here, with the sampler
 * (wrap modes, nearest or bilinear), uv transform and channel each entry carries.
 * src/scene/texture.h fills the buffers (layout: TextureInfo in shared.h); vkrt_texture_sample
 * and vkrt_texture_texel in src/scene/texture.c repeat these steps on the CPU for the tests, so a
 * change here belongs there too.
 */
#ifndef VKRT_TEXTURE_GLSL
#define VKRT_TEXTURE_GLSL

#include "../shared.h"

/* The exact sRGB decoding curve (IEC 61966-2-1), not a 2.2 power: dark texels would come out
 * several times too dark with the approximation. */
vec3 texture_srgb_to_linear(vec3 c)
{
    vec3 curve = pow((c + 0.055) / 1.055, vec3(2.4));
    return mix(c / 12.92, curve, greaterThan(c, vec3(0.04045)));
}

/* i modulo n for any int i. Unsigned, because GLSL leaves % of negative ints undefined; uint(abs(i))
 * is right even for the most negative int. */
uint texture_wrap(int i, uint n)
{
    uint r = uint(abs(i)) % n;
    return (i < 0 && r != 0u) ? n - r : r;
}

/* Texel index i of a row or column of n texels under a wrap mode (VKRT_TEXTURE_REPEAT, _CLAMP,
 * _MIRROR), as Vulkan's samplers address it: mirrored repeat runs 0 .. n-1, n-1 .. 0 again and
 * again. */
uint texture_wrap_mode(int i, uint n, uint mode)
{
    if (mode == VKRT_TEXTURE_CLAMP)
        return uint(clamp(i, 0, int(n) - 1));
    if (mode == VKRT_TEXTURE_MIRROR) {
        uint m = texture_wrap(i, 2u * n);
        return m < n ? m : 2u * n - 1u - m;
    }
    return texture_wrap(i, n);
}

/* Texel (x, y) of an image of size w x h whose texels start at word `at` of the texel buffer,
 * with texture info's format and wrap modes, as linear RGBA: x from the left, y from the top row,
 * both wrapped into the image by the wrap modes. 8-bit colour maps are decoded from sRGB here,
 * per texel, so that filtering averages light rather than encoded values. */
vec4 texture_texel_of(TextureInfo info, uint at, uint w, uint h, int x, int y)
{
    uint wrap_u = (info.flags >> 2u) & 3u, wrap_v = (info.flags >> 4u) & 3u;
    uint i = (wrap_u | wrap_v) == VKRT_TEXTURE_REPEAT
                 ? texture_wrap(y, h) * w + texture_wrap(x, w)
                 : texture_wrap_mode(y, h, wrap_v) * w + texture_wrap_mode(x, w, wrap_u);
    if ((info.flags & VKRT_TEXTURE_HALF) != 0u) {
        uint word = at + 2u * i;
        return vec4(unpackHalf2x16(texel_word(word)), unpackHalf2x16(texel_word(word + 1u)));
    }
    vec4 c = unpackUnorm4x8(texel_word(at + i));
    if ((info.flags & VKRT_TEXTURE_SRGB) != 0u)
        c.rgb = texture_srgb_to_linear(c.rgb);
    return c;
}

/* Texel (x, y) of texture tex's image (its level 0), as texture_texel_of reads it. */
vec4 texture_texel(uint tex, int x, int y)
{
    TextureInfo info = texture_infos[tex];
    return texture_texel_of(info, info.offset, info.width, info.height, x, y);
}

/* An image coordinate brought into the span the wrap mode repeats, before it is scaled to texels:
 * repeat [0, 1] by its fraction, clamp [0, 1] (beyond it the edge texel is all there is), mirror
 * [0, 2] (one period of the mirrored image). Done first so that a large coordinate keeps its
 * precision. */
float texture_fold(float c, uint mode)
{
    if (mode == VKRT_TEXTURE_CLAMP)
        return clamp(c, 0.0, 1.0);
    if (mode == VKRT_TEXTURE_MIRROR)
        return c - 2.0 * floor(c * 0.5);
    return fract(c);
}

/* A footprint (log2 of a width in uv units) below any image's texel: the image itself is read. */
const float TEXTURE_FULL_RESOLUTION = -1.0e30;

/* log2 of the width in uv units of a cone of width `width` meeting, at cosine cos_in, a triangle
 * with edges e1, e2 (world) and duv1, duv2 (uv): RTG 2019 eq. 20.34's
 * 0.5 log2(t_a / p_a) + log2(|w| / |n.d|), t_a and p_a twice the triangle's area in uv and in the
 * world; TEXTURE_FULL_RESOLUTION where the cone has no width or the mapping is degenerate. */
float texture_cone_footprint(float width, float cos_in, vec3 e1, vec3 e2, vec2 duv1, vec2 duv2)
{
    float uv_area = abs(duv1.x * duv2.y - duv1.y * duv2.x);
    float world_area = length(cross(e1, e2));
    float footprint = 0.5 * log2(uv_area / world_area) + log2(abs(width) / max(cos_in, 1e-4));
    return width != 0.0 && uv_area > 0.0 && world_area > 0.0 && !isnan(footprint) &&
                   !isinf(footprint)
               ? footprint
               : TEXTURE_FULL_RESOLUTION;
}

/* Level `level` of info's image: where its texels start, and its size (VKRT_TEXTURE_LEVELS in
 * shared.h: each level halves the one before, rounding down, to at least 1). */
uint texture_level(TextureInfo info, uint level, out uint w, out uint h)
{
    uint words = (info.flags & VKRT_TEXTURE_HALF) != 0u ? 2u : 1u;
    uint at = info.offset;
    w = info.width;
    h = info.height;
    for (uint k = 0u; k < level; ++k) {
        at += words * w * h;
        w = max(w >> 1u, 1u);
        h = max(h >> 1u, 1u);
    }
    return at;
}

/* The bilinear blend of the four texels of a w x h level starting at word `at` about the wrapped
 * image coordinates: texel k covers [k, k + 1) with its centre at k + 0.5. */
vec4 texture_bilinear(TextureInfo info, uint at, uint w, uint h, vec2 wrapped)
{
    vec2 p = wrapped * vec2(w, h) - 0.5;
    vec2 p0 = floor(p);
    vec2 f = p - p0;
    int x = int(p0.x), y = int(p0.y);
    vec4 top = mix(texture_texel_of(info, at, w, h, x, y),
                   texture_texel_of(info, at, w, h, x + 1, y), f.x);
    vec4 bottom = mix(texture_texel_of(info, at, w, h, x, y + 1),
                      texture_texel_of(info, at, w, h, x + 1, y + 1), f.x);
    return mix(top, bottom, f.y);
}

/* Texture tex at uv, linear RGBA, as its TextureInfo says, for a footprint on the surface
 * `footprint` = log2 of its width in uv units (surface_at's texture_footprint; TEXTURE_FULL_RESOLUTION or anything
 * that makes the level below 0: the image itself). uv follows the OBJ convention (v = 0 is the
 * bottom row of the image, which is stored top row first), so the image coordinates are
 * (s, t) = (u, 1 - v), s from the left and t down from the top row; the map's uv transform moves
 * (s, t) (VKRT_TEXTURE_TRANSFORM); each axis wraps by its mode; texel k covers [k, k + 1) with its
 * centre at k + 0.5, blended bilinearly or (VKRT_TEXTURE_NEAREST) the one texel holding the point;
 * a one-number map's channel goes to all four components (VKRT_TEXTURE_CHANNEL). Non-finite
 * coordinates read as 0. Repeat, bilinear and untransformed is the first branch throughout.
 *
 * The level of detail is the footprint in texels, log2 of its width times the texels per uv unit
 * (0.5 log2(width x height), RTG 2019 eq. 20.35's texture term; a uv transform scales it by the
 * square root of its determinant). Where it is above 0 and the image has levels (VKRT_TEXTURE_
 * LEVELS), the two levels about it are read bilinearly and blended by its fraction (trilinear
 * filtering, isotropic: the cone's footprint is a circle, its stretch along a grazing view is
 * not followed). Nearest-texel maps read their image alone. */
vec4 texture_sample_footprint(uint tex, vec2 uv, float footprint)
{
    TextureInfo info = texture_infos[tex];
    uv = mix(uv, vec2(0.0), bvec2(isnan(uv.x) || isinf(uv.x), isnan(uv.y) || isinf(uv.y)));
    vec2 st = vec2(uv.x, 1.0 - uv.y);
    float lod = footprint + 0.5 * log2(float(info.width) * float(info.height));
    if ((info.flags & VKRT_TEXTURE_TRANSFORM) != 0u) {
        st = vec2(info.uv_matrix.x * st.x + info.uv_matrix.y * st.y + info.uv_offset.x,
                  info.uv_matrix.z * st.x + info.uv_matrix.w * st.y + info.uv_offset.y);
        st = mix(st, vec2(0.0), bvec2(isnan(st.x) || isinf(st.x), isnan(st.y) || isinf(st.y)));
        lod += 0.5 * log2(abs(info.uv_matrix.x * info.uv_matrix.w -
                              info.uv_matrix.y * info.uv_matrix.z));
    }
    uint wrap_u = (info.flags >> 2u) & 3u, wrap_v = (info.flags >> 4u) & 3u;
    vec2 wrapped = (wrap_u | wrap_v) == VKRT_TEXTURE_REPEAT
                       ? fract(st)
                       : vec2(texture_fold(st.x, wrap_u), texture_fold(st.y, wrap_v));
    vec4 c;
    uint levels = VKRT_TEXTURE_LEVELS_OF(info.flags);
    if ((info.flags & VKRT_TEXTURE_NEAREST) != 0u) {
        vec2 p = floor(wrapped * vec2(info.width, info.height));
        c = texture_texel(tex, int(p.x), int(p.y));
    } else {
        /* The level below lod and, weighed by lod's fraction, the one above it: one bilinear
         * read in a loop of one or two, so that the kernels hold one copy of it. Without levels
         * or below level 0, level 0 alone, read as before levels existed. */
        lod = levels == 0u || !(lod > 0.0) ? 0.0 : min(lod, float(levels));
        uint level = min(uint(lod), max(levels, 1u) - 1u);
        float above = lod - float(level);
        uint w, h;
        uint at = texture_level(info, level, w, h);
        uint reads = above > 0.0 ? 2u : 1u;
        c = vec4(0.0);
        for (uint k = 0u; k < reads; ++k) {
            vec4 b = texture_bilinear(info, at, w, h, wrapped);
            c = k == 0u ? b : mix(c, b, above);
            at += ((info.flags & VKRT_TEXTURE_HALF) != 0u ? 2u : 1u) * w * h;
            w = max(w >> 1u, 1u);
            h = max(h >> 1u, 1u);
        }
    }
    uint channel = (info.flags >> 8u) & 3u;
    return channel == 0u ? c : vec4(c[channel]);
}

/* The footprint texture_sample reads with: the hit being shaded's (surface_at's
 * texture_footprint), set by every material call for the surface it is given
 * (src/render/material_kernel.c); TEXTURE_FULL_RESOLUTION until then. */
float texture_footprint = TEXTURE_FULL_RESOLUTION;

/* Texture tex at uv for the footprint of the hit being shaded (texture_sample_footprint). */
vec4 texture_sample(uint tex, vec2 uv)
{
    return texture_sample_footprint(tex, uv, texture_footprint);
}

#endif
