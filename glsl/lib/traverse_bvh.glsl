/*
 * traverse_bvh.glsl: stack traversal of the 4-wide BVH (src/accel/bvh.c builds a binary tree,
 * bvh_quads.c collapses it into BvhQuad nodes with quantized child boxes).
 *
 * Each step fetches one 64-byte node and tests its (up to) 4 children's boxes together, four
 * lanes of a vec4 per plane. The children hit are sorted by entry distance (a 5-exchange network);
 * leaves among them are intersected at once, nearest first, each only if it still begins before
 * the closest hit; of the inner ones the nearest is visited next and the others pushed, farthest
 * deepest (after Ylitie, Karras and Laine, HPG 2017, and Aila and Laine, HPG 2009, without
 * persistent threads). Shadow rays return at the first hit. Triangles are stored in BVH order, so
 * a leaf's triangles are contiguous. Needs bindings.glsl and intersect.glsl included first.
 */
#ifndef VKRT_TRAVERSE_BVH_GLSL
#define VKRT_TRAVERSE_BVH_GLSL

/* Entries the stack can hold; src/render/accel_gpu.c refuses a tree whose paths could need more
 * (bvh_quads.max_stack: up to 3 per level). */
const int BVH_STACK_SIZE = 64;

/* Ize, "Robust BVH Ray Traversal" (JCGT 2013): scaling the exit distance by 1 + 2 gamma(3) makes
 * the slab test conservative, so rounding never culls a box whose triangle the watertight test
 * would hit. It holds for the (plane - origin) * inverse form used below, which rounds twice per
 * plane; a fused plane * inverse - origin * inverse would round the product of the origin apart
 * from the plane's and lose the bound. The planes are decoded first, conservatively: each
 * contains its child's float box (src/accel/bvh_quads.c). */
const float BOX_EXIT_SCALE = 1.0000004;

/* This invocation's traversal work, counted when TRAVERSAL_STATS is set (lib/traversal_stats.glsl
 * reports it). */
uint traversal_steps = 0u;
uint traversal_tests = 0u;

/* The largest float: a limit no missed child's key (+inf) passes, even for a ray of tmax +inf. */
const float FLT_MAX = 3.40282347e38;

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

/* The 4 bytes of w as floats, byte k in lane k: one plane of the 4 children. */
vec4 plane_bytes(uint w)
{
    return vec4((uvec4(w) >> uvec4(0u, 8u, 16u, 24u)) & 0xFFu);
}

/* Orders (ka, ra) before (kb, rb) by key. */
void order_pair(inout float ka, inout uint ra, inout float kb, inout uint rb)
{
    if (kb < ka) {
        float k = ka;
        ka = kb;
        kb = k;
        uint r = ra;
        ra = rb;
        rb = r;
    }
}

/* Intersects the leaf child (key, ref) if it was hit and still begins before the closest hit;
 * returns true when it found a hit. */
bool visit_leaf(RayShear s, float key, uint ref, float tmin, inout Hit hit)
{
    if ((ref & VKRT_BVH_LEAF) == 0u || !(key <= min(hit.t * BOX_EXIT_SCALE, FLT_MAX)))
        return false;
    return bvh_leaf(s, ref & 0x07FFFFFFu, ((ref >> 27) & 0xFu) + 1u, tmin, hit);
}

