/*
 * occlusion.comp: any-hit tracing of every ray in the wavefront (shadow rays). Writes the hit
 * record's triangle as 0 when something blocks the ray, VKRT_NO_HIT when the way is clear.
 */
#include "lib/bindings.glsl"
#include "lib/traverse.glsl"
#ifdef VKRT_SUBGROUPS
#include "lib/traversal_stats.glsl"
#endif

void main()
{
    uint index = invocation_index();
    if (index >= dispatch_ray_count())
        return;
    /* A later brute-force block has nothing to add to a ray already blocked. */
    if (frame_brute_merges(frame) && hits[index].triangle != VKRT_NO_HIT)
        return;
    Ray ray = load_ray(index);
    bool blocked = trace_any(ray.origin.xyz, ray.direction.xyz, ray_tmin(ray), ray_tmax(ray));
    hits[index] = Hit(ray_tmax(ray), 0.0, 0.0, blocked ? 0u : VKRT_NO_HIT);
#ifdef VKRT_SUBGROUPS
    record_traversal_stats();
#endif
}
