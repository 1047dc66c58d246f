/*
 * surface_maps.glsl: the .mtl maps that change the surface every built-in sees (glsl/shared.h,
 * VKRT_MATERIAL_*_MAP; docs/materials.md): the shading normal from a tangent-space normal map
 * (`norm`, or a `map_Bump` whose image is one) or from a height map (`map_Bump`, `bump`), and the
 * emission Ke times `map_Ke`. Normal and height maps are read as data (no sRGB decoding), map_Ke as
 * colour. A scene compiles the code of the kinds its materials use only (SURFACE_MAPS).
 *
 * The tangent frame is the triangle's texture space, dp/du and dp/dv from its corners and their
 * uv (pbrt's triangle), made orthogonal to the shading normal per hit: with interpolated normals
 * the frame turns with them, as MikkTSpace's per-pixel frame does (it differs from a baked
 * MikkTSpace frame only in that the tangents are per triangle, not averaged over the vertices).
 * The bitangent takes the sign of dp/dv, so mirrored uv mirror the map; normal maps follow the
 * OpenGL convention, green = +v (up in the image), as Blender bakes them.
 */
#ifndef VKRT_SURFACE_MAPS_GLSL
#define VKRT_SURFACE_MAPS_GLSL

#include "bindings.glsl"
#include "texture.glsl"

/* Least cosine a mapped normal keeps with the geometric normal and with the direction to the
 * viewer: a map may tilt the normal past either, which would make the surface black where it is
 * seen (every BSDF is zero for a viewer behind the shading normal) or let light in from below. */
const float MAPPED_NORMAL_MIN_COS = 0.01;

/* The triangle's dp/du and dp/dv (not unit, not orthogonal). False where its uv are degenerate
 * (all on a line): no texture space to map in. */
bool texture_space(Triangle tri, TriangleTexcoords tc, out vec3 dpdu, out vec3 dpdv)
{
    vec2 duv1 = tc.uv01.zw - tc.uv01.xy, duv2 = tc.uv2.xy - tc.uv01.xy;
    vec3 e1 = tri.v1.xyz - tri.v0.xyz, e2 = tri.v2.xyz - tri.v0.xyz;
    float det = duv1.x * duv2.y - duv1.y * duv2.x;
    dpdu = (duv2.y * e1 - duv1.y * e2) / det;
    dpdv = (duv1.x * e2 - duv2.x * e1) / det;
    return det != 0.0 && !any(isinf(dpdu)) && !any(isinf(dpdv)) && !any(isnan(dpdu)) &&
           !any(isnan(dpdv));
}

/* The height of a height map at uv: the mean of its channels, so that a colour image used as
 * one (dabrovic-sponza's) reads as its brightness. */
float map_height(uint tex, vec2 uv, float footprint)
{
    return dot(texture_sample_footprint(tex, uv, footprint).rgb, vec3(1.0 / 3.0));
}

/* The normal of material m's normal or height map at uv, for a surface of unit normal n (the side
 * the map's +z is on: the OBJ's normal, or the winding's), with texture space dpdu, dpdv, the map
 * read at the hit's footprint (texture_sample_footprint).
 * Normal map: the texel as (2 rgb - 1) in the frame (t, b, n), its x and y times -bm (Blender's
 * normal map strength). Height map: the surface displaced by -bm times the height along n, in
 * scene units (pbrt's and Mitsuba's bump map): n' = (dpdu + dh/du n) x (dpdv + dh/dv n), dh/du and
 * dh/dv by central differences half a texel either side (a ramp's slope exactly). */
vec3 mapped_normal(uint m, vec3 n, vec3 dpdu, vec3 dpdv, vec2 uv, float footprint)
{
    Material mat = materials[m];
    uint tex = mat.textures[VKRT_SLOT_DETAIL >> 2u][VKRT_SLOT_DETAIL & 3u];
    float multiplier = mat.maps.y;
    vec3 su = dpdu - n * dot(n, dpdu), sv = dpdv - n * dot(n, dpdv);
    if ((SURFACE_MAPS & VKRT_MATERIAL_NORMAL_MAP) != 0u &&
        (mat.info.y & VKRT_MATERIAL_NORMAL_MAP) != 0u) {
        if (!(dot(su, su) > 0.0))
            return n;
        vec3 t = normalize(su);
        vec3 b = cross(n, t);
        if (dot(b, sv) < 0.0)
            b = -b;
        vec3 local = texture_sample_footprint(tex, uv, footprint).rgb * 2.0 - 1.0;
        local.xy *= multiplier;
        vec3 mapped = local.x * t + local.y * b + local.z * n;
        return dot(mapped, mapped) > 0.0 ? normalize(mapped) : n;
    }
    if ((SURFACE_MAPS & VKRT_MATERIAL_BUMP_MAP) == 0u)
        return n;
    TextureInfo info = texture_infos[tex];
    vec2 du = vec2(0.5 / float(info.width), 0.0), dv = vec2(0.0, 0.5 / float(info.height));
    float dhdu = (map_height(tex, uv + du, footprint) - map_height(tex, uv - du, footprint)) *
                 float(info.width);
    float dhdv = (map_height(tex, uv + dv, footprint) - map_height(tex, uv - dv, footprint)) *
                 float(info.height);
    vec3 bumped = cross(su + multiplier * dhdu * n, sv + multiplier * dhdv * n);
    if (!(dot(bumped, bumped) > 0.0))
        return n;
    bumped = normalize(bumped);
    return dot(bumped, n) < 0.0 ? -bumped : bumped;
}

/* Keeps a mapped normal n (on the side of the arriving ray, as ng) in front of the geometric
 * normal ng and of the viewer wo (unit, dot(wo, ng) > 0): each step adds a multiple of ng or wo,
 * which only raises the other cosine. */
vec3 guard_mapped_normal(vec3 n, vec3 ng, vec3 wo)
{
    float c = dot(n, ng);
    if (c < MAPPED_NORMAL_MIN_COS)
        n = normalize(n + (MAPPED_NORMAL_MIN_COS - c) * ng);
    c = dot(n, wo);
    if (c < MAPPED_NORMAL_MIN_COS)
        n = normalize(n + (MAPPED_NORMAL_MIN_COS - c) * wo);
    return n;
}

/* Emission of material m at uv: Ke (parameters 8-10), times map_Ke where it has one. */
vec3 surface_emission(uint m, vec2 uv)
{
    vec3 ke = materials[m].params[2].xyz;
    if ((SURFACE_MAPS & VKRT_MATERIAL_EMISSION_MAP) != 0u &&
        (materials[m].info.y & VKRT_MATERIAL_EMISSION_MAP) != 0u)
        ke *= texture_sample(materials[m].textures[VKRT_SLOT_EMISSION >> 2u]
                                                   [VKRT_SLOT_EMISSION & 3u], uv).rgb;
    return ke;
}

#endif
