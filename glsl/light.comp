/*
 * light.comp: the light samples of every hit. For each hit whose material reads lights, and each
 * light that can reach it (lib/surface.glsl, light_geometry), an early-exit shadow ray decides
 * whether the light is visible; the answer is one bit per light in light_visibility, which the
 * shading kernel reads through light_sample(). Ambient lights need no ray. On a scene with
 * emissive triangles the last light is a point drawn on them (lib/emitters.glsl).
 */
#include "lib/bindings.glsl"
#include "lib/emitters.glsl"
#include "lib/traverse.glsl"

shared uint workgroup_shadow_rays;

void main()
{
    if (gl_LocalInvocationIndex == 0u)
        workgroup_shadow_rays = 0u;
    barrier();

    uint index = invocation_index();
    uint shadow_rays = 0u;
    if (index < dispatch_ray_count()) {
        Ray ray = load_ray(index);
        Hit hit = hits[index];
        uint words = frame.range.w;
        bool lit = (ray.info.w & VKRT_RAY_DEAD) == 0u && hit.triangle != VKRT_NO_HIT &&
                   (materials[material_of(hit.triangle)].info.y & VKRT_MATERIAL_USES_LIGHTS) != 0u;
        Surface s;
        if (lit)
            s = surface_at(ray, hit);
        for (uint w = 0u; w < words; ++w) {
            uint bits = 0u;
            uint end = min(whitted_light_count(), 32u * (w + 1u));
            for (uint i = 32u * w; lit && i < end; ++i) {
                vec3 to_light, irradiance, origin, direction;
                float tmax;
                if (!whitted_light(s, ray.info.y, i, to_light, irradiance, origin, direction, tmax))
                    continue;
                ++shadow_rays;
                if (!trace_any(origin, direction, 0.0, tmax))
                    bits |= 1u << (i & 31u);
            }
            light_visibility[index * words + w] = bits;
        }
    }
    atomicAdd(workgroup_shadow_rays, shadow_rays);
    barrier();
    if (gl_LocalInvocationIndex == 0u)
        atomicAdd(counters.shadow_rays, workgroup_shadow_rays);
}
