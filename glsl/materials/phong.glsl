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
    add_radiance(coverage * (sum + mtl_emission(s)));
}

/* Path: the same BRDF, kd / pi + ks (Ns + 8) / (8 pi) cos^Ns(n.h), sampled as a mixture of the
 * cosine lobe and the half-vector lobe cos^Ns (density (Ns + 1) / (2 pi) cos^Ns per half-vector,
 * / (4 |wo.h|) per direction), chosen in proportion to the luminance of kd and ks. */
float phong_specular_probability(vec3 kd, vec3 ks)
{
    float d = luminance(kd), k = luminance(ks);
    return d + k > 0.0 ? k / (d + k) : 0.0;
}

vec3 emitted(Surface s)
{
    return mtl_coverage(s) * mtl_emitted(s);
}

vec3 bsdf_eval(Surface s, vec3 wi, out float pdf)
{
    pdf = 0.0;
    float c = dot(wi, s.normal);
    if (c <= 0.0 || dot(wi, s.geometric_normal) <= 0.0)
        return vec3(0.0);
    vec3 kd = mtl_diffuse(s), ks = param3(4u);
    float ns = max(param(7u), 0.0);
    vec3 wo = -s.incoming;
    vec3 h = normalize(wi + wo);
    float nh = max(dot(s.normal, h), 0.0);
    float lobe = pow(nh, ns);
    float ps = phong_specular_probability(kd, ks);
    float coverage = mtl_coverage(s);
    pdf = coverage * ((1.0 - ps) * c / PI +
                      ps * (ns + 1.0) / (2.0 * PI) * lobe / (4.0 * max(dot(wo, h), 1e-8)));
    return coverage * (kd / PI + ks * (ns + 8.0) / (8.0 * PI) * lobe) * c;
}

bool bsdf_sample(Surface s, out BsdfSample b)
{
    if (mtl_pass_through(s, b))
        return true;
    vec3 kd = mtl_diffuse(s), ks = param3(4u);
    float ns = max(param(7u), 0.0);
    float ps = phong_specular_probability(kd, ks);
    if (random() < ps) {
        /* The half-vector about the normal, cos^Ns distributed. */
        vec2 u = random2();
        float cos_h = pow(u.x, 1.0 / (ns + 1.0));
        float sin_h = sqrt(max(0.0, 1.0 - cos_h * cos_h)), phi = 2.0 * PI * u.y;
        vec3 t = normalize(abs(s.normal.x) > 0.5 ? cross(s.normal, vec3(0.0, 1.0, 0.0))
                                                 : cross(s.normal, vec3(1.0, 0.0, 0.0)));
        vec3 h = sin_h * cos(phi) * t + sin_h * sin(phi) * cross(s.normal, t) + cos_h * s.normal;
        b.direction = reflect(s.incoming, h);
    } else {
        vec2 u = random2();
        b.direction = cosine_direction(s.normal, u.x, u.y);
    }
    b.delta = false;
    float pdf;
    vec3 f_cos = bsdf_eval(s, b.direction, pdf);
    /* bsdf_eval scales by coverage; the pass-through above already took the uncovered part. */
    float coverage = mtl_coverage(s);
    b.pdf = pdf;
    b.weight = pdf > 0.0 ? f_cos / pdf : vec3(0.0);
    return pdf > 0.0 && coverage > 0.0;
}
