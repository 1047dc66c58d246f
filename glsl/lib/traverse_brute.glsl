/*
 * traverse_brute.glsl: brute-force traversal, every ray against every triangle.
 *
 * The reference the faster structures are held against, and the right choice for a handful of
 * triangles. Needs bindings.glsl and intersect.glsl included first.
 */
#ifndef VKRT_TRAVERSE_BRUTE_GLSL
#define VKRT_TRAVERSE_BRUTE_GLSL

/* Closest hit in (tmin, tmax); hit.triangle == VKRT_NO_HIT on a miss. */
Hit trace_closest(vec3 origin, vec3 dir, float tmin, float tmax)
{
    RayShear s = ray_shear_make(origin, dir);
    Hit hit;
    hit.t = tmax;
    hit.u = 0.0;
    hit.v = 0.0;
    hit.triangle = VKRT_NO_HIT;
    uint count = frame.counts.x;
    for (uint i = 0u; i < count; ++i) {
        Triangle tri = triangles[i];
        float t, u, v;
        if (intersect_triangle(s, tri.v0.xyz, tri.v1.xyz, tri.v2.xyz, tmin, hit.t, t, u, v)) {
            hit.t = t;
            hit.u = u;
            hit.v = v;
            hit.triangle = i;
        }
    }
    return hit;
}

/* True if anything lies in (tmin, tmax): shadow rays stop at the first hit. */
bool trace_any(vec3 origin, vec3 dir, float tmin, float tmax)
{
    RayShear s = ray_shear_make(origin, dir);
    uint count = frame.counts.x;
    for (uint i = 0u; i < count; ++i) {
        Triangle tri = triangles[i];
        float t, u, v;
        if (intersect_triangle(s, tri.v0.xyz, tri.v1.xyz, tri.v2.xyz, tmin, tmax, t, u, v))
            return true;
    }
    return false;
}

#endif
