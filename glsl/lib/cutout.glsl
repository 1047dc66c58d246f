/*
 * cutout.glsl: textures that cut surfaces out (foliage cards, fences): a map_d, or the alpha of an
 * RGBA map_Kd given without map_d, as exporters and game assets make them. The test is part of
 * traversal, so every ray, camera, shadow, light sample or bounce, of either integrator, sees the
 * same holes. A hit where the coverage c is below 1 counts with probability c (pbrt-v4's
 * stochastic alpha test), decided by a hash of the ray and the hit's barycentrics, so the same ray always
 * gets the same answer and a pixel's samples average to the fractional coverage. Scenes without
 * cut-outs compile none of it (HAS_CUTOUTS).

 *
 * A camera ray reads coverage at the footprint of its cone (cutout_cone), as the surface's colour
 * is, so that a distant leaf covers the pixel share its mipmapped coverage says rather than
 * sparkling between texels: that is the pixel's filter over the card. Every other ray reads the
 * image itself: a bounce's cone is wide (a diffuse bounce's spreads by its pdf) and stands for the
 * footprint of the picture's filtering, not for the ray, so filtered coverage would turn a cut-out
 * card into a half-opaque veil for the light that passes it (a test of light through a card's
 * hole, tests/test_path.c, saw the floor under the hole 20% too bright). Shadow rays and the
 * meshes of an instanced scene (whose triangles traversal sees in their own space) have no cone.
 */
#ifndef VKRT_CUTOUT_GLSL
#define VKRT_CUTOUT_GLSL

#include "bindings.glsl"
#include "rng.glsl"
#include "texture.glsl"

/* The ray being traced, hashed (cutout_begin_ray), and where it starts and goes. */
uint cutout_ray_seed = 0u;
vec3 cutout_origin = vec3(0.0), cutout_direction = vec3(0.0);
/* The cone of the rays traced next (ray_cone: width at the origin, spread); zero: none. */
vec2 cutout_cone = vec2(0.0);

void cutout_begin_ray(vec3 origin, vec3 dir)
{
    if (!HAS_CUTOUTS)
        return;
    cutout_origin = origin;
    cutout_direction = dir;
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
    float footprint = TEXTURE_FULL_RESOLUTION;
    if (HAS_TEXCOORDS) {
        TriangleTexcoords tc = texcoords_at(tri);
        uv = (1.0 - u - v) * tc.uv01.xy + u * tc.uv01.zw + v * tc.uv2.xy;
        if (ACCEL_KIND != VKRT_TRAVERSE_BVH_INSTANCED && cutout_cone != vec2(0.0)) {
            Triangle t = triangle_at(tri);
            vec3 e1 = t.v1.xyz - t.v0.xyz, e2 = t.v2.xyz - t.v0.xyz;
            vec3 p = t.v0.xyz + u * e1 + v * e2;
            float width = cutout_cone.x + cutout_cone.y * distance(p, cutout_origin);
            float cos_in = abs(dot(normalize(cross(e1, e2)), cutout_direction));
            footprint = texture_cone_footprint(width, cos_in, e1, e2, tc.uv01.zw - tc.uv01.xy,
                                               tc.uv2.xy - tc.uv01.xy);
        }
    }
    uint tex = m.info.w == VKRT_CUTOUT_MAP_D ? m.textures[0].y : m.textures[0].x;
    vec4 texel = texture_sample_footprint(tex, uv, footprint);
    float coverage = m.info.w == VKRT_CUTOUT_MAP_D ? texel.r : texel.a;
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
