/*
 * traverse_bvh.glsl: stack traversal of the BVH (src/accel/bvh.c builds a binary SAH tree;
 * bvh_quads.c collapses it into 4-wide BvhQuad nodes with quantized child boxes, bvh_pairs.c
 * lays it out as BvhPair records of two float boxes; BVH_WIDTH says which).
 *
 * Each step fetches one 64-byte node and tests all its children's boxes together, four lanes of
 * a vec4 per plane. Of the children hit, the nearest is visited next and the others pushed, the
 * farthest deepest (4-wide: sorted by entry distance with a 5-exchange network). Leaves go
 * through the same loop as inner nodes, so the triangle test is compiled once rather than inlined
 * at each place a leaf can be met, which makes the kernel larger and slower. After
 * Aila and Laine, HPG 2009, and Ylitie, Karras and Laine, HPG 2017, without persistent threads.
 * Shadow rays return at the first hit. Triangles are stored in BVH order, so a leaf's triangles
 * are contiguous. Needs bindings.glsl and intersect.glsl included first.
 */
#ifndef VKRT_TRAVERSE_BVH_GLSL
#define VKRT_TRAVERSE_BVH_GLSL

/* Entries the stack can hold (glsl/shared.h). */
const int BVH_STACK_SIZE = VKRT_BVH_STACK_SIZE;

/* Ize, "Robust BVH Ray Traversal" (JCGT 2013): scaling the exit distance by 1 + 2 gamma(3) makes
 * the slab test conservative, so rounding never culls a box whose triangle the watertight test
 * would hit. It holds where each plane's distance errs by at most two roundings relative to
 * itself, as (plane - origin) * inverse does. The BVH's steps compute the distance as one fma of
 * the plane with per-ray constants instead, whose product origin * inverse rounds apart from the
 * plane's; SlabRay (below) moves those constants by a margin that brings each distance back
 * within one rounding, on the safe side. The planes are decoded first, conservatively: each
 * contains its child's float box (src/accel/bvh_quads.c). */
const float BOX_EXIT_SCALE = 1.0000004;

/* This invocation's traversal work, counted when TRAVERSAL_STATS is set (lib/traversal_stats.glsl
 * reports it). */
uint traversal_steps = 0u;
uint traversal_tests = 0u;
uint traversal_leaves = 0u;

/* Marks "no node chosen yet" in a step. */
const uint NO_NODE = 0xFFFFFFFFu;

/* The inverse of d with each component's magnitude raised to tiny at least, sign kept. */
vec3 inverse_at_least(vec3 d, vec3 tiny)
{
    return 1.0 / vec3(abs(d.x) < tiny.x ? (d.x < 0.0 ? -tiny.x : tiny.x) : d.x,
                      abs(d.y) < tiny.y ? (d.y < 0.0 ? -tiny.y : tiny.y) : d.y,
                      abs(d.z) < tiny.z ? (d.z < 0.0 ? -tiny.z : tiny.z) : d.z);
}

/* A direction component of exactly 0 would give 0 * inf = NaN in the slab test for an origin on a
 * slab plane; a tiny stand-in keeps every product finite and ordered. */
vec3 safe_inverse(vec3 d)
{
    return inverse_at_least(d, vec3(1e-30));
}

/* The per-ray constants of the BVH's slab tests: a plane p's distance is fma(p, inv_dir, bias),
 * one operation where (p - origin) * inv_dir took two. The bias, -origin * inv_dir, is rounded
 * once per ray, and its error is relative to |origin * inv_dir|, not to the distance, which is
 * far smaller for a ray that starts near a box but far from the scene's origin. So each bias is
 * moved by a margin of 2^-21 |origin * inv_dir|, towards smaller distances for the plane a ray
 * enters a box by (lo where inv_dir >= 0) and towards larger ones for the plane it leaves by.
 * That is 8 units of rounding of the product; the errors it must cover come to about 3 (the
 * product's, the bias's own rounding, and p * inv_dir's where a compiler does not fuse), after
 * which each distance errs by at most one rounding relative to itself, which BOX_EXIT_SCALE
 * covers. The floor keeps the margin where the product flushes to zero. tests/test_accel.c
 * checks it with a sphere far from the origin, which leaks without the margin. */
