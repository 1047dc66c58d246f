/*
 * roughconductor: a rough metal: GGX microfacets with visible-normal sampling
 * (lib/microfacet.glsl), Schlick's Fresnel with the specular colour Ks (parameters 4-6) as the
 * reflectance at normal incidence, roughness in 16 (GGX alpha = roughness^2; below 0.02 a
 * perfect mirror), Ke (8-10) emitted from the front face.
 * Whitted: the lights through the BSDF (rough_whitted_shade calls light_sample, which this
 * comment names so that the renderer traces shadow rays for it) and one glossy reflection ray.
 */
RoughMaterial roughconductor_material()
{
    return RoughMaterial(vec3(0.0), vec3(0.0), param3(4u), vec3(1.0), 1.0, 1.5,
                         ggx_alpha(param(16u)), false);
}

uint count_rays(Surface s)
{
    return 1u;
}

void shade(Surface s)
{
    rough_whitted_shade(s, roughconductor_material(), 1.0);
    add_radiance(param3(8u));
}

vec3 emitted(Surface s)
{
    return mtl_emitted(s);
}

vec3 bsdf_eval(Surface s, vec3 wi, out float pdf)
{
    return rough_eval(s, roughconductor_material(), wi, pdf);
}

bool bsdf_sample(Surface s, out BsdfSample b)
{
    return rough_sample(s, roughconductor_material(), b);
}
