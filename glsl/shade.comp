/*
 * shade.comp: runs every hit's material shader (and the environment shader for rays that missed):
 * the radiance it adds goes to the ray's pixel with a float atomic add, the rays it casts go into
 * the slots count.comp reserved. Slots a shader leaves unused are filled with dead rays, so the
 * next trace needs no compaction to stay correct.
 */
#include "generated/materials.glsl"

/* Adds c to pixel p. Float atomics where the device has them (VK_EXT_shader_atomic_float), else a
 * compare-and-swap loop on the float's bits. */
void add_to_pixel(uint p, vec3 c)
{
#ifdef VKRT_FLOAT_ATOMICS
    atomicAdd(image[p].x, c.x);
    atomicAdd(image[p].y, c.y);
    atomicAdd(image[p].z, c.z);
#else
    for (uint k = 0u; k < 3u; ++k) {
        uint word = 4u * p + k;
        uint seen = image_words[word];
        for (;;) {
            uint wanted = floatBitsToUint(uintBitsToFloat(seen) + c[k]);
            uint before = atomicCompSwap(image_words[word], seen, wanted);
            if (before == seen)
                break;
            seen = before;
        }
    }
#endif
}

void main()
{
    uint index = invocation_index();
    if (index >= dispatch_ray_count())
        return;
    Ray ray = load_ray(index);
    if ((ray.info.w & VKRT_RAY_DEAD) != 0u)
        return;
    Hit hit = hits[index];
    vkrt_ray_index = index;
    vkrt_ray = ray;
    vkrt_rng = ray.info.y;
    vkrt_radiance = vec3(0.0);
    if (hit.triangle == VKRT_NO_HIT) {
        vkrt_material = VKRT_ENVIRONMENT_MATERIAL;
        vkrt_radiance = material_environment(ray.direction.xyz, ray.payload);
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
        Ray dead;
        dead.origin = vec4(0.0);
        dead.direction = vec4(0.0, 0.0, 1.0, -1.0);
        dead.importance = vec4(0.0);
        dead.info = uvec4(ray.info.x, 0u, ray.info.z + 1u, VKRT_RAY_DEAD);
        dead.payload = vec4(0.0);
        for (uint k = vkrt_cast_done; k < vkrt_cast_reserved; ++k)
            if (vkrt_cast_first + k < frame.wave.w)
                store_child_ray(vkrt_cast_first + k, dead);
    }
    vec3 c = ray.importance.rgb * vkrt_radiance;
    /* One NaN would spread through every sample of its pixel: drop it, count it. */
    if (any(isnan(c)) || any(isinf(c))) {
        atomicAdd(counters.nonfinite, 1u);
        return;
    }
    if (any(notEqual(c, vec3(0.0))))
        add_to_pixel(ray.info.x, c);
}
