/*
 * intersect.glsl: ray-triangle intersection and ray-origin offsetting.
 *
 * intersect_triangle is the watertight test of Woop, Benthin and Wald, "Watertight Ray/Triangle
 * Intersection", JCGT 2013: the triangle is sheared into a space where the ray is the +z axis,
 * and the 2D edge functions U, V, W decide inclusion. Two triangles sharing an edge compute that
 * edge's function from the same two sheared vertices in opposite order, and IEEE subtraction is
 * antisymmetric, so a ray through the edge is accepted by at least one of them. `precise` stops
 * the compiler from fusing a*b - c*d into an fma, which would break that symmetry. Edges are
 * inclusive (>= 0), so a ray through a shared vertex or edge hits; a triangle of zero area
 * (det == 0) is never hit, so degenerate input yields no hit and no NaN.
 */
#ifndef VKRT_INTERSECT_GLSL
#define VKRT_INTERSECT_GLSL

#include "ray_offset.glsl"

/* |det| below this fraction of the largest edge-function product is rounding noise (2^-18). */
const float RELIABLE_DET_FRACTION = 1.0 / 262144.0;

/* Per-ray constants of the watertight test: the axis permutation and the shear, as the rows of
 * the map from a vertex (relative to the origin) to its sheared coordinates, so that the test
 * multiplies where it would otherwise pick vector components by a per-ray index: row_x has 1 at
 * kx and -Sx at kz, row_y 1 at ky and -Sy at kz, row_z Sz at kz, zeros elsewhere. */
struct RayShear {
    vec3 origin;
    vec3 row_x, row_y, row_z;
};

RayShear ray_shear_make(vec3 origin, vec3 dir)
{
    RayShear s;
    s.origin = origin;
    vec3 a = abs(dir);
    int kz = (a.x > a.y) ? (a.x > a.z ? 0 : 2) : (a.y > a.z ? 1 : 2);
    int kx = (kz + 1) % 3;
    int ky = (kx + 1) % 3;
    /* Keep the winding of the sheared triangle independent of the ray's z sign. */
    if ((kz == 0 ? dir.x : kz == 1 ? dir.y : dir.z) < 0.0) {
        int t = kx;
        kx = ky;
        ky = t;
    }
    /* One-hot axes, and the components they pick, without indexing by a per-ray value: a
     * product by 0 or 1 and a sum of zeros are exact, so dot(dir, ex) is dir[kx]. */
    vec3 ex = vec3(equal(ivec3(0, 1, 2), ivec3(kx)));
    vec3 ey = vec3(equal(ivec3(0, 1, 2), ivec3(ky)));
    vec3 ez = vec3(equal(ivec3(0, 1, 2), ivec3(kz)));
    float dz = dot(dir, ez);
    s.row_x = ex - (dot(dir, ex) / dz) * ez;
    s.row_y = ey - (dot(dir, ey) / dz) * ez;
    s.row_z = (1.0 / dz) * ez;
    return s;
}

/* Returns true and the hit's t and barycentrics (u of v1, v of v2) when the ray hits the
 * triangle with tmin < t < tmax. */
bool intersect_triangle(RayShear s, vec3 p0, vec3 p1, vec3 p2, float tmin, float tmax,
                        out float t, out float u, out float v)
{
    vec3 a = p0 - s.origin;
    vec3 b = p1 - s.origin;
    vec3 c = p2 - s.origin;
    /* Each sheared coordinate as fmas along a row: the zero terms add exactly nothing, so it is
     * one product and one sum of the vertex's own components, the same whichever triangle the
     * vertex belongs to (precise: no other contraction). */
    precise float ax = fma(a.x, s.row_x.x, fma(a.y, s.row_x.y, a.z * s.row_x.z));
    precise float ay = fma(a.x, s.row_y.x, fma(a.y, s.row_y.y, a.z * s.row_y.z));
    precise float bx = fma(b.x, s.row_x.x, fma(b.y, s.row_x.y, b.z * s.row_x.z));
    precise float by = fma(b.x, s.row_y.x, fma(b.y, s.row_y.y, b.z * s.row_y.z));
    precise float cx = fma(c.x, s.row_x.x, fma(c.y, s.row_x.y, c.z * s.row_x.z));
    precise float cy = fma(c.x, s.row_y.x, fma(c.y, s.row_y.y, c.z * s.row_y.z));

    precise float eu = cx * by - cy * bx;
    precise float ev = ax * cy - ay * cx;
    precise float ew = bx * ay - by * ax;
    t = 0.0;
    u = 0.0;
    v = 0.0;
    if ((eu < 0.0 || ev < 0.0 || ew < 0.0) && (eu > 0.0 || ev > 0.0 || ew > 0.0))
        return false;
    float det = eu + ev + ew;
    /* Each edge function carries a rounding error of a few ULPs of its largest product. When the
     * ray lies nearly in the plane of a triangle far from it (the sheared triangle degenerates
     * to a sliver whose line passes by the ray), all three functions are below that error, their
     * signs are noise, and the test above can accept a triangle the ray passes thousands of units
     * away from: brute force in tests/test_accel.c found such false hits on the stadium scene.
     * A real hit puts the triangle around the ray, where the products are no larger than the
     * triangle's size squared, so this rejects only rays that graze its plane within about 1e-5
     * radians. The paper's double-precision fallback covers exact zeros only, not this. */
    float largest = max(max(max(abs(cx * by), abs(cy * bx)), max(abs(ax * cy), abs(ay * cx))),
                        max(abs(bx * ay), abs(by * ax)));
    if (abs(det) <= largest * RELIABLE_DET_FRACTION)
        return false;

    /* Scaled distance; compared before the division, which is the expensive part. */
    float az = dot(a, s.row_z);
    float bz = dot(b, s.row_z);
    float cz = dot(c, s.row_z);
    float scaled_t = eu * az + ev * bz + ew * cz;
    float inv_det = 1.0 / det;
    float hit_t = scaled_t * inv_det;
    if (!(hit_t > tmin && hit_t < tmax))
        return false;
    t = hit_t;
    u = ev * inv_det;
    v = ew * inv_det;
    return true;
}

