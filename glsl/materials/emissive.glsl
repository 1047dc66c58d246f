/*
 * emissive: a surface that only gives light, Ke (parameters 8-10), as seen by the camera and by
 * reflections. It does not light other surfaces: vkrt lights scenes with its light sources
 * (scene.cfg), and an emissive surface shows where they are.
 */
uint count_rays(Surface s)
{
    return 0u;
}

void shade(Surface s)
{
    add_radiance(param3(8u));
}
