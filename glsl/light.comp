/*
 * light.comp: the light samples of every hit of this depth, for the integrator the kernels were
 * built for (the INTEGRATOR specialization constant).
 *
 * Whitted: for each hit whose material reads lights, and each light that can reach it
 * (lib/surface.glsl, light_geometry), an early-exit shadow ray decides whether the light is
 * visible; the answer is one bit per light in light_visibility, which the shading kernel reads
 * through light_sample(). Ambient lights need no ray. On a scene with emissive triangles the last
 * light is a point drawn on them (lib/emitters.glsl).
 *
 * Path: next-event estimation (lib/nee.glsl), whose light is added to the pixel here.
 */
/* The path tracer's part (the material module and lib/nee.glsl), or for Whitted a nee_at that
 * returns 0 and is never called: src/render/material_kernel.c writes it for the integrator the
 * kernels are built for. */
#include "generated/light_stage.glsl"
#include "lib/bindings.glsl"
#include "lib/emitters.glsl"
#include "lib/traverse.glsl"

shared uint workgroup_shadow_rays;

/* Whitted's visibility bits of ray index's lights; returns the shadow rays it traced. */
uint whitted_visibility(uint index)
{
    uint shadow_rays = 0u;
    Ray ray = load_ray(index);
    Hit hit = hits[index];
    uint words = frame_light_words(frame);
    bool lit = !ray_is_dead(ray) && hit.triangle != VKRT_NO_HIT &&
               (materials[material_of(hit_uploaded_triangle(hit.triangle))].info.y & VKRT_MATERIAL_USES_LIGHTS) != 0u;
    Surface s;
    if (lit)
        s = surface_at(ray, hit);
    for (uint w = 0u; w < words; ++w) {
        uint bits = 0u;
        uint end = min(whitted_light_count(), 32u * (w + 1u));
        for (uint i = 32u * w; lit && i < end; ++i) {
            vec3 to_light, irradiance, origin, direction;
            float tmax;
            if (!whitted_light(s, ray_seed(ray), i, to_light, irradiance, origin, direction, tmax))
                continue;
            ++shadow_rays;
            if (!trace_any(origin, direction, 0.0, tmax))
                bits |= 1u << (i & 31u);
        }
        light_visibility[index * words + w] = bits;
    }
    return shadow_rays;
}

void main()
{
    if (gl_LocalInvocationIndex == 0u)
        workgroup_shadow_rays = 0u;
    barrier();

    uint invocation = invocation_index();
    uint shadow_rays = 0u;
    /* Whitted takes the rays in their slots' order, next-event estimation in the grouped one. */
    if (invocation < dispatch_ray_count())
        shadow_rays = INTEGRATOR == VKRT_INTEGRATE_PATH ? nee_at(ray_of_invocation(invocation))
                                                        : whitted_visibility(invocation);
    atomicAdd(workgroup_shadow_rays, shadow_rays);
    barrier();
    if (gl_LocalInvocationIndex == 0u)
        atomicAdd(counters.shadow_rays, workgroup_shadow_rays);
}
