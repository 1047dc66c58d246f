// stripes.glsl: a procedural, rim-lit, glossy material of my own, written from
// docs/materials.md. It exercises s.position, s.normal, s.incoming, s.payload and random().
//
// Material file numbers:
//   0-2   colour A of the stripes
//   3-5   colour B of the stripes
//   6     stripes per metre (world space, along a tilted axis)
//   7-9   rim-light colour (radiance added at grazing angles, like a back light)
//   10    rim exponent (larger: thinner rim)
//   11    glossy coat reflectance (grey), 0 for no coat
//   12    glossy roughness: how far the reflected rays scatter (0: mirror)
//   13    glossy rays from a camera ray's hit (1..16)
//
// The payload: payload.x is 1 on rays this shader cast. A hit reached by such a ray
// casts only one glossy ray instead of param(13), so inter-reflections between
// striped objects do not multiply the ray count at every bounce.

// Helper names share one namespace with the scene's other shaders: prefixed.
uint stripes_ray_count(Surface s)
{
    if (param(11u) <= 0.0)
        return 0u;                                   // no coat, no rays
    if (s.payload.x > 0.5)
        return 1u;                                   // already a glossy ray: one is enough
    return uint(clamp(param(13u), 1.0, 16.0));
}

uint count_rays(Surface s)
{
    return stripes_ray_count(s);                     // no random() here, so shade need not match
}

void shade(Surface s)
{
    // Procedural stripes from the world position, along a tilted axis.
    vec3  axis   = normalize(vec3(0.3, 1.0, 0.2));
    float t      = dot(s.position, axis) * param(6u);
    float band   = smoothstep(0.4, 0.6, abs(fract(t) * 2.0 - 1.0));  // soft-edged 0/1 bands
    vec3  albedo = mix(param3(0u), param3(3u), band);

    float coat = param(11u);
    // Lambertian base under the coat (what the coat does not reflect).
    add_radiance(diffuse_light(s, (1.0 - coat) * albedo));

    // Rim light: strongest where the surface is seen edge-on.
    float facing = max(dot(s.normal, -s.incoming), 0.0);
    add_radiance(param3(7u) * pow(1.0 - facing, max(param(10u), 1.0)));

    // Glossy coat: n rays around the mirror direction, each 1/n of the reflectance.
    uint n = stripes_ray_count(s);
    if (n == 0u)
        return;
    vec3  mirror    = reflect(s.incoming, s.normal);
    float roughness = param(12u);
    for (uint k = 0u; k < n; ++k) {
        // A random point in the unit ball (rejection-free: direction times cbrt of radius).
        float z   = 2.0 * random() - 1.0;
        float phi = 2.0 * PI * random();
        float r   = pow(random(), 1.0 / 3.0);
        vec3  ball = r * vec3(sqrt(1.0 - z * z) * cos(phi), sqrt(1.0 - z * z) * sin(phi), z);
        vec3  dir  = normalize(mirror + roughness * ball);
        if (dot(dir, s.geometric_normal) <= 0.0)
            dir = mirror;                            // would go into the surface: use the mirror ray
        cast_ray_payload(s, dir, vec3(coat / float(n)), vec4(1.0, 0.0, 0.0, 0.0));
    }
}
