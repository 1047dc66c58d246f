/*
 * textured: diffuse with its albedo from a texture, Kd (parameters 0-2) times map_Kd (texture
 * slot 0), sampled at the hit's uv; map_d (slot 1) or parameter 3 cut the surface out.
 */

uint count_rays(Surface s)
{
    return mtl_see_through_count(s);
}

void shade(Surface s)
{
    float coverage = mtl_see_through(s);
    add_radiance(coverage * (diffuse_light(s, mtl_diffuse(s)) + mtl_emission(s)));
}

/* Path: as diffuse, the albedo Kd times map_Kd. */
vec3 emitted(Surface s)
{
    return mtl_coverage(s) * mtl_emitted(s);
}

vec3 bsdf_eval(Surface s, vec3 wi, out float pdf)
{
    float coverage = mtl_coverage(s);
    vec3 f = lambert_eval(s, mtl_diffuse(s), wi, pdf);
    pdf *= coverage;
    return coverage * f;
}

bool bsdf_sample(Surface s, out BsdfSample b)
{
    if (mtl_pass_through(s, b))
        return true;
    bool ok = lambert_sample(s, mtl_diffuse(s), b);
    b.pdf *= mtl_coverage(s);
    return ok;
}
