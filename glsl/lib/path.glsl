/*
 * path.glsl: the path tracer's vertex (docs/architecture.md, "The path integrator"): what the
 * next-event kernel (nee.comp), count.comp and shade.comp share. A path is a chain of rays of
 * the wavefront; a ray carries the throughput to its pixel in importance.rgb and, in
 * importance.w, the solid-angle pdf of the BSDF sample that cast it (0 for camera rays and delta
 * lobes: an emitter such a ray hits is counted in full, since no light sample could find it).
 *
 * Direct light at each vertex is next-event estimation: every delta light (point, spot,
 * directional) once, one emissive triangle from the alias table, and the environment once, each
 * with a shadow ray; emitters and environment are also found by the BSDF's own rays, and the two
 * strategies are weighted by Veach's power heuristic (LIGHT_SAMPLING picks one alone, for tests).
 * Russian roulette ends a path with probability 1 - min(throughput's largest channel, 0.95) at
 * every vertex from depth ROULETTE_DEPTH on, and the survivors carry 1 / survival, so the
 * estimate stays unbiased up to max-depth. Included after the generated material module.
 */
#ifndef VKRT_PATH_GLSL
#define VKRT_PATH_GLSL

#include "environment.glsl"
#include "pixel.glsl"

/* Rays of this depth and deeper play Russian roulette before casting their continuation (depth 0
 * is the camera ray: its hit is the path's first vertex). */
const uint ROULETTE_DEPTH = 3u;

/* The random streams of a vertex, apart from the material's own (random(), keyed by the ray's
 * seed): light sampling and roulette each hash the seed with a key of their own. */
uint light_stream(Ray ray)
{
    return pcg_hash(ray.info.y ^ 0x6C8E9CF5u);
}

/* The probability that the path of ray carries on past its hit, and whether it does: the same
 * answer in count.comp (which reserves the slot) and shade.comp (which fills it). */
float path_survival(Ray ray)
{
    if (ray.info.z < ROULETTE_DEPTH)
        return 1.0;
    return min(max(ray.importance.r, max(ray.importance.g, ray.importance.b)), 0.95);
}

bool path_continues(Ray ray)
{
    float q = path_survival(ray);
    return q >= 1.0 || rng_float(pcg_hash(ray.info.y ^ 0x2F6B1A3Du)) < q;
}

/* Veach's power heuristic for a sample of pdf a against the other strategy's b. */
float power_heuristic(float a, float b)
{
    a *= a;
    b *= b;
    return a + b > 0.0 ? a / (a + b) : 0.0;
}

/* The weight of a light sample of pdf pl against the BSDF's pb, and of a BSDF sample of pdf pb
 * that found a light of pdf pl, for the sampling LIGHT_SAMPLING asks. */
float light_sample_weight(float pl, float pb)
{
    return LIGHT_SAMPLING == VKRT_SAMPLING_MIS ? power_heuristic(pl, pb) : 1.0;
}

float bsdf_sample_weight(float pb, float pl)
{
    if (pl <= 0.0)
        return 1.0; /* no light sample could have found it */
    if (LIGHT_SAMPLING == VKRT_SAMPLING_LIGHTS)
        return 0.0;
    return LIGHT_SAMPLING == VKRT_SAMPLING_MIS ? power_heuristic(pb, pl) : 1.0;
}

/* ---- Emissive triangles -------------------------------------------------------------------- */

/* The solid-angle density with which a light sample from distance `dist` finds a point of an
 * emissive triangle of material m seen at cosine cos_light: the triangle was chosen in
 * proportion to its power and the point uniformly on it, so the density per area is
 * luminance(Ke) / total power (glsl/shared.h LightInfo). */
float emitter_pdf(uint m, float dist, float cos_light)
{
    if (light_info.emitter_count == 0u || cos_light <= 0.0)
        return 0.0;
    vec3 ke = vec3(materials[m].params[2].x, materials[m].params[2].y, materials[m].params[2].z);
    return luminance(ke) / light_info.emitter_power * dist * dist / cos_light;
}

/* A point on an emissive triangle for the vertex at s: the alias table picks the triangle, u.yz
 * a point on it uniformly. Fills the surface of the light there (as seen along the sample's
 * direction), the unit direction to it, the distance and the solid-angle pdf; false when the
 * triangle turns its back to s. */
bool sample_emitter(Surface s, vec3 u, out Surface light, out vec3 wi, out float dist,
                    out float pdf)
{
    uint n = light_info.emitter_count;
    float x = u.x * float(n);
    uint i = min(uint(x), n - 1u);
    if (x - float(i) >= emitters[i].keep)
        i = emitters[i].alias;
    uint tri = emitters[i].triangle;
    Triangle t = triangles[tri];
    /* Uniform on the triangle (pbrt's square-root mapping): barycentrics of v1 and v2. */
    float r = sqrt(u.y);
    float b1 = r * (1.0 - u.z), b2 = r * u.z;
    vec3 p = (1.0 - b1 - b2) * t.v0.xyz + b1 * t.v1.xyz + b2 * t.v2.xyz;
    vec3 d = p - s.position;
    dist = length(d);
    wi = d / dist;
    vec3 ng = triangle_normal(t.v0.xyz, t.v1.xyz, t.v2.xyz);
    float cos_light = -dot(wi, ng);
    Ray towards;
    towards.origin = vec4(s.position, 0.0);
    towards.direction = vec4(wi, dist);
    towards.importance = vec4(0.0);
    towards.info = uvec4(0u);
    towards.payload = vec4(0.0);
    light = surface_at(towards, Hit(dist, b1, b2, tri));
    pdf = emitter_pdf(light.material, dist, cos_light);
    return pdf > 0.0 && dist > 0.0;
}

/* ---- The environment ------------------------------------------------------------------------ */

/* The solid-angle density with which a light sample finds direction d of the environment: the
 * map's importance (lib/envmap.glsl), or uniform over the sphere for a constant or a shader's sky. */
float environment_pdf(vec3 d)
{
    if (light_info.environment_sampled == 0u)
        return 0.0;
    if (light_info.environment_width > 0u)
        return envmap_pdf(light_info, d);
    return 1.0 / (4.0 * PI);
}

/* A direction of the environment for a light sample, and its solid-angle pdf (0: none). */
vec3 sample_environment(vec2 u, out float pdf)
{
    if (light_info.environment_width > 0u) {
        float pdf_uv;
        vec2 uv = envmap_sample(light_info, u, pdf_uv);
        vec3 d = envmap_direction(uv, light_info.environment_rotate);
        float sin_theta = sqrt(d.x * d.x + d.z * d.z);
        pdf = sin_theta > 0.0 ? pdf_uv / (2.0 * PI * PI * sin_theta) : 0.0;
        return d;
    }
    float z = 1.0 - 2.0 * u.x;
    float r = sqrt(max(0.0, 1.0 - z * z)), phi = 2.0 * PI * u.y;
    pdf = 1.0 / (4.0 * PI);
    return vec3(r * cos(phi), r * sin(phi), z);
}

#endif
