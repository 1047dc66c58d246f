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
    add_radiance(diffuse_light(s, mtl_diffuse(s)) + mtl_emission(s));
    cast_ray(s, reflect(s.incoming, s.normal), param3(4u));
}

/* Path: the mirror is a delta lobe of reflectance Ks over the Lambertian base Kd; one of the two
 * is sampled, in proportion to their luminance. */
float mirror_probability(Surface s)
{
    float m = luminance(param3(4u)), d = luminance(mtl_diffuse(s));
    return m + d > 0.0 ? m / (m + d) : 1.0;
}

vec3 emitted(Surface s)
{
    return mtl_emitted(s);
}

vec3 bsdf_eval(Surface s, vec3 wi, out float pdf)
{
    vec3 f = lambert_eval(s, mtl_diffuse(s), wi, pdf);
    pdf *= 1.0 - mirror_probability(s);
    return f;
}

bool bsdf_sample(Surface s, out BsdfSample b)
{
    float p = mirror_probability(s);
    if (random() < p) {
        b.direction = reflect(s.incoming, s.normal);
        b.weight = param3(4u) / p;
        b.pdf = 0.0;
        b.delta = true;
        return dot(b.direction, s.geometric_normal) > 0.0;
    }
    if (!lambert_sample(s, mtl_diffuse(s), b))
        return false;
    b.weight /= 1.0 - p;
    b.pdf *= 1.0 - p;
    return true;
}
