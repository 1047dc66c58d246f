/*
 * absorbing_glass: glass whose inside absorbs light with Beer-Lambert attenuation, exp(-sigma d),
 * sigma per colour channel in parameters 0-2, per unit of scene length; Ni in 11 (0 means 1.5).
 * The example of the ray payload: a ray entering the solid carries the entry point in
 * payload.xyz and 1 in payload.w; where it leaves, the distance travelled inside is known and the
 * ray leaving is weighted by the absorption along it. Reflections inside keep counting from the
 * last point.
 */
float absorbing_eta(Surface s)
{
    float ni = param(11u) > 0.0 ? param(11u) : 1.5;
    return s.front_face ? ni : 1.0 / ni;
}

uint count_rays(Surface s)
{
    float cos_i = max(-dot(s.incoming, s.normal), 0.0);
    return fresnel_dielectric(cos_i, absorbing_eta(s)) >= 1.0 ? 1u : 2u;
}

void shade(Surface s)
{
    /* Light that crossed the inside to get here was absorbed on the way. */
    vec3 absorbed = vec3(1.0);
    if (!s.front_face && s.payload.w == 1.0)
        absorbed = exp(-param3(0u) * distance(s.position, s.payload.xyz));
    float eta = absorbing_eta(s);
    float cos_i = max(-dot(s.incoming, s.normal), 0.0);
    float reflectance = fresnel_dielectric(cos_i, eta);
    /* A reflection stays on the side it came from: inside, it carries on measuring from here. */
    vec4 reflected_payload = s.front_face ? vec4(0.0) : vec4(s.position, 1.0);
    cast_ray_payload(s, reflect(s.incoming, s.normal), reflectance * absorbed, reflected_payload);
    if (reflectance < 1.0) {
        vec4 refracted_payload = s.front_face ? vec4(s.position, 1.0) : vec4(0.0);
        vec3 refracted = normalize(refract(s.incoming, s.normal, 1.0 / eta));
        cast_ray_payload(s, refracted, (1.0 - reflectance) * absorbed, refracted_payload);
    }
}

/* Path: as glass, one of reflection and refraction chosen by Fresnel (dielectric_sample), with
 * the absorption of the way inside and the payload as above; no emission. */
vec3 emitted(Surface s)
{
    return vec3(0.0);
}

vec3 bsdf_eval(Surface s, vec3 wi, out float pdf)
{
    return black_eval(pdf);
}

bool bsdf_sample(Surface s, out BsdfSample b)
{
    vec3 absorbed = vec3(1.0);
    if (!s.front_face && s.payload.w == 1.0)
        absorbed = exp(-param3(0u) * distance(s.position, s.payload.xyz));
    bool reflected = dielectric_sample(s, absorbing_eta(s), b);
    b.weight *= absorbed;
    /* Inside the solid, the ray carries the point it measures absorption from. */
    bool inside_after = reflected ? !s.front_face : s.front_face;
    set_payload(inside_after ? vec4(s.position, 1.0) : vec4(0.0));
    return true;
}
