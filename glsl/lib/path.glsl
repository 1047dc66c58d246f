/*
 * path.glsl: the path tracer's vertex (docs/architecture.md, "The path integrator"): what the
 * next-event kernel (nee.comp), count.comp and shade.comp share. A path is a chain of rays of
 * the wavefront; a ray carries the throughput to its pixel (ray_throughput) and the solid-angle
 * pdf of the BSDF sample that cast it (ray_bsdf_pdf; 0 for camera rays and delta lobes: an
 * emitter such a ray hits is counted in full, since no light sample could find it).
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

#include "emitters.glsl"
#include "environment.glsl"
#include "mis.glsl"
#include "pixel.glsl"

/* Rays of this depth and deeper play Russian roulette before casting their continuation (depth 0
 * is the camera ray: its hit is the path's first vertex). 4 is Mitsuba 3's default (its rr_depth
 * 5 counts the vertex after the bounce): starting earlier ends too many of the long paths that
 * caustics through several glass surfaces need, and costs more error than it saves time
 * (docs/speed-vs-accuracy.md). */
const uint ROULETTE_DEPTH = 4u;

/* The numbers of a vertex come from the sampler (lib/sampler.glsl), each use at its own
 * dimension of the ray's depth block (SAMPLER_DIM_*); the material's random() takes the BSDF
 * block in shade.comp. A random() anywhere else (a shader's bsdf_eval, say, which should not
 * draw) walks this hash stream instead, so it never repeats a number the sampler gave out. */
uint light_stream(Ray ray)
{
    return pcg_hash(ray_seed(ray) ^ 0x6C8E9CF5u);
}

/* Dimension `dimension` (SAMPLER_DIM_*) of ray's depth block, and the stratified pair that starts
 * at the even `dimension`: what a vertex's light samples and roulette draw. */
float path_1d(Ray ray, uint dimension)
{
    return sampler_1d(ray, frame.counts.w, dimension);
}

vec2 path_2d(Ray ray, uint dimension)
{
    return sampler_2d(ray, frame.counts.w, dimension);
}

/* The probability that the path of ray carries on past its hit, and whether it does: the same
 * answer in count.comp (which reserves the slot) and shade.comp (which fills it). */
float path_survival(Ray ray)
{
    if (ray_depth(ray) < ROULETTE_DEPTH)
        return 1.0;
    vec3 throughput = ray_throughput(ray);
    return min(max(throughput.r, max(throughput.g, throughput.b)), 0.95);
}

bool path_continues(Ray ray)
{
    float q = path_survival(ray);
    return q >= 1.0 || path_1d(ray, SAMPLER_DIM_ROULETTE) < q;
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
