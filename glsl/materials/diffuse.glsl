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
    add_radiance(coverage * (diffuse_light(s, param3(0u)) + param3(8u)));
}
