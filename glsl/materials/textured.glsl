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
    add_radiance(coverage * (diffuse_light(s, mtl_diffuse(s)) + param3(8u)));
}
