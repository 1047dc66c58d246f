/*
 * traverse_brute.glsl: brute-force traversal, every ray against every triangle.
 *
 * The reference the faster structures are held against, and the right choice for a handful of
 * triangles. Needs bindings.glsl and intersect.glsl included first.
 *
 * Some CPU devices end an invocation's loops after 65535 iterations in all, silently (a loop over
 * more triangles would skip the rest), so the host splits brute force into dispatches over blocks
 * of triangles (frame_brute_first .. frame_brute_end), each continuing from the hits of the last
 * (frame_brute_merges).
 */
#ifndef VKRT_TRAVERSE_BRUTE_GLSL
#define VKRT_TRAVERSE_BRUTE_GLSL

/* Closest hit among this dispatch's triangles in (tmin, tmax); hit.triangle == VKRT_NO_HIT on a
 * miss. */
Hit brute_closest(RayShear s, float tmin, float tmax)
{
    Hit hit = Hit(tmax, 0.0, 0.0, VKRT_NO_HIT);
    uint end = frame_brute_end(frame);
    for (uint i = frame_brute_first(frame); i < end; ++i) {
        Triangle tri = load_triangle(i);
        float t, u, v;
        if (intersect_triangle(s, tri.v0.xyz, tri.v1.xyz, tri.v2.xyz, tmin, hit.t, t, u, v) &&
            cutout_keeps(i, u, v))
            hit = Hit(t, u, v, i);
    }
    return hit;
}

/* True if one of this dispatch's triangles lies in (tmin, tmax); stops at the first. */
bool brute_any(RayShear s, float tmin, float tmax)
{
    uint end = frame_brute_end(frame);
    for (uint i = frame_brute_first(frame); i < end; ++i) {
        Triangle tri = load_triangle(i);
        float t, u, v;
        if (intersect_triangle(s, tri.v0.xyz, tri.v1.xyz, tri.v2.xyz, tmin, tmax, t, u, v) &&
            cutout_keeps(i, u, v))
            return true;
    }
    return false;
}

#endif
