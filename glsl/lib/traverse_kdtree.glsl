/*
 * traverse_kdtree.glsl: the kd-tree's walk (src/accel/kdtree.c builds it), front to back with a
 * stack of the far children still to visit and the stretch of the ray inside each: the sequential
 * walk of Havran's thesis and Wald's (the seed thesis's Algorithm 4), without recursion.
 *
 * The ray is clipped to the root box; at an inner node, the plane's distance t_split cuts the
 * node's stretch [t0, t1] into the near child's and the far child's. Where the ray crosses both,
 * the far child and its stretch are pushed and the near child is visited.
 *
 * Hits: a triangle lies in every leaf its part touches, so it may be hit beyond the current
 * leaf, inside a leaf still to come. Any hit closer than the best so far is kept (the triangle
 * test's interval is (tmin, best t), not the leaf's), and the walk ends after a leaf whose stretch
 * reaches the best hit: every leaf after it lies farther along the ray. A triangle met again in a
 * later leaf is tested again (no mailbox); it cannot replace itself, as its t is not below its own.
 *
 * Robustness: t_split = (split - origin) / dir rounds, and so do the root box's distances, each
 * to within a few units of rounding of itself. So the near child's stretch ends at t_split
 * (1 + 2^-20) and the far child's starts at t_split (1 - 2^-20): a ray that crosses a plane
 * where it meets a triangle lying in that plane, or a triangle ending on it, visits both sides
 * and is not lost to rounding (about 8 units of rounding of margin, for an error of 3). A
 * component of the direction that is 0 (or whose inverse overflows) never crosses the plane: the
 * ray stays on its origin's side, and when it runs in the plane itself it visits both children
 * with the whole stretch, since a triangle that touches the plane went to one side or the other;
 * and no hit in the first ends the walk before the second is seen (the two stretches are one). An origin on
 * the plane goes to the side the direction points into. Needs bindings.glsl, intersect.glsl,
 * traverse_bvh.glsl (safe_inverse, slab_interval, the statistics) and traverse_grid.glsl
 * (test_references) included first.
 */
#ifndef VKRT_TRAVERSE_KDTREE_GLSL
#define VKRT_TRAVERSE_KDTREE_GLSL

const int KD_STACK_SIZE = VKRT_KD_STACK_SIZE;

/* The relative margin of every plane's and the root box's distances (see the top). */
const float KD_MARGIN = 1.0 / 1048576.0;

/* A stack entry's top bit: the walk is blocked from ending there (kd_traverse's `blocked`). */
const uint KD_BLOCKED = 0x80000000u;

KdNode load_kd_node(uint i)
{
    if (TEXEL_LOADS) {
        uvec4 t = texelFetch(node_texels, int(i));
        return KdNode(uintBitsToFloat(t.x), t.y, t.z, t.w);
    }
#ifdef VKRT_SPLIT_ARRAYS
    if (SPLIT_NODES != 0u)
        return KdChunk(split_chunk(VKRT_SPLIT_NODES, i, SPLIT_NODES)).v[split_index(i, SPLIT_NODES)];
#endif
    return kd_nodes[i];
}

/* The closest hit (any_hit false) or the first hit found (any_hit true) in (tmin, tmax). */
Hit kd_traverse(RayShear s, vec3 dir, float tmin, float tmax, bool any_hit)
{
    Hit hit = Hit(tmax, 0.0, 0.0, VKRT_NO_HIT);
    vec3 origin = s.origin;
    vec2 span = slab_interval(grid.lo.xyz, grid.hi.xyz, origin, safe_inverse(dir), tmin, tmax);
    float t0 = max(tmin, span.x - abs(span.x) * KD_MARGIN);
    float t1 = min(tmax, span.y + abs(span.y) * KD_MARGIN);
    if (!(t0 <= t1))
        return hit;
    vec3 inv_dir = 1.0 / dir;
    uint stack_node[KD_STACK_SIZE];
    float stack_t0[KD_STACK_SIZE];
    float stack_t1[KD_STACK_SIZE];
    int top = 0;
    uint node = 0u;
    /* Set inside the near child of a plane the ray runs in, until its sibling is popped: the two
     * share the stretch, so a hit in it ends nothing (the sibling may hold a closer one). The
     * stack keeps it in its entries' top bit. */
    bool blocked = false;
    while (true) {
        /* Down to a leaf. */
        KdNode n = load_kd_node(node);
        while (n.axis != VKRT_KD_LEAF) {
            if (TRAVERSAL_STATS)
                ++traversal_steps;
            float o = origin[n.axis], d = dir[n.axis], inv = inv_dir[n.axis];
            bool below_first = o < n.split || (o == n.split && d <= 0.0);
            uint near = below_first ? n.a : n.b;
            uint far = below_first ? n.b : n.a;
            float t_split = (n.split - o) * inv;
            bool both;
            bool in_plane = false;
            if (d == 0.0 || isinf(inv)) {
                /* Parallel to the plane: in it, both sides; else the origin's. */
                in_plane = o == n.split;
                both = in_plane;
            } else if (t_split <= 0.0 || t_split * (1.0 - KD_MARGIN) > t1) {
                /* Moving away from the plane, or reaching it past this stretch. */
                both = false;
            } else if (t_split * (1.0 + KD_MARGIN) < t0) {
                /* The plane lies before this stretch: only the far side. */
                both = false;
                near = far;
            } else {
                /* Both: the far child, from the plane on, waits on the stack (the host made
                 * no tree deeper than the stack). */
                both = true;
            }
            if (both && top < KD_STACK_SIZE) {
                stack_node[top] = far | (blocked ? KD_BLOCKED : 0u);
                stack_t0[top] = in_plane ? t0 : max(t0, t_split * (1.0 - KD_MARGIN));
                stack_t1[top] = t1;
                ++top;
                if (in_plane)
                    blocked = true;
                else
                    t1 = min(t1, t_split * (1.0 + KD_MARGIN));
            }
            node = near;
            n = load_kd_node(node);
        }
        /* The leaf's triangles. */
        if (TRAVERSAL_STATS) {
            traversal_tests += n.b;
            ++traversal_leaves;
        }
        if (test_references(s, n.a, n.a + n.b, tmin, any_hit, hit))
            return hit;
        /* Done when the closest hit lies within this leaf's stretch, or nothing is left. */
        if (hit.triangle != VKRT_NO_HIT && hit.t <= t1 && !blocked)
            break;
        if (top == 0)
            break;
        --top;
        node = stack_node[top] & ~KD_BLOCKED;
        blocked = (stack_node[top] & KD_BLOCKED) != 0u;
        t0 = stack_t0[top];
        t1 = stack_t1[top];
        if (hit.t < t0)
            break;
    }
    return hit;
}

#endif
