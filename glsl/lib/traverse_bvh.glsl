/*
 * traverse_bvh.glsl: stack traversal of the binary BVH (src/accel/bvh.c builds it).
 *
 * Children are tested at their parent, both boxes at once; the nearer child is visited first and
 * the farther one pushed (Aila and Laine, "Understanding the Efficiency of Ray Traversal on GPUs",
 * 2009, without their persistent threads). Shadow rays return at the first hit. Triangles are
 * stored in BVH order, so a leaf's triangles are contiguous. Needs bindings.glsl and
 * intersect.glsl included first.
 */
#ifndef VKRT_TRAVERSE_BVH_GLSL
#define VKRT_TRAVERSE_BVH_GLSL

/* Deep enough for any tree the binned SAH builder makes of 2^32 triangles in practice: the stack
 * holds one entry per level on the current path. */
const int BVH_STACK_SIZE = 64;

/* Ize, "Robust BVH Ray Traversal" (JCGT 2013): scaling the exit distance by 1 + 2 gamma(3) makes
 * the slab test conservative, so rounding never culls a box whose triangle the watertight test
 * would hit. */
const float BOX_EXIT_SCALE = 1.0000004;

/* A direction component of exactly 0 would give 0 * inf = NaN in the slab test for an origin on a
 * slab plane; a tiny stand-in keeps every product finite and ordered. */
vec3 safe_inverse(vec3 d)
{
    const float tiny = 1e-30;
    return 1.0 / vec3(abs(d.x) < tiny ? (d.x < 0.0 ? -tiny : tiny) : d.x,
                      abs(d.y) < tiny ? (d.y < 0.0 ? -tiny : tiny) : d.y,
                      abs(d.z) < tiny ? (d.z < 0.0 ? -tiny : tiny) : d.z);
}

/* Where the ray enters and leaves the box, clipped to [tmin, tmax]: the slab test. The box is
 * missed when x > y. */
vec2 slab_interval(vec3 lo, vec3 hi, vec3 origin, vec3 inv_dir, float tmin, float tmax)
{
    vec3 t0 = (lo - origin) * inv_dir;
    vec3 t1 = (hi - origin) * inv_dir;
    vec3 tn = min(t0, t1), tf = max(t0, t1);
    return vec2(max(max(tn.x, tn.y), max(tn.z, tmin)), min(min(tf.x, tf.y), min(tf.z, tmax)));
}

/* Entry distance of the ray into the box within [tmin, tmax], or +inf when it misses. */
float box_entry(vec3 lo, vec3 hi, vec3 origin, vec3 inv_dir, float tmin, float tmax)
{
    vec2 span = slab_interval(lo, hi, origin, inv_dir, tmin, tmax);
    return span.x <= span.y * BOX_EXIT_SCALE ? span.x : uintBitsToFloat(0x7f800000u);
}

/* The closest hit (any_hit false) or the first hit found (any_hit true) in (tmin, tmax). */
Hit bvh_traverse(RayShear s, vec3 dir, float tmin, float tmax, bool any_hit)
{
    const float inf = uintBitsToFloat(0x7f800000u);
    Hit hit = Hit(tmax, 0.0, 0.0, VKRT_NO_HIT);
    vec3 inv_dir = safe_inverse(dir);
    BvhNode root = bvh_nodes[0];
    if (box_entry(root.lo.xyz, root.hi.xyz, s.origin, inv_dir, tmin, tmax) == inf)
        return hit;
    uint stack[BVH_STACK_SIZE];
    int top = 0;
    uint node = 0u;
    while (true) {
        BvhNode n = bvh_nodes[node];
        uint count = floatBitsToUint(n.hi.w);
        uint first = floatBitsToUint(n.lo.w);
        if (count > 0u) {
            for (uint i = first; i < first + count; ++i) {
                Triangle tri = triangles[i];
                float t, u, v;
                if (intersect_triangle(s, tri.v0.xyz, tri.v1.xyz, tri.v2.xyz, tmin, hit.t, t, u, v)) {
                    hit = Hit(t, u, v, i);
                    if (any_hit)
                        return hit;
                }
            }
        } else {
            BvhNode a = bvh_nodes[first], b = bvh_nodes[first + 1u];
            float ta = box_entry(a.lo.xyz, a.hi.xyz, s.origin, inv_dir, tmin, hit.t);
            float tb = box_entry(b.lo.xyz, b.hi.xyz, s.origin, inv_dir, tmin, hit.t);
            if (ta != inf || tb != inf) {
                uint near_child = ta <= tb ? first : first + 1u;
                uint far_child = ta <= tb ? first + 1u : first;
                if (ta != inf && tb != inf && top < BVH_STACK_SIZE)
                    stack[top++] = far_child;
                node = near_child;
                continue;
            }
        }
        /* Pop the next subtree; its box was hit when it was pushed, and may since lie beyond the
         * closest hit, which the next box tests below it catch. */
        if (top == 0)
            break;
        node = stack[--top];
    }
    return hit;
}

#endif
