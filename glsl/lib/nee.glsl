/*
 * nee.glsl: the path tracer's direct light at a hit (next-event estimation; lib/path.glsl says
 * which lights and how they are weighted), the light kernel's work under the path integrator.
 * Each light sample whose BSDF value is not zero casts a shadow ray here, and what gets through is
 * added to the pixel at once, weighted by the path's throughput: the path carries on in
 * shade.comp with its own BSDF sample. The last depth has none: its rays only find the light
 * their BSDF samples hit (src/render/renderer.c says why). Included by light.comp after the
 * generated material module.
 */
#ifndef VKRT_NEE_GLSL
#define VKRT_NEE_GLSL

#include "path.glsl"
#include "traverse.glsl"

/* Whether nothing blocks the way from s along wi for tmax. */
bool unoccluded(Surface s, vec3 wi, float tmax)
{
    return !trace_any(surface_origin(s, wi), wi, 0.0, tmax);
}

/* Whether nothing blocks the way from s (leaving towards wi) to the point `to` on a light: the
 * shadow ray starts at s's offset origin and ends short of `to` by a relative margin far above
 * the rounding of its length, so it does not find the light's own triangle. */
bool unoccluded_to(Surface s, vec3 wi, vec3 to)
{
    vec3 origin = surface_origin(s, wi);
    vec3 d = to - origin;
    float len = length(d);
    return len > 0.0 && !trace_any(origin, d / len, 0.0, len * (1.0 - 1e-4));
}

/* The direct light reaching the eye through the vertex at s, per unit throughput. */
vec3 direct_light(Surface s, uint shader, inout uint shadow_rays)
{
    vec3 sum = vec3(0.0);
    /* Delta lights: no other way to find them, so every one is sampled. Ambient light is
     * Whitted's stand-in for indirect light, which the path tracer computes: not sampled. */
    for (uint i = 0u; i < frame.counts.y; ++i) {
        vec3 to_light, irradiance, origin, direction;
        float distance_to_light, tmax, pdf;
        if (!light_geometry(s, i, to_light, distance_to_light, irradiance))
            continue;
        vec3 f = material_bsdf_eval(shader, s, to_light, pdf);
        if (all(equal(f, vec3(0.0))))
            continue;
        shadow_ray(s, i, to_light, origin, direction, tmax);
        ++shadow_rays;
        if (!trace_any(origin, direction, 0.0, tmax))
            sum += f * irradiance;
    }
    if (LIGHT_SAMPLING == VKRT_SAMPLING_BSDF)
        return sum;
    if (light_info.emitter_count > 0u) {
        Surface light;
        vec3 wi;
        float dist, pdf_light, pdf_bsdf;
        vec3 u = vec3(path_1d(vkrt_ray, SAMPLER_DIM_EMITTER_CHOICE),
                      path_2d(vkrt_ray, SAMPLER_DIM_EMITTER_POINT));
        if (sample_emitter(s, u, light, wi, dist, pdf_light)) {
            vkrt_material = light.material;
            vec3 le = material_emitted(materials[light.material].info.x, light);
            vkrt_material = s.material;
            vec3 f = material_bsdf_eval(shader, s, wi, pdf_bsdf);
            if (any(greaterThan(f * le, vec3(0.0)))) {
                ++shadow_rays;
                if (unoccluded_to(s, wi, light.position))
                    sum += f * le * (light_sample_weight(pdf_light, pdf_bsdf) / pdf_light);
            }
        }
    }
    if (light_info.environment_sampled != 0u) {
        float pdf_env, pdf_bsdf;
        vec3 wi = sample_environment(path_2d(vkrt_ray, SAMPLER_DIM_ENVIRONMENT), pdf_env);
        vec3 f = material_bsdf_eval(shader, s, wi, pdf_bsdf);
        /* A sample straight up or down of a map has pdf 0 (sin(theta) = 0: envmap_pdf): no sample
         * at all, not 0 / 0 (a NaN in the pixel). */
        if (pdf_env > 0.0 && any(greaterThan(f, vec3(0.0)))) {
            vec3 le = environment_radiance(wi, vkrt_ray.payload);
            if (any(greaterThan(le, vec3(0.0)))) {
                ++shadow_rays;
                if (unoccluded(s, wi, FAR))
                    sum += f * le * (light_sample_weight(pdf_env, pdf_bsdf) / pdf_env);
            }
        }
    }
    return sum;
}

/* Next-event estimation at the hit of ray index: its direct light added to its pixel; returns
 * the shadow rays it traced. */
uint nee_at(uint index)
{
    uint shadow_rays = 0u;
    Ray ray = load_ray(index);
    Hit hit = hits[index];
    if (!ray_is_dead(ray) && hit.triangle != VKRT_NO_HIT && frame.wave.y < frame.wave.z) {
        Surface s = surface_at(ray, hit);
        vkrt_material = s.material;
        vkrt_ray_index = index;
        vkrt_ray = ray;
        vkrt_rng = light_stream(ray);
        vkrt_dimension = SAMPLER_BSDF_DIMS; /* the BSDF block is shade.comp's */
        vec3 direct = direct_light(s, materials[s.material].info.x, shadow_rays);
        add_finite_to_pixel(ray, ray_throughput(ray) * direct);
    }
    return shadow_rays;
}

#endif
