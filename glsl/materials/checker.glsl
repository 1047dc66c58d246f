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
