/*
 * roughplastic: a Lambertian base of albedo Kd times map_Kd (parameters 0-2, texture slot 0)
 * under a GGX dielectric coat of index Ni (11; 0 means 1.5) whose reflection is scaled by Ks
 * (4-6; 1 1 1 is a plain coat), roughness in 16 (GGX alpha = roughness^2; below 0.02 a smooth
 * coat). Mitsuba 3's `roughplastic` (nonlinear false): the base sees the rough coat's
 * transmittance in and out and its internal reflectance, from the tables the host makes for the
 * scene's indices and roughnesses (Material.maps.w; lib/microfacet.glsl, plastic_diffuse); under
 * a smooth coat, Mitsuba's smooth `plastic`.
 * Numbers 18 and 19 put a clear coat over it (weight, roughness; lib/microfacet.glsl): with Ks 0
 * and Ni 1 (no Fresnel of its own) the base is exactly Lambertian, so that is a coated diffuse.
 * Number 20 is a sheen beside the base (Disney's; lib/microfacet.glsl, "The sheen").
 * Whitted: the lights through the whole BSDF by light_sample, the ambient light on the base, and
 * one glossy reflection ray from the coat.
 * The entry points (count_rays, shade, emitted, bsdf_eval, bsdf_sample) are ROUGH_BUILTIN's.
 */
RoughMaterial roughplastic_material(Surface s)
{
    float ni = param(11u) > 0.0 ? param(11u) : 1.5;
    RoughMaterial m = RoughMaterial(mtl_diffuse(s), param3(4u), vec3(0.0), vec3(1.0), 0.0, ni,
                                    ggx_alpha(mtl_roughness(s)), false, mtl_sheen(s),
                                    PLASTIC_NO_TABLE, 0.0);
    plastic_find_row(m);
    return m;
}

ROUGH_BUILTIN(roughplastic_material)
