/*
 * shade.comp: runs every hit's material shader (and the environment shader for rays that missed):
 * the radiance it adds goes to the ray's pixel with a float atomic add, the rays it casts go into
 * the slots count.comp reserved. Slots a shader leaves unused are filled with dead rays, so the
 * next trace needs no compaction to stay correct. The path integrator's version of a hit is
 * shade_path below (lib/path.glsl): the emitted light the ray finds, weighted against light
 * sampling, and one continuation drawn from the BSDF. Which one runs is the INTEGRATOR
 * specialization constant.
 */
#include "generated/materials.glsl"
#include "lib/environment.glsl"
#include "lib/path.glsl"
#include "lib/pixel.glsl"

/* The light ray finds where it ends (an emitter it hits, or the environment it escapes to),
 * weighted against the light sample of the vertex it came from. */
vec3 found_light(Ray ray, Hit hit, Surface s)
{
    /* Camera rays and delta lobes carry pdf 0: no light sample could have found this. */
    float pdf_bsdf = ray_bsdf_pdf(ray);
    if (hit.triangle == VKRT_NO_HIT) {
        vec3 le = environment_radiance(ray.direction.xyz, ray.payload);
        return pdf_bsdf > 0.0 ? le * bsdf_sample_weight(pdf_bsdf, environment_pdf(ray.direction.xyz))
                              : le;
    }
    vec3 le = material_emitted(materials[s.material].info.x, s);
    if (pdf_bsdf <= 0.0 || all(equal(le, vec3(0.0))))
        return le;
    float cos_light = abs(dot(ray.direction.xyz, s.geometric_normal));
    return le * bsdf_sample_weight(pdf_bsdf, emitter_pdf(s.material, hit.t, cos_light));
}

void shade_path(uint index, Ray ray, Hit hit)
{
    vkrt_radiance = vec3(0.0);
    Surface s;
    if (hit.triangle == VKRT_NO_HIT) {
        vkrt_material = VKRT_ENVIRONMENT_MATERIAL;
    } else {
        s = surface_at(ray, hit);
        vkrt_material = s.material;
    }
    add_finite_to_pixel(ray, ray_throughput(ray) * found_light(ray, hit, s));
    uvec2 slots = ray_slots[index];
    /* count.comp reserved one slot when the path carries on (never at the last depth). */
    if (hit.triangle == VKRT_NO_HIT || frame.wave.y >= frame.wave.z || slots.y == 0u ||
        slots.x >= frame.wave.w)
        return;
    Ray child = ray_dead(ray);
    BsdfSample b;
    vkrt_child_payload = ray.payload;
    if (material_bsdf_sample(materials[s.material].info.x, s, b) &&
        any(greaterThan(b.weight, vec3(0.0)))) {
        child = ray_cast(ray, 0u, surface_origin(s, b.direction), b.direction,
                         ray_throughput(ray) * b.weight / path_survival(ray),
                         b.delta ? 0.0 : b.pdf, vkrt_child_payload);
        surface_cast_cone(s, child, b.delta ? 0.0 : b.pdf); /* texture filtering */
    }
    store_child_ray(slots.x, child);
}

/* Whitted's hit: the material's shade adds radiance and casts its own rays into its slots. */
void shade_whitted(uint index, Ray ray, Hit hit)
{
    if (hit.triangle == VKRT_NO_HIT) {
        vkrt_material = VKRT_ENVIRONMENT_MATERIAL;
        vkrt_radiance = environment_radiance(ray.direction.xyz, ray.payload);
    } else {
        Surface s = surface_at(ray, hit);
        uvec2 slots = ray_slots[index];
        vkrt_material = s.material;
        vkrt_casting = true;
        vkrt_cast_first = slots.x;
        /* At the last depth count.comp did not run: nothing is reserved, casts end there. */
        vkrt_cast_reserved = frame.wave.y < frame.wave.z ? slots.y : 0u;
        vkrt_cast_done = 0u;
        material_shade(materials[s.material].info.x, s);
        Ray dead = ray_dead(ray);
        for (uint k = vkrt_cast_done; k < vkrt_cast_reserved; ++k)
            if (vkrt_cast_first + k < frame.wave.w)
                store_child_ray(vkrt_cast_first + k, dead);
    }
    add_finite_to_pixel(ray, ray_throughput(ray) * vkrt_radiance);
}

void main()
{
    uint invocation = invocation_index();
    if (invocation >= dispatch_ray_count())
        return;
    uint index = ray_of_invocation(invocation);
    Ray ray = load_ray(index);
    if (ray_is_dead(ray))
        return;
    Hit hit = hits[index];
    vkrt_ray_index = index;
    vkrt_ray = ray;
    vkrt_rng = ray_seed(ray);
    vkrt_dimension = 0u;
    vkrt_radiance = vec3(0.0);
    if (INTEGRATOR == VKRT_INTEGRATE_PATH)
        shade_path(index, ray, hit);
    else
        shade_whitted(index, ray, hit);
}
