/*
 * emissive: a surface that only gives light, Ke (parameters 8-10), as seen by the camera and by
 * reflections, and lighting other surfaces from its front face: both integrators sample the
 * emissive triangles as area lights (lib/emitters.glsl).
 */
uint count_rays(Surface s)
{
    return 0u;
}

void shade(Surface s)
{
    add_radiance(mtl_emission(s));
}

/* Path: Ke from the front face; a black BSDF. */
vec3 emitted(Surface s)
{
    return mtl_emitted(s);
}

vec3 bsdf_eval(Surface s, vec3 wi, out float pdf)
{
    return black_eval(pdf);
}

bool bsdf_sample(Surface s, out BsdfSample b)
{
    return false;
}
