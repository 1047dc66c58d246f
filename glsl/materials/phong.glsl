/*
 * phong: diffuse (Kd times map_Kd) plus a Blinn-Phong highlight of colour Ks (parameters 4-6)
 * and exponent Ns (7). The highlight is normalised, (Ns + 8) / (8 pi) cos^Ns of the half-vector
 * angle, so that a larger exponent makes a smaller, brighter highlight of about the same energy.
 */

uint count_rays(Surface s)
{
    return mtl_see_through_count(s);
}

void shade(Surface s)
{
    float coverage = mtl_see_through(s);
    vec3 kd = mtl_diffuse(s), ks = param3(4u);
    float ns = max(param(7u), 0.0);
    vec3 to_viewer = -s.incoming;
    vec3 sum = kd * ambient_light();
    for (uint i = 0u; i < light_count(); ++i) {
        vec3 to_light, irradiance;
        if (!light_sample(s, i, to_light, irradiance))
            continue;
        vec3 h = normalize(to_light + to_viewer);
        float specular = (ns + 8.0) / (8.0 * PI) * pow(max(dot(s.normal, h), 0.0), ns);
        sum += (kd / PI + ks * specular) * irradiance * dot(s.normal, to_light);
    }
    add_radiance(coverage * (sum + param3(8u)));
}