struct SlabRay {
    vec3 inv_dir;
    vec3 lo_bias;
    vec3 hi_bias;
};

/* The BVH's inverse direction: safe_inverse's stand-in for a component near 0 also grows with the
 * origin's coordinate, to 2^-120 of it, so that origin * inv_dir stays below 2^120 and the biases
 * finite. With 1e-30 alone, a ray with a component of exactly 0 (the middle column of an image of
 * odd width) from an origin past 3.4e8 on that axis got an infinite product, -inf and NaN biases,
 * and missed every box: a Cornell box scaled by 1e7 showed a cross of holes. The stand-in still
 * puts every plane not through the origin at least 2^-24 |origin| / (2^-120 |origin|) = 2^96
 * along the ray, beyond any hit. */
const float SLAB_TINY_PER_COORDINATE = 7.52316385e-37; /* 2^-120 */

SlabRay slab_ray_make(vec3 origin, vec3 dir)
{
    vec3 inv_dir = inverse_at_least(dir, max(vec3(1e-30), abs(origin) * SLAB_TINY_PER_COORDINATE));
    precise vec3 product = origin * inv_dir;
    precise vec3 margin = max(abs(product) * (1.0 / 2097152.0), vec3(1e-30));
    vec3 toward = mix(vec3(-1.0), vec3(1.0), greaterThanEqual(inv_dir, vec3(0.0)));
    precise vec3 lo_bias = -product - toward * margin;
    precise vec3 hi_bias = -product + toward * margin;
    return SlabRay(inv_dir, lo_bias, hi_bias);
}

