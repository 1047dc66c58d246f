/*
 * shade.comp: runs every hit's material shader (and the environment shader for rays that missed):
 * the radiance it adds goes to the ray's pixel with a float atomic add, the rays it casts go into
 * the slots count.comp reserved. Slots a shader leaves unused are filled with dead rays, so the
 * next trace needs no compaction to stay correct. The path integrator's version of a hit is
 * shade_path below (lib/path.glsl): the emitted light the ray finds, weighted against light
 * sampling, and one continuation drawn from the BSDF. Which one runs is the INTEGRATOR
 * specialization constant.
 *
 * With --aov (AOVS, lib/aov.glsl) a camera ray's hit records depth and position, and a ray that
 * carries its path's albedo and normal (ray_aov_pending) records them at a surface whose BSDF
 * sample is not a delta lobe; at a delta lobe (a mirror, glass) the ray it casts that way
 * carries them on, as OpenImageDenoise advises. Both integrators decide by the material's
 * bsdf_sample, so a mirror over a diffuse base follows the mirror as often as the path tracer
 * would; its albedo is the sample's weight (f cos / pdf: exactly Kd for a Lambertian surface,
 * the directional albedo on average for a glossy one).
 */
#include "generated/materials.glsl"
#include "lib/aov.glsl"
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

/* --aov: a path that carries its albedo and normal ends at this hit or escape (the last depth,
 * Russian roulette, or the environment): the environment's radiance and no normal, or the
 * surface's own albedo and normal whatever its lobe (a mirror's is its reflectance). */
void aov_path_end(Ray ray, Hit hit, Surface s)
{
    if (hit.triangle == VKRT_NO_HIT) {
        aov_record_surface(ray, environment_radiance(ray.direction.xyz, ray.payload), vec3(0.0));
        return;
    }
    BsdfSample b;
    bool sampled = material_bsdf_sample(materials[s.material].info.x, s, b);
    aov_record_surface(ray, sampled ? b.weight : vec3(0.0), s.normal);
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
    if (AOVS != 0u && hit.triangle != VKRT_NO_HIT)
        aov_record_first_hit(ray, hit.t, s.position);
    uvec2 slots = ray_slots[index];
    /* count.comp reserved one slot when the path carries on (never at the last depth). */
    if (hit.triangle == VKRT_NO_HIT || frame.wave.y >= frame.wave.z || slots.y == 0u ||
        slots.x >= frame.wave.w) {
        if (AOVS != 0u && ray_aov_pending(ray))
            aov_path_end(ray, hit, s);
        return;
    }
    Ray child = ray_dead(ray);
    BsdfSample b;
    vkrt_child_payload = ray.payload;
    bool sampled = material_bsdf_sample(materials[s.material].info.x, s, b);
    if (sampled && any(greaterThan(b.weight, vec3(0.0)))) {
        child = ray_cast(ray, 0u, surface_origin(s, b.direction), b.direction,
                         ray_throughput(ray) * b.weight / path_survival(ray),
                         b.delta ? 0.0 : b.pdf, vkrt_child_payload);
        surface_cast_cone(s, child, b.delta ? 0.0 : b.pdf); /* texture filtering */
    }
    if (AOVS != 0u && ray_aov_pending(ray)) {
        if (sampled && b.delta && !ray_is_dead(child))
            ray_mark_aov_pending(child);
        else
            aov_record_surface(ray, sampled ? b.weight : vec3(0.0), s.normal);
    }
    store_child_ray(slots.x, child);
}

/* --aov, Whitted: the material's own rays are cast (its shade); a bsdf_sample of the path
 * tracer's says whether the path goes on through a delta lobe, and which of those rays, the one
 * cast closest to the sampled direction (glass casts both its reflection and its refraction, and
 * the sample picks one by Fresnel), carries the AOVs on. A surface that is not a delta, or whose
 * ray was not cast (the last depth, too weak to trace), records its own. */
void aov_whitted_hit(Ray ray, Surface s)
{
    BsdfSample b;
    bool sampled = material_bsdf_sample(materials[s.material].info.x, s, b);
    uint carrier = vkrt_cast_done;
    float closest = 0.999;
    for (uint k = 0u; sampled && b.delta && k < vkrt_cast_done; ++k) {
        uint slot = vkrt_cast_first + k;
        if (slot >= frame.wave.w)
            continue;
        Ray carried = aov_load_child_ray(slot);
        float alignment = dot(carried.direction.xyz, b.direction);
        if (!ray_is_dead(carried) && alignment > closest) {
            carrier = k;
            closest = alignment;
        }
    }
    if (carrier == vkrt_cast_done) {
        aov_record_surface(ray, sampled ? b.weight : vec3(0.0), s.normal);
        return;
    }
    Ray carried = aov_load_child_ray(vkrt_cast_first + carrier);
    ray_mark_aov_pending(carried);
    store_child_ray(vkrt_cast_first + carrier, carried);
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
        if (AOVS != 0u) {
            aov_record_first_hit(ray, hit.t, s.position);
            if (ray_aov_pending(ray))
                aov_whitted_hit(ray, s);
        }
    }
    if (AOVS != 0u && hit.triangle == VKRT_NO_HIT && ray_aov_pending(ray))
        aov_record_surface(ray, vkrt_radiance, vec3(0.0));
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
