/*
 * roughdielectric: rough glass: a GGX microfacet boundary of index Ni (parameter 11; 0 means 1.5)
 * that reflects and refracts (Walter et al. 2007, lib/microfacet.glsl), transmission tinted by Tf
 * (12-14; all 0 means clear), roughness in 16 (GGX alpha = roughness^2; below 0.02 the smooth
 * glass's delta lobes, so roughness 0 is @glass). Entering or leaving is read from front_face,
 * as glass does: the OBJ's winding must face out of the solid.
 * Whitted: one ray per hit, reflected or refracted as the BSDF samples it (so rough glass is
 * noisy where smooth glass is not), plus highlights of the lights by light_sample.
 */
RoughMaterial roughdielectric_material(Surface s)
{
    return RoughMaterial(vec3(0.0), vec3(0.0), vec3(0.0), mtl_transmission_filter(), 0.0,
                         mtl_dielectric_eta(s), ggx_alpha(param(16u)), true);
}

uint count_rays(Surface s)
{
    return 1u;
}

void shade(Surface s)
{
    rough_whitted_shade(s, roughdielectric_material(s), 1.0);
    add_radiance(param3(8u));
}

vec3 emitted(Surface s)
{
    return mtl_emitted(s);
}

vec3 bsdf_eval(Surface s, vec3 wi, out float pdf)
{
    return rough_eval(s, roughdielectric_material(s), wi, pdf);
}

bool bsdf_sample(Surface s, out BsdfSample b)
{
    return rough_sample(s, roughdielectric_material(s), b);
}
