/*
 * diffuse: a Lambertian surface of albedo Kd (parameters 0-2), lit by the scene's lights, with
 * Ke (8-10) emitted and parameter 3 as transparency. Casts no rays of its own.
 *
 * The smallest useful material: one function says how many rays a hit casts, the other adds the
 * light the surface sends back to the viewer.
 */

uint count_rays(Surface s)
{
    return mtl_see_through_count(s);
}

void shade(Surface s)
{
    float coverage = mtl_see_through(s);
    add_radiance(coverage * (diffuse_light(s, param3(0u)) + mtl_emission(s)));
}

/* Path: Ke from the front face; a Lambertian lobe of albedo Kd, cut out by coverage. */
vec3 emitted(Surface s)
{
    return mtl_coverage(s) * mtl_emitted(s);
}

vec3 bsdf_eval(Surface s, vec3 wi, out float pdf)
{
    float coverage = mtl_coverage(s);
    vec3 f = lambert_eval(s, param3(0u), wi, pdf);
    pdf *= coverage;
    return coverage * f;
}

bool bsdf_sample(Surface s, out BsdfSample b)
{
    if (mtl_pass_through(s, b))
        return true;
    bool ok = lambert_sample(s, param3(0u), b);
    b.pdf *= mtl_coverage(s);
    return ok;
}
