/*
 * traverse_brute.glsl: brute-force traversal, every ray against every triangle.
 *
 * The reference the faster structures are held against, and the right choice for a handful of
 * triangles. Needs bindings.glsl and intersect.glsl included first.
 *
 * Mesa's llvmpipe (lavapipe) ends an invocation's loops after 65535 iterations in all, silently:
 * a brute-force loop over the bunny's 69,451 triangles skipped every one past index 65534 (found
 * by tests/test_accel.c). So the host splits brute force into dispatches over blocks of
 * triangles (frame.range), each continuing from the hits of the last.
 */
#ifndef VKRT_TRAVERSE_BRUTE_GLSL
#define VKRT_TRAVERSE_BRUTE_GLSL

/* Closest hit in (tmin, tmax); hit.triangle == VKRT_NO_HIT on a miss. */
/* Closest hit among triangles frame.range.x .. frame.range.y - 1 in (tmin, tmax). */
Hit brute_closest(RayShear s, float tmin, float tmax)
{
    Hit hit = Hit(tmax, 0.0, 0.0, VKRT_NO_HIT);
    for (uint i = frame.range.x; i < frame.range.y; ++i) {
        Triangle tri = load_triangle(i);
        float t, u, v;
        if (intersect_triangle(s, tri.v0.xyz, tri.v1.xyz, tri.v2.xyz, tmin, hit.t, t, u, v) &&
            cutout_keeps(i, u, v))
            hit = Hit(t, u, v, i);
    }
    return hit;
}

/* True if one of the range's triangles lies in (tmin, tmax); stops at the first. */
bool brute_any(RayShear s, float tmin, float tmax)
{
    for (uint i = frame.range.x; i < frame.range.y; ++i) {
        Triangle tri = load_triangle(i);
        float t, u, v;
        if (intersect_triangle(s, tri.v0.xyz, tri.v1.xyz, tri.v2.xyz, tmin, tmax, t, u, v) &&
            cutout_keeps(i, u, v))
            return true;
    }
    return false;
}

#endif
