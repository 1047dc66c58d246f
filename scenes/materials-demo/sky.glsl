// sky.glsl: an environment shader, a sky gradient by direction with a sun glow.
//
// Material file numbers:
//   0-2  horizon radiance
//   3-5  zenith radiance
//   6-8  ground radiance (directions below the horizon)
//   9-11 direction towards the sun (need not be unit length)
//   12   sun glow strength (0: none)

vec3 environment(vec3 direction, vec4 payload)
{
    vec3 d = normalize(direction);
    vec3 sky;
    if (d.y >= 0.0) {
        // Horizon to zenith; sqrt keeps the horizon band narrow.
        sky = mix(param3(0u), param3(3u), sqrt(d.y));
    } else {
        // Below the horizon: fade quickly from the horizon colour to the ground.
        sky = mix(param3(0u), param3(6u), clamp(-d.y * 8.0, 0.0, 1.0));
    }
    // A soft glow around the sun direction.
    vec3 sun = param3(9u);
    if (dot(sun, sun) > 0.0) {
        float c = max(dot(d, normalize(sun)), 0.0);
        sky += param(12u) * vec3(1.0, 0.9, 0.7) * pow(c, 64.0);
    }
    return sky;   // the payload is not used here
}