/* The closest hit (any_hit false) or the first hit found (any_hit true) in (tmin, tmax). */
Hit bvh_traverse(RayShear s, vec3 dir, float tmin, float tmax, bool any_hit)
{
    const float inf = uintBitsToFloat(0x7f800000u);
    Hit hit = Hit(tmax, 0.0, 0.0, VKRT_NO_HIT);
    vec3 inv_dir = safe_inverse(dir);
    uint stack[BVH_STACK_SIZE];
    int top = 0;
    uint node = 0u;
    while (true) {
        BvhQuad n = bvh_nodes[node];
        if (TRAVERSAL_STATS)
            ++traversal_steps;
        uint meta = floatBitsToUint(n.origin.w);
        vec3 scale = vec3(uintBitsToFloat((meta & 0xFFu) << 23),
                          uintBitsToFloat(((meta >> 8) & 0xFFu) << 23),
                          uintBitsToFloat(((meta >> 16) & 0xFFu) << 23));
        /* q * scale is exact, so each decoded plane is rounded once whether or not the compiler
         * fuses; precise keeps it from being reassociated with the subtraction below. */
        precise vec4 x_lo = n.origin.x + plane_bytes(n.planes.x) * scale.x;
        precise vec4 x_hi = n.origin.x + plane_bytes(n.planes.y) * scale.x;
        precise vec4 y_lo = n.origin.y + plane_bytes(n.planes.z) * scale.y;
        precise vec4 y_hi = n.origin.y + plane_bytes(n.planes.w) * scale.y;
        precise vec4 z_lo = n.origin.z + plane_bytes(n.planes_z.x) * scale.z;
        precise vec4 z_hi = n.origin.z + plane_bytes(n.planes_z.y) * scale.z;
        vec4 tx0 = (x_lo - s.origin.x) * inv_dir.x, tx1 = (x_hi - s.origin.x) * inv_dir.x;
        vec4 ty0 = (y_lo - s.origin.y) * inv_dir.y, ty1 = (y_hi - s.origin.y) * inv_dir.y;
        vec4 tz0 = (z_lo - s.origin.z) * inv_dir.z, tz1 = (z_hi - s.origin.z) * inv_dir.z;
        vec4 enter = max(max(min(tx0, tx1), min(ty0, ty1)), max(min(tz0, tz1), vec4(tmin)));
        vec4 leave = min(min(max(tx0, tx1), max(ty0, ty1)), min(max(tz0, tz1), vec4(hit.t)));
        /* Missed children, and the slots past the node's child count, sort last. */
        vec4 key = mix(vec4(inf), enter, lessThanEqual(enter, leave * BOX_EXIT_SCALE));
        key = mix(vec4(inf), key, lessThan(uvec4(0u, 1u, 2u, 3u), uvec4(meta >> 24)));
        float k0 = key.x, k1 = key.y, k2 = key.z, k3 = key.w;
        uint r0 = n.refs.x, r1 = n.refs.y, r2 = n.refs.z, r3 = n.refs.w;
        order_pair(k0, r0, k1, r1);
        order_pair(k2, r2, k3, r3);
        order_pair(k0, r0, k2, r2);
        order_pair(k1, r1, k3, r3);
        order_pair(k1, r1, k2, r2);
        /* Leaves, nearest first: each may shorten the ray for the boxes after it. */
        if (k0 != inf) {
            if (visit_leaf(s, k0, r0, tmin, hit) && any_hit)
                return hit;
            if (visit_leaf(s, k1, r1, tmin, hit) && any_hit)
                return hit;
            if (visit_leaf(s, k2, r2, tmin, hit) && any_hit)
                return hit;
            if (visit_leaf(s, k3, r3, tmin, hit) && any_hit)
                return hit;
        }
        /* Inner children, farthest first: each nearer one pushes the one chosen before it, so
         * the nearest is visited next and the farthest lies deepest in the stack. */
        float limit = min(hit.t * BOX_EXIT_SCALE, FLT_MAX); /* below the key of a missed child */
        uint next = NO_NODE;
        if (k3 <= limit && (r3 & VKRT_BVH_LEAF) == 0u)
            next = r3;
        if (k2 <= limit && (r2 & VKRT_BVH_LEAF) == 0u) {
            if (next != NO_NODE && top < BVH_STACK_SIZE)
                stack[top++] = next;
            next = r2;
        }
        if (k1 <= limit && (r1 & VKRT_BVH_LEAF) == 0u) {
            if (next != NO_NODE && top < BVH_STACK_SIZE)
                stack[top++] = next;
            next = r1;
        }
        if (k0 <= limit && (r0 & VKRT_BVH_LEAF) == 0u) {
            if (next != NO_NODE && top < BVH_STACK_SIZE)
                stack[top++] = next;
            next = r0;
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
