/*
 * glass: a smooth dielectric of index of refraction Ni (parameter 11; 0 means 1.5) whose
 * transmitted light is tinted by Tf (12-14; all 0 means clear). A hit casts the reflected ray,
 * weighted by the Fresnel reflectance, and the refracted one, weighted by the rest, both at once
 * (as a Whitted ray tracer does, so glass is noise-free); past the critical angle only the
 * reflection (total internal reflection). Entering or leaving is read from front_face: the OBJ's
 * winding must face out of the solid.
 */
uint count_rays(Surface s)
{
    float cos_i = -dot(s.incoming, s.normal);
    return fresnel_dielectric(max(cos_i, 0.0), mtl_dielectric_eta(s)) >= 1.0 ? 1u : 2u;
}

void shade(Surface s)
{
    float eta = mtl_dielectric_eta(s);
    float cos_i = max(-dot(s.incoming, s.normal), 0.0);
    float reflectance = fresnel_dielectric(cos_i, eta);
    cast_ray(s, reflect(s.incoming, s.normal), vec3(reflectance));
    if (reflectance < 1.0) {
        vec3 refracted = refract(s.incoming, s.normal, 1.0 / eta);
        cast_ray(s, normalize(refracted), (1.0 - reflectance) * mtl_transmission_filter());
    }
    add_radiance(mtl_emission(s));
}

/* Path: reflection or refraction, one chosen by the Fresnel reflectance (dielectric_sample), the
 * refracted light tinted; both are delta lobes, so there is nothing to evaluate. */
bool bsdf_sample(Surface s, out BsdfSample b)
{
    if (!dielectric_sample(s, mtl_dielectric_eta(s), b))
        b.weight *= mtl_transmission_filter();
    return true;
}

vec3 bsdf_eval(Surface s, vec3 wi, out float pdf)
{
    return black_eval(pdf);
}

vec3 emitted(Surface s)
{
    return mtl_emitted(s);
}
