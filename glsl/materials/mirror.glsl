/*
 * mirror: a perfect mirror of reflectance Ks (parameters 4-6) over a diffuse base Kd (0-2), as
 * .mtl illum 3 and 5 describe. One reflected ray per hit.
 */

uint count_rays(Surface s)
{
    return 1u;
}

void shade(Surface s)
{
    add_radiance(diffuse_light(s, mtl_diffuse(s)) + param3(8u));
    cast_ray(s, reflect(s.incoming, s.normal), param3(4u));
}
