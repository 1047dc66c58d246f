/*
 * texture.glsl: reading the scene's textures from the texel buffer.
 *
 * All textures live in one array of uints described by texture_infos[]: bindings.glsl declares
 * both, and texel_word(i), word i of the array (which reaches its chunks when the array is split
 * over several buffers), before this file is included. Devices without descriptor indexing
 * cannot take an array of sampled images, and the filtering is done here.
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

/* Texel (x, y) of texture tex as linear RGBA: x from the left, y from the top row, both wrapped
 * into the image. 8-bit colour maps are decoded from sRGB here, per texel, so that filtering
 * averages light rather than encoded values. */
vec4 texture_texel(uint tex, int x, int y)
{
    TextureInfo info = texture_infos[tex];
    uint i = texture_wrap(y, info.height) * info.width + texture_wrap(x, info.width);
    if ((info.flags & VKRT_TEXTURE_HALF) != 0u) {
        uint at = info.offset + 2u * i;
        return vec4(unpackHalf2x16(texel_word(at)), unpackHalf2x16(texel_word(at + 1u)));
    }
    vec4 c = unpackUnorm4x8(texel_word(info.offset + i));
    if ((info.flags & VKRT_TEXTURE_SRGB) != 0u)
        c.rgb = texture_srgb_to_linear(c.rgb);
    return c;
}

/* Bilinear sample of texture tex at uv, repeating in both directions. uv follows the OBJ
 * convention (v = 0 is the bottom row of the image, which is stored top row first), and texel k
 * covers [k, k + 1) with its centre at k + 0.5. Non-finite uv read as 0. */
vec4 texture_sample(uint tex, vec2 uv)
{
    TextureInfo info = texture_infos[tex];
    uv = mix(uv, vec2(0.0), bvec2(isnan(uv.x) || isinf(uv.x), isnan(uv.y) || isinf(uv.y)));
    /* Wrap first, so that a large uv keeps its precision. */
    vec2 wrapped = fract(vec2(uv.x, 1.0 - uv.y));
    vec2 p = wrapped * vec2(info.width, info.height) - 0.5;
    vec2 p0 = floor(p);
    vec2 f = p - p0;
    int x = int(p0.x), y = int(p0.y);
    vec4 top = mix(texture_texel(tex, x, y), texture_texel(tex, x + 1, y), f.x);
    vec4 bottom = mix(texture_texel(tex, x, y + 1), texture_texel(tex, x + 1, y + 1), f.x);
    return mix(top, bottom, f.y);
}

#endif
