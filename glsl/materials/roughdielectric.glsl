/*
 * roughdielectric: rough glass: a GGX microfacet boundary of index Ni (parameter 11; 0 means 1.5)
 * that reflects and refracts (Walter et al. 2007, lib/microfacet.glsl), transmission tinted by Tf
 * (12-14; all 0 means clear), roughness in 16 (GGX alpha = roughness^2; below 0.02 the smooth
 * glass's delta lobes, so roughness 0 is @glass). Entering or leaving is read from front_face,
 * as glass does: the OBJ's winding must face out of the solid.
 * Numbers 18 and 19 put a clear coat on its front face (weight, roughness; lib/microfacet.glsl).
 * Whitted: one ray per hit, reflected or refracted as the BSDF samples it (so rough glass is
 * noisy where smooth glass is not), plus highlights of the lights by light_sample.
 * The entry points (count_rays, shade, emitted, bsdf_eval, bsdf_sample) are ROUGH_BUILTIN's.
 */
RoughMaterial roughdielectric_material(Surface s)
{
    return RoughMaterial(vec3(0.0), vec3(0.0), vec3(0.0), mtl_transmission_filter(), 0.0,
                         mtl_dielectric_eta(s), ggx_alpha(mtl_roughness(s)), true, 0.0,
                         PLASTIC_NO_TABLE, 0.0);
}

ROUGH_BUILTIN(roughdielectric_material)
