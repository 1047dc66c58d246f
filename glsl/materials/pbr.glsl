/*
 * pbr: what the .mtl PBR extension describes (docs/materials.md): base colour Kd times map_Kd,
 * roughness Pr (parameter 16) times map_Pr (texture slot 2), metallic Pm (17) times map_Pm
 * (slot 3). A mixture, in the metallic workflow: a share `metallic` of a rough conductor whose
 * Schlick reflectance is the base colour, the rest a rough plastic (the base colour under a
 * clear GGX coat of index Ni, 11; 1 or less means 1.5). One roughness for both, GGX
 * alpha = roughness^2.
 * d and map_d cut it out as they do the other built-ins. A clear coat over it: weight 18 (the .mtl
 * Pc / 4), roughness 19 (Pcr) (lib/microfacet.glsl, rough_coat). A sheen beside the non-metal
 * share: the .mtl's Ps times map_Ps (lib/mtl.glsl, mtl_sheen).
 * Whitted: the lights through the BSDF by light_sample, ambient light on the diffuse share, one
 * glossy reflection ray. The entry points are ROUGH_BUILTIN's.
 */
RoughMaterial pbr_material(Surface s)
{
    vec3 base = mtl_diffuse(s);
    float metallic = clamp(param(17u) * material_texture(3u, s.uv).r, 0.0, 1.0);
    /* The .mtl's Ni defaults to 1, which would be no coat at all: a coat needs an index above 1. */
    float ni = param(11u) > 1.0 ? param(11u) : 1.5;
    return RoughMaterial(base, vec3(1.0), base, vec3(1.0), metallic, ni,
                         ggx_alpha(mtl_roughness(s)), false, mtl_sheen(s),
                         PLASTIC_NO_TABLE, 0.0);
}

ROUGH_BUILTIN(pbr_material)
