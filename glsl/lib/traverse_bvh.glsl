/*
 * traverse_bvh.glsl: stack traversal of the binary BVH (src/accel/bvh.c builds it, bvh_pairs.c
 * lays it out as BvhPair records).
 *
 * Each step fetches one 64-byte record holding both children's boxes and tests them together;
 * the nearer child is visited first and the farther one pushed (Aila and Laine, "Understanding
 * the Efficiency of Ray Traversal on GPUs", HPG 2009, without their persistent threads). A child
 * that is a leaf is intersected at once, so leaves never go through the stack, and the farther
 * child is tested again against the hit the nearer leaf found. Shadow rays return at the first
 * hit. Triangles are stored in BVH order, so a leaf's triangles are contiguous. Needs
 * bindings.glsl and intersect.glsl included first.
 */
#ifndef VKRT_TRAVERSE_BVH_GLSL
#define VKRT_TRAVERSE_BVH_GLSL

/* The stack holds at most one entry per level of the current path; src/render/accel_gpu.c
 * refuses a tree deeper than this. */
const int BVH_STACK_SIZE = 64;

/* Ize, "Robust BVH Ray Traversal" (JCGT 2013): scaling the exit distance by 1 + 2 gamma(3) makes
 * the slab test conservative, so rounding never culls a box whose triangle the watertight test
 * would hit. It holds for the (plane - origin) * inverse form used below, which rounds twice per
 * plane; a fused plane * inverse - origin * inverse would round the product of the origin apart
 * from the plane's and lose the bound. */
const float BOX_EXIT_SCALE = 1.0000004;

/* This invocation's traversal work, counted when TRAVERSAL_STATS is set (lib/traversal_stats.glsl
 * reports it). */
uint traversal_steps = 0u;
uint traversal_tests = 0u;

/* Marks "no node chosen yet" in a step. */
const uint NO_NODE = 0xFFFFFFFFu;

/* A direction component of exactly 0 would give 0 * inf = NaN in the slab test for an origin on a
 * slab plane; a tiny stand-in keeps every product finite and ordered. */
vec3 safe_inverse(vec3 d)
{
    const float tiny = 1e-30;
    return 1.0 / vec3(abs(d.x) < tiny ? (d.x < 0.0 ? -tiny : tiny) : d.x,
                      abs(d.y) < tiny ? (d.y < 0.0 ? -tiny : tiny) : d.y,
                      abs(d.z) < tiny ? (d.z < 0.0 ? -tiny : tiny) : d.z);
}

/* Where the ray enters and leaves the box, clipped to [tmin, tmax]: the slab test of one box
 * (the grid's walk clips rays to its frame with it). The box is missed when x > y. */
vec2 slab_interval(vec3 lo, vec3 hi, vec3 origin, vec3 inv_dir, float tmin, float tmax)
{
    vec3 t0 = (lo - origin) * inv_dir;
    vec3 t1 = (hi - origin) * inv_dir;
    vec3 tn = min(t0, t1), tf = max(t0, t1);
    return vec2(max(max(tn.x, tn.y), max(tn.z, tmin)), min(min(tf.x, tf.y), min(tf.z, tmax)));
}

/* Tests the leaf's count triangles from first on, keeping the closest hit in hit; returns true
 * when one was found. */
bool bvh_leaf(RayShear s, uint first, uint count, float tmin, inout Hit hit)
{
    bool found = false;
    if (TRAVERSAL_STATS)
        traversal_tests += count;
    for (uint i = first; i < first + count; ++i) {
        Triangle tri = triangles[i];
        float t, u, v;
        if (intersect_triangle(s, tri.v0.xyz, tri.v1.xyz, tri.v2.xyz, tmin, hit.t, t, u, v)) {
            hit = Hit(t, u, v, i);
            found = true;
        }
    }
    return found;
}

/* The closest hit (any_hit false) or the first hit found (any_hit true) in (tmin, tmax). */
Hit bvh_traverse(RayShear s, vec3 dir, float tmin, float tmax, bool any_hit)
{
    Hit hit = Hit(tmax, 0.0, 0.0, VKRT_NO_HIT);
    vec3 inv_dir = safe_inverse(dir);
    uint stack[BVH_STACK_SIZE];
    int top = 0;
    uint node = 0u;
    while (true) {
        BvhPair n = bvh_pairs[node];
        if (TRAVERSAL_STATS)
            ++traversal_steps;
        /* Slab distances of both children at once: lanes (a.lo, a.hi, b.lo, b.hi). */
        vec4 tx = (n.x - s.origin.x) * inv_dir.x;
        vec4 ty = (n.y - s.origin.y) * inv_dir.y;
        vec4 tz = (n.z - s.origin.z) * inv_dir.z;
        float a_in = max(max(min(tx.x, tx.y), min(ty.x, ty.y)), max(min(tz.x, tz.y), tmin));
        float a_out = min(min(max(tx.x, tx.y), max(ty.x, ty.y)), min(max(tz.x, tz.y), hit.t));
        float b_in = max(max(min(tx.z, tx.w), min(ty.z, ty.w)), max(min(tz.z, tz.w), tmin));
        float b_out = min(min(max(tx.z, tx.w), max(ty.z, ty.w)), min(max(tz.z, tz.w), hit.t));
        bool near_hit = a_in <= a_out * BOX_EXIT_SCALE;
        bool far_hit = b_in <= b_out * BOX_EXIT_SCALE;
        uvec2 near_child = n.refs.xz, far_child = n.refs.yw; /* (ref, triangle count) */
        float far_in = b_in;
        if (!near_hit || (far_hit && b_in < a_in)) {
            /* b first; when a was missed, b alone (in the near slot) or nothing. */
            near_child = n.refs.yw;
            far_child = n.refs.xz;
            far_in = a_in;
            bool a_hit = near_hit;
            near_hit = far_hit;
            far_hit = a_hit;
        }
        uint next = NO_NODE;
        if (near_hit) {
            if (near_child.y == 0u)
                next = near_child.x;
            else if (bvh_leaf(s, near_child.x, near_child.y, tmin, hit) && any_hit)
                return hit;
        }
        /* The nearer leaf may have found a hit before the farther box begins. */
        if (far_hit && far_in <= hit.t * BOX_EXIT_SCALE) {
            if (far_child.y > 0u) {
                if (bvh_leaf(s, far_child.x, far_child.y, tmin, hit) && any_hit)
                    return hit;
            } else if (next == NO_NODE) {
                next = far_child.x;
            } else if (top < BVH_STACK_SIZE) {
                stack[top++] = far_child.x;
            }
        }
        if (next == NO_NODE) {
            /* Pop the next subtree; its box was hit when it was pushed, and may since lie beyond
             * the closest hit, which its children's box tests catch. */
            if (top == 0)
                break;
            next = stack[--top];
        }
        node = next;
    }
    return hit;
}

#endif