/* A hit point is off its triangle's plane by rounding of two kinds, and the origin of a ray that
 * leaves it is moved off the plane by more than both (after Wächter and Binder, "A Fast and
 * Robust Method for Avoiding Self-Intersection", Ray Tracing Gems, ch. 6, and the error bounds of
 * pbrt-v4: Pharr, Jakob and Humphreys, "Physically Based Rendering", 4th ed., 6.8):
 * - Absolute: the point interpolated from the vertices (surface_at: w v0 + u v1 + v v2, with
 *   w = 1 - u - v rounded) errs by up to about 2.5 ULPs of the largest coordinate per component,
 *   4.3 along the normal, and rounding the moved origin adds 0.9: about 5 ULPs in all (pbrt's
 *   gamma(7) bound, counted per operation). Nothing cancels this far from the origin, so the
 *   offset has OFFSET_ULPS_OF_POSITION = 8 ULPs of the largest coordinate. On the bumpy sphere of
 *   tests/stability, 1e5 units away, 0 ULPs leave half the lit points in their own shadow and 2
 *   are enough.
 * - Relative: the intersection test works on the vertices less the ray's origin, differences
 *   of nearby floats, exact (Sterbenz) or off by an ULP of the difference, so its own error,
 *   wherever the triangle is, is ULPs of the triangle's size: of a whole wall (the 555-unit
 *   Cornell box) for a point near its corner. OFFSET_ULPS_OF_SIZE = 256 ULPs of the size, which
 *   clears the Cornell box's walls; Wächter and Binder's per-coordinate offset left a point on
 *   its plane x = 0 almost unmoved and the wall showed self-shadowing noise.
 * An offset that is all absolute (256 ULPs of the largest coordinate) would be 0.01 units 350
 * units from the origin and 3 units at 1e5: past the neighbouring facets that shadow a grazing
 * point, so the shadows' edges would brighten as a scene moves away from the origin.
 * The rule itself is lib/ray_offset.glsl, which compiles as C too: src/bench_rays.c offsets its
 * rays by it. */

/* Moves a surface point p off its surface along the geometric normal n (facing the side the new
 * ray leaves towards) by ray_offset_distance(magnitude). */
vec3 offset_ray_origin(vec3 p, vec3 n, float magnitude)
{
    return p + ray_offset_distance(magnitude) * n;
}

/* The unit normal of the triangle's plane (winding a, b, c), or 0 for a triangle of no area. The
 * cross product is divided by its largest component before it is normalised: its squared length
 * is of degree 4 in the coordinates and overflowed float for a 555-unit Cornell box scaled by
 * 1e7 (sides 5.55e9: (5.55e9)^4 > 3.4e38), where normalize() returned a zero normal and no
 * light reached the walls. The division also helps tiny triangles: with sides under 1e-10
 * that square is below float's smallest normal number, which a GPU may flush to 0. The cross
 * product itself is finite for sides up to 1e19 (docs/scene-format.md, Coordinates). */
vec3 triangle_normal(vec3 a, vec3 b, vec3 c)
{
    vec3 n = cross(b - a, c - a);
    float largest = max(abs(n.x), max(abs(n.y), abs(n.z)));
    return largest > 0.0 ? normalize(n / largest) : vec3(0.0);
}

/* The scale of a triangle's rounding errors, for offset_ray_origin (ray_offset_magnitude). */
float triangle_magnitude(vec3 a, vec3 b, vec3 c)
{
    vec3 l = max(abs(a), max(abs(b), abs(c)));
    vec3 s = max(a, max(b, c)) - min(a, min(b, c));
    return ray_offset_magnitude(max(l.x, max(l.y, l.z)), max(s.x, max(s.y, s.z)));
}

#endif
