/*
 * trace.comp: closest hit of every ray in the wavefront.
 *
 * Which structure the traversal walks is a specialization constant (lib/traverse.glsl). Dead rays
 * (slots a shader left unused) get no hit and cost one load.
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
    Ray ray = load_ray(index);
    /* A later brute-force block continues from the closest hit of the earlier ones. */
    Hit previous = Hit(ray_tmax(ray), 0.0, 0.0, VKRT_NO_HIT);
    if (frame_brute_merges(frame))
        previous = hits[index];
    if (ray_is_dead(ray)) {
        hits[index] = previous;
        return;
    }
    /* Coverage at the cone's footprint for camera rays alone (lib/cutout.glsl says why). */
    cutout_cone = ray_depth(ray) == 0u ? vec2(ray_cone_width(ray), ray_cone_spread(ray))
                                       : vec2(0.0);
    Hit hit = trace_closest(ray.origin.xyz, ray.direction.xyz, ray_tmin(ray), previous.t);
    hits[index] = hit.triangle != VKRT_NO_HIT ? hit : previous;
#ifdef VKRT_SUBGROUPS
    record_traversal_stats();
#endif
}
