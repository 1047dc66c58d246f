/*
 * roughconductor: a rough metal: GGX microfacets with visible-normal sampling
 * (lib/microfacet.glsl), Schlick's Fresnel with the specular colour Ks (parameters 4-6) as the
 * reflectance at normal incidence, roughness in 16 (GGX alpha = roughness^2; below 0.02 a
 * perfect mirror), Ke (8-10) emitted from the front face.
 * Numbers 18 and 19 put a clear coat over it (weight, roughness; lib/microfacet.glsl).
 * Whitted: the lights through the BSDF (rough_whitted_shade calls light_sample, which this
 * comment names so that the renderer traces shadow rays for it) and one glossy reflection ray.
 * The entry points (count_rays, shade, emitted, bsdf_eval, bsdf_sample) are ROUGH_BUILTIN's.
 */
RoughMaterial roughconductor_material(Surface s)
{
    return RoughMaterial(vec3(0.0), vec3(0.0), param3(4u), vec3(1.0), 1.0, 1.5,
                         ggx_alpha(mtl_roughness(s)), false, 0.0, PLASTIC_NO_TABLE,
                         0.0);
}

ROUGH_BUILTIN(roughconductor_material)
