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

/* Texel (x, y) of texture tex as linear RGBA: x from the left, y from the top row, both wrapped
 * into the image by the texture's wrap modes. 8-bit colour maps are decoded from sRGB here, per
 * texel, so that filtering averages light rather than encoded values. */
vec4 texture_texel(uint tex, int x, int y)
{
    TextureInfo info = texture_infos[tex];
    uint wrap_u = (info.flags >> 2u) & 3u, wrap_v = (info.flags >> 4u) & 3u;
    uint i = (wrap_u | wrap_v) == VKRT_TEXTURE_REPEAT
                 ? texture_wrap(y, info.height) * info.width + texture_wrap(x, info.width)
                 : texture_wrap_mode(y, info.height, wrap_v) * info.width +
                       texture_wrap_mode(x, info.width, wrap_u);
    if ((info.flags & VKRT_TEXTURE_HALF) != 0u) {
        uint at = info.offset + 2u * i;
        return vec4(unpackHalf2x16(texel_word(at)), unpackHalf2x16(texel_word(at + 1u)));
    }
    vec4 c = unpackUnorm4x8(texel_word(info.offset + i));
    if ((info.flags & VKRT_TEXTURE_SRGB) != 0u)
        c.rgb = texture_srgb_to_linear(c.rgb);
    return c;
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

/* Texture tex at uv, linear RGBA, as its TextureInfo says: uv follows the OBJ convention (v = 0 is
 * the bottom row of the image, which is stored top row first), so the image coordinates are
 * (s, t) = (u, 1 - v), s from the left and t down from the top row; the map's uv transform moves
 * (s, t) (VKRT_TEXTURE_TRANSFORM); each axis wraps by its mode; texel k covers [k, k + 1) with its
 * centre at k + 0.5, blended bilinearly or (VKRT_TEXTURE_NEAREST) the one texel holding the point;
 * a one-number map's channel goes to all four components (VKRT_TEXTURE_CHANNEL). Non-finite
 * coordinates read as 0. Repeat, bilinear and untransformed is the first branch throughout. */
vec4 texture_sample(uint tex, vec2 uv)
{
    TextureInfo info = texture_infos[tex];
    uv = mix(uv, vec2(0.0), bvec2(isnan(uv.x) || isinf(uv.x), isnan(uv.y) || isinf(uv.y)));
    vec2 st = vec2(uv.x, 1.0 - uv.y);
    if ((info.flags & VKRT_TEXTURE_TRANSFORM) != 0u) {
        st = vec2(info.uv_matrix.x * st.x + info.uv_matrix.y * st.y + info.uv_offset.x,
                  info.uv_matrix.z * st.x + info.uv_matrix.w * st.y + info.uv_offset.y);
        st = mix(st, vec2(0.0), bvec2(isnan(st.x) || isinf(st.x), isnan(st.y) || isinf(st.y)));
    }
    uint wrap_u = (info.flags >> 2u) & 3u, wrap_v = (info.flags >> 4u) & 3u;
    vec2 wrapped = (wrap_u | wrap_v) == VKRT_TEXTURE_REPEAT
                       ? fract(st)
                       : vec2(texture_fold(st.x, wrap_u), texture_fold(st.y, wrap_v));
    vec2 size = vec2(info.width, info.height);
    vec4 c;
    if ((info.flags & VKRT_TEXTURE_NEAREST) != 0u) {
        vec2 p = floor(wrapped * size);
        c = texture_texel(tex, int(p.x), int(p.y));
    } else {
        vec2 p = wrapped * size - 0.5;
        vec2 p0 = floor(p);
        vec2 f = p - p0;
        int x = int(p0.x), y = int(p0.y);
        vec4 top = mix(texture_texel(tex, x, y), texture_texel(tex, x + 1, y), f.x);
        vec4 bottom = mix(texture_texel(tex, x, y + 1), texture_texel(tex, x + 1, y + 1), f.x);
        c = mix(top, bottom, f.y);
    }
    uint channel = (info.flags >> 8u) & 3u;
    return channel == 0u ? c : vec4(c[channel]);
}

#endif
