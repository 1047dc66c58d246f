/*
 * checker: a procedural material, no texture needed: a 3D checkerboard of two diffuse albedos,
 * parameters 0-2 and 4-6, with squares of size parameter 8 (0 means 1) in world space, so it
 * works on any mesh, with or without uvs.
 */
uint count_rays(Surface s)
{
    return 0u;
}

void shade(Surface s)
{
    float size = param(8u) > 0.0 ? param(8u) : 1.0;
    /* Nudge into the surface so a face lying on a square boundary does not flicker. */
    ivec3 cell = ivec3(floor((s.position - 1e-4 * s.geometric_normal) / size));
    bool odd = ((cell.x + cell.y + cell.z) & 1) != 0;
    add_radiance(diffuse_light(s, odd ? param3(4u) : param3(0u)));
}

/* Path: a Lambertian lobe of the square's albedo; no emission. */
vec3 checker_albedo(Surface s)
{
    float size = param(8u) > 0.0 ? param(8u) : 1.0;
    ivec3 cell = ivec3(floor((s.position - 1e-4 * s.geometric_normal) / size));
    return ((cell.x + cell.y + cell.z) & 1) != 0 ? param3(4u) : param3(0u);
}

vec3 emitted(Surface s)
{
    return vec3(0.0);
}

vec3 bsdf_eval(Surface s, vec3 wi, out float pdf)
{
    return lambert_eval(s, checker_albedo(s), wi, pdf);
}

bool bsdf_sample(Surface s, out BsdfSample b)
{
    return lambert_sample(s, checker_albedo(s), b);
}
