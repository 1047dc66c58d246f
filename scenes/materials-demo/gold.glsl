// gold.glsl: a coloured metal (gold by default), written from docs/materials.md.
//
// Material file numbers:
//   0-2  tint: reflectance at normal incidence (F0), e.g. 1.0 0.78 0.34 for gold
//   3    diffuse fraction of the tint for a little matte base (e.g. 0.05)
//   4    Blinn-Phong exponent of the highlight from the scene's lights (e.g. 200)
//
// One reflected ray per hit, weighted by Schlick's Fresnel: the tint face-on,
// turning white at grazing angles as real metals do.

uint count_rays(Surface s)
{
    return 1u;                                       // the mirror reflection
}

void shade(Surface s)
{
    vec3  tint      = param3(0u);
    float matte     = param(3u);
    float shininess = max(param(4u), 1.0);

    vec3  view_dir  = -s.incoming;                   // towards the viewer
    float cos_v     = max(dot(s.normal, view_dir), 0.0);

    // Schlick's approximation of conductor Fresnel, per channel.
    vec3 fresnel = tint + (vec3(1.0) - tint) * pow(1.0 - cos_v, 5.0);

    // A little Lambertian base, lit by all lights (ambient included).
    add_radiance(diffuse_light(s, matte * tint));

    // Highlights of the point and spot lights: normalised Blinn-Phong, tinted.
    for (uint i = 0u; i < light_count(); ++i) {
        vec3 to_light, irradiance;
        if (!light_sample(s, i, to_light, irradiance))
            continue;                                // ambient, behind, or shadowed
        vec3  h     = normalize(to_light + view_dir);
        float cos_l = max(dot(s.normal, to_light), 0.0);
        float spec  = (shininess + 8.0) / (8.0 * PI) * pow(max(dot(s.normal, h), 0.0), shininess);
        add_radiance(fresnel * spec * irradiance * cos_l);
    }

    // The reflection itself carries the (Fresnel-weighted) tint.
    cast_ray(s, reflect(s.incoming, s.normal), fresnel);
}
