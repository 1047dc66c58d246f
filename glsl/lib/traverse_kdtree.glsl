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

/* Leaf n's triangles, counted; true when any_hit and one was hit. */
bool kd_leaf(RayShear s, KdNode n, float tmin, bool any_hit, inout Hit hit)
{
    if (TRAVERSAL_STATS) {
        traversal_tests += n.b;
        ++traversal_leaves;
    }
    return test_references(s, n.a, n.a + n.b, tmin, any_hit, hit);
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
        if (kd_leaf(s, n, tmin, any_hit, hit))
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

/* A rope: none, the face lies on the root box (src/accel/kdtree_ropes.h KD_NO_ROPE). */
const uint KD_NO_ROPE = 0xFFFFFFFFu;

/* The rope walk (Popov, Günther, Seidel and Slusallek 2007), for rays with no direction component
 * 0: descend from a node to the leaf the ray is in at t, test its triangles, leave through the
 * exit face (the nearest of the leaf box's three faces ahead of the ray) and descend again from
 * the node across it, the rope (src/accel/kdtree_ropes.c). Hits are kept as in kd_traverse (any
 * hit closer than the best), and the walk ends after a leaf whose exit lies beyond the best hit.
 *
 * Robustness: the descent asks, at each plane, whether t has passed the plane's distance, computed
 * as the exit's is. The rope has already taken the walk across the face just left; a plane below
 * the rope in that face (a flat cell's, holding the triangles in the face) ties with t and goes to
 * the near side, so the flat cell is visited before the cell beyond. Each rope leads into the far child of the plane the face lies in, so
 * every leaf comes after the last in the tree's front-to-back order for the ray's octant: the walk
 * ends whatever rounding does. A hit within 2^-20 of the exit does not end the walk (the next
 * leaf may hold a tie on the face).
 *
 * Edges of cells: where the ray passes within the margin of a line where cells meet (two exit
 * faces within 2^-18 of each other, or a plane within 2^-20 of t on the way down), one path of
 * cells visits only some of those around the line, and a triangle touching the line from a cell
 * skipped is lost: a ray aimed at a vertex that perfect splits put on two planes leaked so (58 of
 * test_accel's 3,072 rays at the icosphere's vertices, 100 at the bunny's). There the stack walk
 * (kd_traverse) covers the stretch of 2^-18 either side, with its overlapping margins. */
Hit kd_rope_traverse(RayShear s, vec3 dir, float tmin, float tmax, bool any_hit)
{
    Hit hit = Hit(tmax, 0.0, 0.0, VKRT_NO_HIT);
    vec3 origin = s.origin;
    vec3 inv_dir = 1.0 / dir;
    vec2 span = slab_interval(grid.lo.xyz, grid.hi.xyz, origin, inv_dir, tmin, tmax);
    float t = max(tmin, span.x - abs(span.x) * KD_MARGIN);
    float t1 = min(tmax, span.y + abs(span.y) * KD_MARGIN);
    if (!(t <= t1))
        return hit;
    bvec3 ahead = greaterThan(dir, vec3(0.0));
    uint node = 0u;
    while (true) {
        /* The descent met a plane within the margin of t (see the top). */
        bool corner = false;
        KdNode n = load_kd_node(node);
        while (n.axis != VKRT_KD_LEAF) {
            if (TRAVERSAL_STATS)
                ++traversal_steps;
            float t_split = (n.split - origin[n.axis]) * inv_dir[n.axis];
            bool near_side = t <= t_split;
            corner = corner || abs(t - t_split) <= abs(t) * KD_MARGIN;
            node = near_side == ahead[n.axis] ? n.a : n.b;
            n = load_kd_node(node);
        }
        if (kd_leaf(s, n, tmin, any_hit, hit))
            return hit;
        /* The leaf's record: lo.xyz hi.x | hi.yz rope0 rope1 | rope2 .. rope5. */
        uint at = floatBitsToUint(n.split);
        KdNode r0 = load_kd_node(at), r1 = load_kd_node(at + 1u), r2 = load_kd_node(at + 2u);
        vec3 lo = vec3(r0.split, uintBitsToFloat(r0.axis), uintBitsToFloat(r0.a));
        vec3 hi = vec3(uintBitsToFloat(r0.b), r1.split, uintBitsToFloat(r1.axis));
        vec3 t_face = (mix(lo, hi, ahead) - origin) * inv_dir;
        float t_exit = t_face.x;
        uvec2 ropes = uvec2(r1.a, r1.b);
        bool up = ahead.x;
        if (t_face.y < t_exit) {
            t_exit = t_face.y;
            ropes = uvec2(floatBitsToUint(r2.split), r2.axis);
            up = ahead.y;
        }
        if (t_face.z < t_exit) {
            t_exit = t_face.z;
            ropes = uvec2(r2.a, r2.b);
            up = ahead.z;
        }
        /* Near an edge of cells, where the one path misses a cell: the stack walk over the
         * stretch there (see the top). */
        float band = 4.0 * KD_MARGIN;
        float reach = t_exit + abs(t_exit) * band;
        bool exit_corner =
            int(t_face.x <= reach) + int(t_face.y <= reach) + int(t_face.z <= reach) > 1;
        if (corner || exit_corner) {
            float lo_t = corner ? t - abs(t) * band : t_exit - abs(t_exit) * band;
            float hi_t = exit_corner ? t_exit + abs(t_exit) * band : t + abs(t) * band;
            Hit near = kd_traverse(s, dir, max(tmin, lo_t), min(hit.t, hi_t), any_hit);
            if (near.triangle != VKRT_NO_HIT) {
                hit = near;
                if (any_hit)
                    return hit;
            }
        }
        if (hit.triangle != VKRT_NO_HIT && hit.t < t_exit - abs(t_exit) * KD_MARGIN)
            break;
        node = up ? ropes.y : ropes.x;
        if (node == KD_NO_ROPE || t_exit > t1)
            break;
        t = max(t, t_exit);
    }
    return hit;
}

/* The kd-tree's walk: ropes where KD_ROPES asks for them and the ray has an octant (no direction
 * component 0, whose ray may run in a plane and need both its sides: the stack walk's case). */
Hit kd_walk(RayShear s, vec3 dir, float tmin, float tmax, bool any_hit)
{
    if (KD_ROPES && all(notEqual(dir, vec3(0.0))) && !any(isinf(1.0 / dir)))
        return kd_rope_traverse(s, dir, tmin, tmax, any_hit);
    return kd_traverse(s, dir, tmin, tmax, any_hit);
}

#endif
