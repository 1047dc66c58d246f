/*
 * traverse.glsl: trace_closest and trace_any over the structure the renderer chose.
 *
 * ACCEL_KIND is a specialization constant, so the driver compiles only the chosen walk into the
 * pipeline; the others are dead code.
 */
#ifndef VKRT_TRAVERSE_GLSL
#define VKRT_TRAVERSE_GLSL

#include "cutout.glsl"
#include "intersect.glsl"
#include "traverse_brute.glsl"
#include "traverse_bvh.glsl"
#include "instances.glsl"
#include "traverse_instanced.glsl"
#include "traverse_grid.glsl"
#include "traverse_kdtree.glsl"

/* Closest hit in (tmin, tmax); hit.triangle == VKRT_NO_HIT on a miss. */
Hit trace_closest(vec3 origin, vec3 dir, float tmin, float tmax)
{
    RayShear s = ray_shear_make(origin, dir);
    cutout_begin_ray(origin, dir);
    if (ACCEL_KIND == VKRT_TRAVERSE_BVH)
        return bvh_traverse(s, dir, tmin, tmax, false);
    if (ACCEL_KIND == VKRT_TRAVERSE_BVH_INSTANCED)
        return instanced_traverse(origin, dir, tmin, tmax, false);
    if (ACCEL_KIND == VKRT_TRAVERSE_KDTREE)
        return kd_traverse(s, dir, tmin, tmax, false);
    if (ACCEL_KIND == VKRT_TRAVERSE_GRID)
        return grid_traverse(s, dir, tmin, tmax, false);
    return brute_closest(s, tmin, tmax);
}

/* True if anything lies in (tmin, tmax): shadow rays stop at the first hit. */
bool trace_any(vec3 origin, vec3 dir, float tmin, float tmax)
{
    RayShear s = ray_shear_make(origin, dir);
    cutout_begin_ray(origin, dir);
    if (ACCEL_KIND == VKRT_TRAVERSE_BVH)
        return bvh_traverse(s, dir, tmin, tmax, true).triangle != VKRT_NO_HIT;
    if (ACCEL_KIND == VKRT_TRAVERSE_BVH_INSTANCED)
        return instanced_traverse(origin, dir, tmin, tmax, true).triangle != VKRT_NO_HIT;
    if (ACCEL_KIND == VKRT_TRAVERSE_KDTREE)
        return kd_traverse(s, dir, tmin, tmax, true).triangle != VKRT_NO_HIT;
    if (ACCEL_KIND == VKRT_TRAVERSE_GRID)
        return grid_traverse(s, dir, tmin, tmax, true).triangle != VKRT_NO_HIT;
    return brute_any(s, tmin, tmax);
}

#endif
