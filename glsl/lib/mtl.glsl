/*
 * mtl.glsl: what the built-in materials share. They all read parameters in the layout the .mtl
 * mapping fills (docs/materials.md has the table), so one .mtl material maps to any of them:
 *   0-2 Kd (diffuse albedo)   3 transparency (1 - d)   4-6 Ks (specular)   7 Ns (Phong exponent)
 *   8-10 Ke (emission)        11 Ni (index of refraction)   12-14 Tf (transmission filter)
 *   15 the BSDF family (no built-in reads it)   16 Pr (roughness)   17 Pm (metallic)
 *   18 Pc (clearcoat)   19 Pcr (its roughness)
 * and texture slot 0 is map_Kd (colour), slot 1 map_d (coverage), 2 map_Pr, 3 map_Pm, 6 map_Ps;
 * the sheen Ps (a material file's number 20) is Material.maps.z. The one-number maps (slots 2, 3
 * and 6) are read by their red: a map that names another channel (glTF's metallicRoughness) has
 * that channel in all four (lib/texture.glsl).
 */
#ifndef VKRT_MTL_GLSL
#define VKRT_MTL_GLSL

vec3 mtl_diffuse(Surface s)
{
    return param3(0u) * material_texture(0u, s.uv).rgb;
}

/* eta = n_transmitted / n_incident at this hit of a glass solid of index Ni (0 means 1.5): the
 * index inside over 1 entering (front face), its inverse leaving. */
float mtl_dielectric_eta(Surface s)
{
    float ni = param(11u) > 0.0 ? param(11u) : 1.5;
    return s.front_face ? ni : 1.0 / ni;
}

/* The perceptual roughness of the rough built-ins: number 16 times the red (the map's channel) of
 * texture slot 2 (map_Pr, data); GGX alpha is its square (lib/microfacet.glsl). */
float mtl_roughness(Surface s)
{
    return param(16u) * material_texture(2u, s.uv).r;
}

/* The sheen weight of the rough built-ins (lib/microfacet.glsl, "The sheen"): the .mtl's Ps (a
 * material file's number 20), kept in Material.maps.z so that the 20 numbers' layout stays as it
 * was, times the red of texture slot 6 (map_Ps, data), in [0, 1]. Constant 0 in a scene without
 * a sheen. */
float mtl_sheen(Surface s)
{
    if ((SURFACE_MAPS & VKRT_MATERIAL_SHEEN) == 0u)
        return 0.0;
    return clamp(materials[vkrt_material].maps.z * material_texture(VKRT_SLOT_SHEEN, s.uv).r, 0.0,
                 1.0);
}

/* Glass's transmission filter Tf; all 0 (not given) means clear. */
vec3 mtl_transmission_filter()
{
    vec3 tf = param3(12u);
    return all(equal(tf, vec3(0.0))) ? vec3(1.0) : tf;
}

/* Coverage of the surface in [0, 1]: d, the uniform part. Below 1 the rest of the light goes
 * through. A map_d (or an RGBA map_Kd's alpha) cuts the surface out in traversal instead
 * (lib/cutout.glsl): a hit that reaches the material is one the cut-out kept. */
float mtl_coverage(Surface s)
{
    return clamp(1.0 - param(3u), 0.0, 1.0);
}

/* The ray that carries on through an uncovered part of the surface: 1 ray where coverage < 1. */
uint mtl_see_through_count(Surface s)
{
    return mtl_coverage(s) < 1.0 ? 1u : 0u;
}

/* Casts the see-through ray (weight 1 - coverage) where coverage < 1; returns the coverage, by
 * which the caller scales what the surface itself reflects. Shadow rays ignore coverage. */
float mtl_see_through(Surface s)
{
    float coverage = mtl_coverage(s);
    if (coverage < 1.0)
        cast_ray(s, s.incoming, vec3(1.0 - coverage));
    return coverage;
}

/* For path: with probability 1 - coverage the path goes on through the surface unchanged (a delta
 * lobe of weight 1); false, drawing nothing, where the surface is covered. */
bool mtl_pass_through(Surface s, out BsdfSample b)
{
    float coverage = mtl_coverage(s);
    b.direction = s.incoming;
    b.weight = vec3(1.0);
    b.pdf = 0.0;
    b.delta = true;
    return coverage < 1.0 && random() >= coverage;
}

#endif
