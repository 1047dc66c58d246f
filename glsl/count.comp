/*
 * count.comp: how many rays every hit of this depth will cast, and where they go. Each hit's
 * material answers through its count_rays; an atomic add on the next wave's ray_count reserves a
 * run of slots for them, remembered in ray_slots for the shading kernel: slots [first, first +
 * count) of the next depth's buffer, first = 0 when count = 0. At the last depth nothing is
 * reserved: the path ends there.
 *
 * With subgroup operations (VKRT_SUBGROUPS, from the device) a subgroup reserves the runs of all
 * its rays with one atomic: an exclusive prefix sum of the counts gives each ray its place in the
 * subgroup's block: one atomic per ray on a single address serialises the frame's rays, per
 * subgroup there are as many times fewer as it has lanes, and a subgroup's children land next to
 * each other, in the order of their parents.
 */
#include "generated/materials.glsl"
#include "lib/path.glsl"

/* The count_rays answer of ray index's hit; 0 for dead rays, misses and at the last depth. */
uint hit_count(uint index)
{
    Ray ray = load_ray(index);
    Hit hit = hits[index];
    if (ray_is_dead(ray) || hit.triangle == VKRT_NO_HIT || frame.wave.y >= frame.wave.z)
        return 0u;
    /* The path tracer casts one continuation per hit, unless Russian roulette ends the path. */
    if (INTEGRATOR == VKRT_INTEGRATE_PATH)
        return path_continues(ray) ? 1u : 0u;
    Surface s = surface_at(ray, hit);
    vkrt_material = s.material;
    vkrt_ray_index = index;
    vkrt_ray = ray;
    vkrt_rng = ray_seed(ray);
    vkrt_dimension = 0u;
    vkrt_radiance = vec3(0.0);
    vkrt_casting = false;
    uint count = material_count_rays(materials[s.material].info.x, s);
    if (count > VKRT_MAX_CAST) {
        /* An error of the material, reported by the host; cast nothing rather than a part. */
        atomicAdd(counters.overcount, 1u);
        atomicExchange(counters.overcast_material, s.material + 1u);
        count = 0u;
    }
    return count;
}

void main()
{
    uint invocation = invocation_index();
    /* No early return: invocations past the wave take part in the subgroup sums with 0. */
    bool in_wave = invocation < dispatch_ray_count();
    uint index = in_wave ? ray_of_invocation(invocation) : 0u;
    uint count = in_wave ? hit_count(index) : 0u;
#ifdef VKRT_SUBGROUPS
    /* Lanes that reach this point together (whatever the material branches did to convergence)
     * share one reservation: the elected lane is the first of exactly these lanes, and it is the
     * one whose base subgroupBroadcastFirst hands to the others. */
    uint offset = subgroupExclusiveAdd(count);
    uint total = subgroupAdd(count);
    uint base = 0u;
    if (subgroupElect() && total > 0u)
        base = atomicAdd(waves[frame.wave.y + 1u].ray_count, total);
    base = subgroupBroadcastFirst(base);
    uint first = count > 0u ? base + offset : 0u;
#else
    uint first = count > 0u ? atomicAdd(waves[frame.wave.y + 1u].ray_count, count) : 0u;
#endif
    if (in_wave)
        ray_slots[index] = uvec2(first, count);
}
