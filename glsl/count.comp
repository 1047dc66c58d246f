/*
 * count.comp: how many rays every hit of this depth will cast, and where they go. Each hit's
 * material answers through its count_rays; one atomic add on the next wave's ray_count reserves a
 * run of slots for them, remembered in ray_slots for the shading kernel. At the last depth nothing
 * is reserved: the path ends there.
 */
#include "generated/materials.glsl"

void main()
{
    uint index = invocation_index();
    if (index >= dispatch_ray_count())
        return;
    Ray ray = load_ray(index);
    Hit hit = hits[index];
    uint count = 0u;
    if ((ray.info.w & VKRT_RAY_DEAD) == 0u && hit.triangle != VKRT_NO_HIT &&
        frame.wave.y < frame.wave.z) {
        Surface s = surface_at(ray, hit);
        vkrt_material = s.material;
        vkrt_ray_index = index;
        vkrt_ray = ray;
        vkrt_rng = ray.info.y;
        vkrt_radiance = vec3(0.0);
        vkrt_casting = false;
        count = material_count_rays(materials[s.material].info.x, s);
        if (count > VKRT_MAX_CAST) {
            /* An error of the material, reported by the host; cast nothing rather than a part. */
            atomicAdd(counters.overcount, 1u);
            atomicExchange(counters.overcast_material, s.material + 1u);
            count = 0u;
        }
    }
    uint first = count > 0u ? atomicAdd(waves[frame.wave.y + 1u].ray_count, count) : 0u;
    ray_slots[index] = uvec2(first, count);
}