/* The distances to one axis's planes of a pair record: (lo, hi, lo, hi) of its two boxes. */
vec4 slab_distances(vec4 planes, float inv_dir, float lo_bias, float hi_bias)
{
    return fma(planes, vec4(inv_dir), vec4(lo_bias, hi_bias, lo_bias, hi_bias));
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
    if (TRAVERSAL_STATS) {
        traversal_tests += count;
        ++traversal_leaves;
    }
    for (uint i = first; i < first + count; ++i) {
        Triangle tri = load_triangle(i);
        float t, u, v;
        if (intersect_triangle(s, tri.v0.xyz, tri.v1.xyz, tri.v2.xyz, tmin, hit.t, t, u, v) &&
            cutout_keeps(i, u, v)) {
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

/* Orders (ka, ra) before (kb, rb) by key, with selects rather than a branch. */
void order_pair(inout float ka, inout uint ra, inout float kb, inout uint rb)
{
    bool swap = kb < ka;
    float k = ka;
    uint r = ra;
    ka = swap ? kb : ka;
    ra = swap ? rb : ra;
    kb = swap ? k : kb;
    rb = swap ? r : rb;
}

/* One step at the pair record `node`: tests both children against (tmin, hit_t) and returns the
 * one to visit next (the nearer, or any for a shadow ray), or NO_NODE when neither was hit; push
 * is the other when both were, else NO_NODE. */
uint bvh_pair_step(SlabRay b, float tmin, float hit_t, bool any_hit, uint node, out uint push)
{
    BvhPair n = load_pair(node);
    if (TRAVERSAL_STATS)
        ++traversal_steps;
    vec4 tx = slab_distances(n.x, b.inv_dir.x, b.lo_bias.x, b.hi_bias.x);
    vec4 ty = slab_distances(n.y, b.inv_dir.y, b.lo_bias.y, b.hi_bias.y);
    vec4 tz = slab_distances(n.z, b.inv_dir.z, b.lo_bias.z, b.hi_bias.z);
    float a_in = max(max(min(tx.x, tx.y), min(ty.x, ty.y)), max(min(tz.x, tz.y), tmin));
    float a_out = min(min(max(tx.x, tx.y), max(ty.x, ty.y)), min(max(tz.x, tz.y), hit_t));
    float b_in = max(max(min(tx.z, tx.w), min(ty.z, ty.w)), max(min(tz.z, tz.w), tmin));
    float b_out = min(min(max(tx.z, tx.w), max(ty.z, ty.w)), min(max(tz.z, tz.w), hit_t));
    bool hit_a = a_in <= a_out * BOX_EXIT_SCALE;
    bool hit_b = b_in <= b_out * BOX_EXIT_SCALE;
    push = NO_NODE;
    if (hit_a && hit_b) {
        /* A shadow ray wants any hit, in any order: it skips the ordering. */
        bool a_first = any_hit || a_in <= b_in;
        push = a_first ? n.refs.y : n.refs.x;
        return a_first ? n.refs.x : n.refs.y;
    }
    return hit_a ? n.refs.x : hit_b ? n.refs.y : NO_NODE;
}

/* One step at the 4-wide node `node`: tests its children against (tmin, hit_t) and returns the
 * nearest hit, or NO_NODE; the others hit, farthest first, come back in push_far, push_mid and
 * push_near (NO_NODE where fewer were hit), to be pushed in that order. */
uint bvh_quad_step(SlabRay b, float tmin, float hit_t, uint node, out uint push_far,
                   out uint push_mid, out uint push_near)
{
    const float inf = uintBitsToFloat(0x7f800000u);
    /* Loaded here rather than through a function like load_pair: glslang's propagation of
     * `precise` (below) through a struct returned by a function never ended. */
    BvhQuad n;
    if (TEXEL_LOADS) {
        int t = int(4u * node);
        n.origin = uintBitsToFloat(texelFetch(node_texels, t));
        n.planes = texelFetch(node_texels, t + 1);
        n.planes_z = texelFetch(node_texels, t + 2);
        n.refs = texelFetch(node_texels, t + 3);
    } else {
#ifdef VKRT_SPLIT_ARRAYS
        if (SPLIT_NODES != 0u)
            n = QuadChunk(split_chunk(VKRT_SPLIT_NODES, node, SPLIT_NODES))
                    .v[split_index(node, SPLIT_NODES)];
        else
#endif
            n = bvh_nodes[node];
    }
    if (TRAVERSAL_STATS)
        ++traversal_steps;
    uint meta = floatBitsToUint(n.origin.w);
    vec3 scale = vec3(uintBitsToFloat((meta & 0xFFu) << 23),
                      uintBitsToFloat(((meta >> 8) & 0xFFu) << 23),
                      uintBitsToFloat(((meta >> 16) & 0xFFu) << 23));
    /* q * scale is exact, so each decoded plane is rounded once whether or not the
     * compiler fuses; precise keeps it from being merged into the distances' fma below. */
    precise vec4 x_lo = n.origin.x + plane_bytes(n.planes.x) * scale.x;
    precise vec4 x_hi = n.origin.x + plane_bytes(n.planes.y) * scale.x;
    precise vec4 y_lo = n.origin.y + plane_bytes(n.planes.z) * scale.y;
    precise vec4 y_hi = n.origin.y + plane_bytes(n.planes.w) * scale.y;
    precise vec4 z_lo = n.origin.z + plane_bytes(n.planes_z.x) * scale.z;
    precise vec4 z_hi = n.origin.z + plane_bytes(n.planes_z.y) * scale.z;
    vec4 tx0 = fma(x_lo, vec4(b.inv_dir.x), vec4(b.lo_bias.x));
    vec4 tx1 = fma(x_hi, vec4(b.inv_dir.x), vec4(b.hi_bias.x));
    vec4 ty0 = fma(y_lo, vec4(b.inv_dir.y), vec4(b.lo_bias.y));
    vec4 ty1 = fma(y_hi, vec4(b.inv_dir.y), vec4(b.hi_bias.y));
    vec4 tz0 = fma(z_lo, vec4(b.inv_dir.z), vec4(b.lo_bias.z));
    vec4 tz1 = fma(z_hi, vec4(b.inv_dir.z), vec4(b.hi_bias.z));
    vec4 enter = max(max(min(tx0, tx1), min(ty0, ty1)), max(min(tz0, tz1), vec4(tmin)));
    vec4 leave = min(min(max(tx0, tx1), max(ty0, ty1)), min(max(tz0, tz1), vec4(hit_t)));
    /* Missed children, and the slots past the node's child count, sort last as +inf. */
    vec4 key = mix(vec4(inf), enter, lessThanEqual(enter, leave * BOX_EXIT_SCALE));
    key = mix(vec4(inf), key, lessThan(uvec4(0u, 1u, 2u, 3u), uvec4(meta >> 24)));
    float k0 = key.x, k1 = key.y, k2 = key.z, k3 = key.w;
    uint r0 = n.refs.x, r1 = n.refs.y, r2 = n.refs.z, r3 = n.refs.w;
    order_pair(k0, r0, k1, r1);
    order_pair(k2, r2, k3, r3);
    order_pair(k0, r0, k2, r2);
    order_pair(k1, r1, k3, r3);
    order_pair(k1, r1, k2, r2);
    push_far = k3 != inf ? r3 : NO_NODE;
    push_mid = k2 != inf ? r2 : NO_NODE;
    push_near = k1 != inf ? r1 : NO_NODE;
    return k0 != inf ? r0 : NO_NODE;
}

/* The nested walk's traversal stack: subtrees still to visit, the nearest on top. The host
 * refused trees whose paths could overflow it (one entry per level of pairs, up to 3 per level of
 * quads); the checks below only keep a corrupt tree from writing past it. (The one-loop walk
 * keeps a stack of its own, below.) */
uint bvh_stack[BVH_STACK_SIZE];
int bvh_top = 0;

void bvh_push(uint ref)
{
    if (ref != NO_NODE && bvh_top < BVH_STACK_SIZE)
        bvh_stack[bvh_top++] = ref;
}

/* The top of the stack, or NO_NODE when it is empty. */
uint bvh_pop()
{
    return bvh_top > 0 ? bvh_stack[--bvh_top] : NO_NODE;
}

/* One step of the nested walk at inner node `node` of either width: pushes the other children hit
 * and returns the one to visit next, or NO_NODE. */
uint bvh_node_step(SlabRay b, float tmin, float hit_t, bool any_hit, uint node)
{
    uint push_far, push_mid = NO_NODE, push_near = NO_NODE;
    uint next;
    if (BVH_WIDTH == 2u)
        next = bvh_pair_step(b, tmin, hit_t, any_hit, node, push_far);
    else
        next = bvh_quad_step(b, tmin, hit_t, node, push_far, push_mid, push_near);
    bvh_push(push_far);
    bvh_push(push_mid);
    bvh_push(push_near);
    return next;
}

/* Tests leaf reference `leaf`'s triangles; true when one was hit. */
bool bvh_leaf_ref(RayShear s, uint leaf, float tmin, inout Hit hit)
{
    return bvh_leaf(s, leaf & 0x07FFFFFFu, ((leaf >> 27) & 0xFu) + 1u, tmin, hit);
}

/* One step of a one-loop walk at inner node ref of either width, on its own stack (an array of
 * the walk's function, which the GPUs keep faster than a global one): ref becomes the child to
 * visit next, or NO_NODE, and the other children hit are pushed, the nearest last. A macro, not
 * a function: GLSL would copy the stack in and out of a call. The pairs' push is unchecked (one
 * entry per level at most, and the host refused deeper trees). */
#define BVH_ONE_LOOP_STEP(b, tmin, hit_t, any_hit, ref, stack, top)                            \
    if (BVH_WIDTH == 2u) {                                                                     \
        uint push;                                                                             \
        ref = bvh_pair_step(b, tmin, hit_t, any_hit, ref, push);                               \
        if (push != NO_NODE)                                                                   \
            stack[top++] = push;                                                               \
    } else {                                                                                   \
        uint far, mid, near;                                                                   \
        ref = bvh_quad_step(b, tmin, hit_t, ref, far, mid, near);                              \
        if (far != NO_NODE && top < BVH_STACK_SIZE)                                            \
            stack[top++] = far;                                                                \
        if (mid != NO_NODE && top < BVH_STACK_SIZE)                                            \
            stack[top++] = mid;                                                                \
        if (near != NO_NODE && top < BVH_STACK_SIZE)                                           \
            stack[top++] = near;                                                               \
    }

/* The walk as one loop that visits a node or a leaf per iteration ("if-if", Aila and Laine, HPG
 * 2009): the default on GPUs. Its stack is an array of this function's, and the pairs' push is
 * unchecked (the host refused deeper trees): the nested walk's stack and helpers made it slower
 * on GPUs (docs/performance.md). */
Hit bvh_traverse_one_loop(RayShear s, SlabRay b, float tmin, float tmax, bool any_hit)
{
    Hit hit = Hit(tmax, 0.0, 0.0, VKRT_NO_HIT);
    uint stack[BVH_STACK_SIZE];
    int top = 0;
    uint ref = 0u; /* the root node: a tree of one leaf has a record too */
    while (true) {
        if ((ref & VKRT_BVH_LEAF) != 0u) {
            if (bvh_leaf_ref(s, ref, tmin, hit) && any_hit)
                return hit;
            ref = NO_NODE;
        } else {
            BVH_ONE_LOOP_STEP(b, tmin, hit.t, any_hit, ref, stack, top);
        }
        if (ref == NO_NODE) {
            /* Pop the next subtree or leaf; its box was hit when it was pushed, and may since lie
             * beyond the closest hit, which its own box tests (or triangle tests) catch. */
            if (top == 0)
                break;
            ref = stack[--top];
        }
    }
    return hit;
}

/* Whether every lane of the subgroup still walking has c: with subgroup operations, else this
 * lane's c (the nested walk then stops at a lane's second leaf). */
#ifdef VKRT_SUBGROUPS
#define VKRT_ALL_LANES(c) subgroupAll(c)
#else
#define VKRT_ALL_LANES(c) (c)
#endif

/* The walk as two loops in a loop ("while-while", Aila and Laine, HPG 2009, section 3, with their
 * speculative traversal): inner nodes in one, leaves in the other. A lane postpones the first
 * leaf it meets and walks on from the stack; the node loop ends at a lane's second leaf or when
 * every lane of the subgroup still walking holds one. The default on CPU devices, which run both
 * sides of every branch that any lane takes, so that in the one-loop walk each iteration pays for
 * a triangle test and a node step; on GPUs it is slower (docs/performance.md). Each loop pops at
 * most once per iteration: a CPU device gathers a pop lane by lane, whether or not a lane pops. */
Hit bvh_traverse_nested(RayShear s, SlabRay b, float tmin, float tmax, bool any_hit)
{
    Hit hit = Hit(tmax, 0.0, 0.0, VKRT_NO_HIT);
    bvh_top = 0;
    uint ref = 0u, leaf = NO_NODE;
    /* NO_NODE has the leaf bit set: a reference without it is an inner node. */
    while (ref != NO_NODE) {
        while ((ref & VKRT_BVH_LEAF) == 0u) {
            ref = bvh_node_step(b, tmin, hit.t, any_hit, ref);
            if (leaf == NO_NODE && ref != NO_NODE && (ref & VKRT_BVH_LEAF) != 0u) {
                leaf = ref;
                ref = NO_NODE;
            }
            if (ref == NO_NODE)
                ref = bvh_pop();
            if (VKRT_ALL_LANES(leaf != NO_NODE))
                break;
        }
        /* The postponed leaf, then each leaf met next, until the walk is at an inner node again
         * or done: one place in the code for the triangle test. */
        while (true) {
            if (leaf == NO_NODE && ref != NO_NODE && (ref & VKRT_BVH_LEAF) != 0u) {
                leaf = ref;
                ref = bvh_pop();
            }
            if (leaf == NO_NODE)
                break;
            if (bvh_leaf_ref(s, leaf, tmin, hit) && any_hit)
                return hit;
            leaf = NO_NODE;
        }
    }
    return hit;
}

/* The closest hit (any_hit false) or the first hit found (any_hit true) in (tmin, tmax). */
Hit bvh_traverse(RayShear s, vec3 dir, float tmin, float tmax, bool any_hit)
{
    SlabRay b = slab_ray_make(s.origin, dir);
    if (NESTED_WALK)
        return bvh_traverse_nested(s, b, tmin, tmax, any_hit);
    return bvh_traverse_one_loop(s, b, tmin, tmax, any_hit);
}

#endif
