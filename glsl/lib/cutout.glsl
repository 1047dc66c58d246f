/*
 * cutout.glsl: textures that cut surfaces out (foliage cards, fences): a map_d, or the alpha of an
 * RGBA map_Kd given without map_d, as exporters and game assets make them. The test is part of
 * traversal, so every ray, camera, shadow, light sample or bounce, of either integrator, sees the
 * same holes. A hit where the coverage c is below 1 counts with probability c (pbrt-v4's
 * stochastic alpha test), decided by a hash of the ray and the hit's barycentrics, so the same ray always
 * gets the same answer and a pixel's samples average to the fractional coverage. Scenes without
 * cut-outs compile none of it (HAS_CUTOUTS).
 */
#ifndef VKRT_CUTOUT_GLSL
#define VKRT_CUTOUT_GLSL

#include "bindings.glsl"
#include "rng.glsl"
#include "texture.glsl"

/* The ray being traced, hashed (cutout_begin_ray). */
uint cutout_ray_seed = 0u;

void cutout_begin_ray(vec3 origin, vec3 dir)
{
    if (!HAS_CUTOUTS)
        return;
    uvec3 o = floatBitsToUint(origin), d = floatBitsToUint(dir);
    cutout_ray_seed = pcg_hash(o.x ^ pcg_hash(o.y ^ pcg_hash(o.z ^ pcg_hash(d.x ^ pcg_hash(
                                                                        d.y ^ pcg_hash(d.z))))));
}

/* Whether the ray's hit of triangle tri at barycentrics (u, v) of v1 and v2 counts. */
bool cutout_keeps(uint tri, float u, float v)
{
    if (!HAS_CUTOUTS)
        return true;
    Material m = materials[material_of(tri)];
    if (m.info.w == VKRT_CUTOUT_NONE)
        return true;
    vec2 uv = vec2(0.0);
    if (HAS_TEXCOORDS) {
        TriangleTexcoords tc = texcoords_at(tri);
        uv = (1.0 - u - v) * tc.uv01.xy + u * tc.uv01.zw + v * tc.uv2.xy;
    }
    float coverage = m.info.w == VKRT_CUTOUT_MAP_D ? texture_sample(m.textures[0].y, uv).r
                                                    : texture_sample(m.textures[0].x, uv).a;
    if (coverage >= 1.0)
        return true;
    /* Keyed by the hit's barycentrics, not the triangle's index: with spatial splits a
     * triangle is stored once per leaf it reaches, and a ray that tests two copies must get one
     * answer (the copies give the same bits), or the triangle would look more opaque. */
    return rng_float(pcg_hash(cutout_ray_seed ^ pcg_hash(floatBitsToUint(u) ^
                                                         pcg_hash(floatBitsToUint(v))))) <
           coverage;
}

#endif
