/*
 * test_bvh.c: tests of the binned-SAH BVH builder (src/accel/bvh.h; Wald 2007, "On fast
 * construction of SAH-based bounding volume hierarchies").
 *
 * Every tree built here goes through check_tree, which checks the layout contract of bvh.h
 * (reachability, adjacent siblings, leaf ranges tiling the triangle order, tight and nested
 * bounds, leaf sizes, the statistics). Trees over random soups, degenerate inputs and, when
 * $VKRT_SCENES_DIR is set, the Stanford bunny and Lost Empire are then traced by a simple CPU
 * traversal (slab test, double-precision Moller-Trumbore) that must find the same closest hit as
 * a brute-force loop over all triangles. Builds with 1, 2 and more threads must be identical,
 * because the builder is deterministic.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <cmocka.h>

#include "accel/bvh.h"
#include "accel/bvh_pairs.h"
#include "accel/bvh_quads.h"
#include "accel/bvh_spatial.h"
#include "scene/obj/obj_load.h"

enum { FLOATS_PER_TRI = 9 };
enum { SOUP_SEED = 12345, RAY_SEED = 777 };
enum { DEFAULT_MAX_LEAF = 8 }; /* bvh.h's default for max_leaf_size 0 */

/* Ray counts: a few thousand against the soups, fewer against the big meshes because the
 * brute-force reference costs rays * triangles. */
enum { SOUP_RAYS = 3000, BUNNY_RAYS = 2000, EMPIRE_RAYS = 300 };

/* Slack of the test's slab test, relative to t: the box test and Moller-Trumbore round
 * differently, and a hit exactly on a box face (flat scenes) must not be lost to that. */
#define SLAB_SLACK 1e-9

/* The reported SAH cost is a float sum; the test recomputes it in double. */
#define SAH_REL_TOL 1e-4

/* Timings printed for the real scenes take the best of this many builds. */
enum { TIMING_RUNS = 3 };

/* ------------------------------------------------------------------------ random numbers */

typedef struct rng {
    uint64_t s;
} rng;

/* splitmix64: small, fixed-seed, the same on every platform. */
static uint64_t rng_next(rng *r)
{
    uint64_t z = (r->s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* Uniform in [0, 1). */
static double rng_unit(rng *r)
{
    return (double)(rng_next(r) >> 11) * (1.0 / 9007199254740992.0);
}

static double rng_range(rng *r, double lo, double hi)
{
    return lo + (hi - lo) * rng_unit(r);
}

/* ------------------------------------------------------------------------ scenes */

static float *alloc_tris(uint32_t n)
{
    float *p = malloc((size_t)n * FLOATS_PER_TRI * sizeof *p);
    assert_non_null(p);
    return p;
}

/* n triangles with random centres in a cube of side extent, vertices within size of the centre. */
static float *make_soup(uint32_t n, uint64_t seed, double extent, double size)
{
    rng r = { seed };
    float *p = alloc_tris(n);
    for (uint32_t i = 0; i < n; i++) {
        double c[3] = { rng_range(&r, 0, extent), rng_range(&r, 0, extent),
                        rng_range(&r, 0, extent) };
        for (int k = 0; k < FLOATS_PER_TRI; k++)
            p[i * FLOATS_PER_TRI + k] = (float)(c[k % 3] + rng_range(&r, -size, size));
    }
    return p;
}

/* A flat grid of side x side quads (two triangles each) in the plane z = 0. */
static float *make_plane(uint32_t side, uint32_t *n)
{
    *n = side * side * 2;
    float *p = alloc_tris(*n);
    float *w = p;
    for (uint32_t y = 0; y < side; y++) {
        for (uint32_t x = 0; x < side; x++) {
            float x0 = (float)x, x1 = (float)x + 1, y0 = (float)y, y1 = (float)y + 1;
            const float quad[2][FLOATS_PER_TRI] = { { x0, y0, 0, x1, y0, 0, x1, y1, 0 },
                                                    { x0, y0, 0, x1, y1, 0, x0, y1, 0 } };
            memcpy(w, quad, sizeof quad);
            w += 2 * FLOATS_PER_TRI;
        }
    }
    return p;
}

/* Zero-area triangles: points, collinear corners, repeated corners, mixed with real ones. */
static float *make_degenerate(uint32_t n, uint64_t seed)
{
    rng r = { seed };
    float *p = make_soup(n, seed, 10.0, 1.0);
    for (uint32_t i = 0; i < n; i++) {
        float *t = p + (size_t)i * FLOATS_PER_TRI;
        switch (rng_next(&r) % 4) {
        case 0: /* a point */
            memcpy(t + 3, t, 3 * sizeof *t);
            memcpy(t + 6, t, 3 * sizeof *t);
            break;
        case 1: /* collinear: the third corner halfway along the first edge, in float */
            for (int a = 0; a < 3; a++)
                t[6 + a] = t[a] + (t[3 + a] - t[a]) * 0.5f;
            break;
        case 2: /* two equal corners */
            memcpy(t + 6, t + 3, 3 * sizeof *t);
            break;
        default: /* a real triangle */
            break;
        }
    }
    return p;
}

/* All triangles on one segment of the x axis: the root box has zero area. */
static float *make_line(uint32_t n)
{
    float *p = alloc_tris(n);
    for (uint32_t i = 0; i < n; i++) {
        float x = (float)i;
        const float t[FLOATS_PER_TRI] = { x, 0, 0, x + 0.5f, 0, 0, x + 1.0f, 0, 0 };
        memcpy(p + (size_t)i * FLOATS_PER_TRI, t, sizeof t);
    }
    return p;
}

/* Triangles of very different sizes: every tenth spans a large part of the scene. */
static float *make_huge_tiny(uint32_t n, uint64_t seed)
{
    rng r = { seed };
    float *p = alloc_tris(n);
    for (uint32_t i = 0; i < n; i++) {
        double size = i % 10 == 0 ? 1e5 : 1e-3;
        double c[3] = { rng_range(&r, -1e4, 1e4), rng_range(&r, -1e4, 1e4),
                        rng_range(&r, -1e4, 1e4) };
        for (int k = 0; k < FLOATS_PER_TRI; k++)
            p[i * FLOATS_PER_TRI + k] = (float)(c[k % 3] + rng_range(&r, -size, size));
    }
    return p;
}

/* ------------------------------------------------------------------------ tree checks */

static void tri_bounds(const float *tri, float lo[3], float hi[3])
{
    for (int a = 0; a < 3; a++) {
        lo[a] = fminf(fminf(tri[a], tri[3 + a]), tri[6 + a]);
        hi[a] = fmaxf(fmaxf(tri[a], tri[3 + a]), tri[6 + a]);
    }
}

static double half_area(const float lo[3], const float hi[3])
{
    double d[3] = { (double)hi[0] - lo[0], (double)hi[1] - lo[1], (double)hi[2] - lo[2] };
    return d[0] * d[1] + d[1] * d[2] + d[2] * d[0];
}

/* A leaf's bounds must equal the union of its triangles' vertices, bit for bit; with spatial
 * splits (clipped), lie within that union. */
static void check_leaf(const bvh *b, const bvh_node *nd, const float *pos, uint32_t max_leaf,
                       bool clipped, uint32_t *cover)
{
    assert_true(nd->count <= max_leaf);
    assert_true((uint64_t)nd->left_first + nd->count <= b->prim_count);
    float lo[3] = { INFINITY, INFINITY, INFINITY }, hi[3] = { -INFINITY, -INFINITY, -INFINITY };
    for (uint32_t i = nd->left_first; i < nd->left_first + nd->count; i++) {
        cover[i]++;
        float tlo[3], thi[3];
        tri_bounds(pos + (size_t)b->prim_order[i] * FLOATS_PER_TRI, tlo, thi);
        for (int a = 0; a < 3; a++) {
            assert_true(clipped || (tlo[a] >= nd->lo[a] && thi[a] <= nd->hi[a]));
            lo[a] = fminf(lo[a], tlo[a]);
            hi[a] = fmaxf(hi[a], thi[a]);
        }
    }
    if (clipped) {
        for (int a = 0; a < 3; a++)
            assert_true(lo[a] <= nd->lo[a] && nd->lo[a] <= nd->hi[a] && nd->hi[a] <= hi[a]);
        return;
    }
    for (int a = 0; a < 3; a++) { /* the builder's records hold +0 for -0 (bvh.c) */
        lo[a] += 0.0f;
        hi[a] += 0.0f;
    }
    assert_memory_equal(lo, nd->lo, sizeof lo);
    assert_memory_equal(hi, nd->hi, sizeof hi);
}

/* An inner node's bounds must equal the union of its children's. */
static void check_inner(const bvh *b, const bvh_node *nd)
{
    assert_true((uint64_t)nd->left_first + 1 < b->node_count);
    assert_true(nd->left_first > 0);
    const bvh_node *l = &b->nodes[nd->left_first], *r = l + 1;
    for (int a = 0; a < 3; a++) {
        assert_true(l->lo[a] >= nd->lo[a] && l->hi[a] <= nd->hi[a]);
        assert_true(r->lo[a] >= nd->lo[a] && r->hi[a] <= nd->hi[a]);
        assert_true(fminf(l->lo[a], r->lo[a]) == nd->lo[a]);
        assert_true(fmaxf(l->hi[a], r->hi[a]) == nd->hi[a]);
    }
}

/* Checks everything bvh.h promises about a tree over n triangles at pos, built with a spatial
 * splits' budget (0: none). */
static void check_tree(const bvh *b, const float *pos, uint32_t n, uint32_t max_leaf,
                       float traversal_cost, float budget)
{
    uint32_t refs = b->prim_count;
    assert_int_equal(b->triangle_count, n);
    if (budget > 0)
        assert_true(refs >= n && refs <= (uint32_t)floor(n * (1.0 + budget)));
    else
        assert_int_equal(refs, n);
    assert_non_null(b->nodes);
    assert_non_null(b->prim_order);
    assert_true(b->node_count >= 1);

    /* prim_order holds every triangle: once each without spatial splits (a permutation) */
    uint32_t *seen = calloc(n, sizeof *seen);
    assert_non_null(seen);
    for (uint32_t i = 0; i < refs; i++) {
        assert_true(b->prim_order[i] < n);
        seen[b->prim_order[i]]++;
    }
    for (uint32_t i = 0; i < n; i++) {
        assert_true(seen[i] >= 1);
        assert_true(budget > 0 || seen[i] == 1);
    }
    free(seen);

    /* walk from the root, depth first, left before right: every node once, depths, leaf cover,
     * SAH, and the children of the k-th inner node at 2k + 1 (bvh.h; bvh_pairs.c relies on it) */
    uint32_t *visits = calloc(b->node_count, sizeof *visits);
    uint32_t *cover = calloc(refs, sizeof *cover);
    uint32_t (*stack)[2] = malloc(b->node_count * sizeof *stack); /* node, depth */
    assert_true(visits && cover && stack);
    uint32_t top = 0, leaves = 0, max_depth = 0, inner = 0;
    double root_area = half_area(b->nodes[0].lo, b->nodes[0].hi), sah = 0.0;
    stack[top][0] = 0;
    stack[top++][1] = 0;
    while (top > 0) {
        top--;
        uint32_t i = stack[top][0], depth = stack[top][1];
        assert_true(i < b->node_count);
        assert_int_equal(visits[i]++, 0);
        const bvh_node *nd = &b->nodes[i];
        double w = root_area > 0 ? half_area(nd->lo, nd->hi) / root_area : 1.0;
        if (nd->count > 0) {
            check_leaf(b, nd, pos, max_leaf, budget > 0, cover);
            leaves++;
            max_depth = depth > max_depth ? depth : max_depth;
            sah += nd->count * w;
            continue;
        }
        check_inner(b, nd);
        assert_int_equal(nd->left_first, 2 * inner++ + 1);
        sah += traversal_cost * w;
        for (uint32_t c = 2; c-- > 0;) {
            assert_true(top + 1 < b->node_count + 1);
            stack[top][0] = nd->left_first + c;
            stack[top++][1] = depth + 1;
        }
    }
    for (uint32_t i = 0; i < b->node_count; i++)
        assert_int_equal(visits[i], 1);
    for (uint32_t i = 0; i < refs; i++)
        assert_int_equal(cover[i], 1);
    assert_int_equal(b->leaf_count, leaves);
    assert_int_equal(b->node_count, 2 * leaves - 1);
    assert_int_equal(b->max_depth, max_depth);
    assert_true(fabs(b->sah_cost - sah) <= SAH_REL_TOL * sah);
    assert_true(b->build_ms >= 0.0);
    free(visits);
    free(cover);
    free(stack);
}

/* ------------------------------------------------------------------------ ray casting */

typedef struct ray {
    double o[3], d[3];
} ray;

typedef struct hit {
    double t;         /* INFINITY: none */
    uint32_t tri;
    uint32_t ties;    /* triangles at exactly t (brute force only) */
} hit;

/* Moller and Trumbore 1997, in double; a hit needs t > 0. Degenerate triangles never hit. */
static bool hit_triangle(const ray *r, const float *v, double *t)
{
    double e1[3], e2[3], s[3], p[3], q[3];
    for (int a = 0; a < 3; a++) {
        e1[a] = (double)v[3 + a] - v[a];
        e2[a] = (double)v[6 + a] - v[a];
        s[a] = r->o[a] - v[a];
    }
    p[0] = r->d[1] * e2[2] - r->d[2] * e2[1];
    p[1] = r->d[2] * e2[0] - r->d[0] * e2[2];
    p[2] = r->d[0] * e2[1] - r->d[1] * e2[0];
    double det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
    /* A triangle degenerate in float (collinear corners) is not quite so in double: its det is
     * rounding noise, and dividing by it puts a "hit" far off the triangle (seen: t = 0.65 for a
     * triangle whose box the ray enters at 0.99, which a traversal finds or not depending on
     * the order it visits leaves in). Such dets are below 1e-5 of |e1| |e2| |d|; the kernel
     * drops its own noise the same way (RELIABLE_DET_FRACTION in glsl/lib/intersect.glsl). */
    double scale = sqrt((e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]) *
                        (e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2]) *
                        (r->d[0] * r->d[0] + r->d[1] * r->d[1] + r->d[2] * r->d[2]));
    if (fabs(det) <= 1e-5 * scale)
        return false;
    double inv = 1.0 / det;
    double u = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) * inv;
    if (u < 0.0 || u > 1.0)
        return false;
    q[0] = s[1] * e1[2] - s[2] * e1[1];
    q[1] = s[2] * e1[0] - s[0] * e1[2];
    q[2] = s[0] * e1[1] - s[1] * e1[0];
    double w = (r->d[0] * q[0] + r->d[1] * q[1] + r->d[2] * q[2]) * inv;
    if (w < 0.0 || u + w > 1.0)
        return false;
    *t = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) * inv;
    return *t > 0.0;
}

static hit brute_force(const ray *r, const float *pos, uint32_t n)
{
    hit h = { INFINITY, UINT32_MAX, 0 };
    for (uint32_t i = 0; i < n; i++) {
        double t;
        if (!hit_triangle(r, pos + (size_t)i * FLOATS_PER_TRI, &t))
            continue;
        if (t < h.t) {
            h = (hit){ t, i, 1 };
        } else if (t == h.t) {
            h.ties++;
        }
    }
    return h;
}

/* Slab test; returns the entry distance or INFINITY on a miss. Axes the ray runs parallel to
 * only check that the origin lies between the slab's planes. */
static double enter_box(const ray *r, const bvh_node *nd)
{
    double tmin = 0.0, tmax = INFINITY;
    for (int a = 0; a < 3; a++) {
        if (r->d[a] == 0.0) {
            if (r->o[a] < nd->lo[a] || r->o[a] > nd->hi[a])
                return INFINITY;
            continue;
        }
        double t0 = (nd->lo[a] - r->o[a]) / r->d[a], t1 = (nd->hi[a] - r->o[a]) / r->d[a];
        tmin = fmax(tmin, fmin(t0, t1));
        tmax = fmin(tmax, fmax(t0, t1));
    }
    return tmin <= tmax + SLAB_SLACK * fabs(tmax) ? tmin : INFINITY;
}

static hit traverse(const bvh *b, const ray *r, const float *pos, uint32_t *stack)
{
    hit h = { INFINITY, UINT32_MAX, 0 };
    uint32_t top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const bvh_node *nd = &b->nodes[stack[--top]];
        double enter = enter_box(r, nd);
        if (enter == INFINITY || enter > h.t + SLAB_SLACK * h.t)
            continue;
        if (nd->count == 0) {
            stack[top++] = nd->left_first;
            stack[top++] = nd->left_first + 1;
            continue;
        }
        for (uint32_t i = nd->left_first; i < nd->left_first + nd->count; i++) {
            double t;
            uint32_t tri = b->prim_order[i];
            if (hit_triangle(r, pos + (size_t)tri * FLOATS_PER_TRI, &t) && t < h.t)
                h = (hit){ t, tri, 0 };
        }
    }
    return h;
}

/* A child word of either GPU layout into a node's first/count (bvh.h leaf references). */
static void decode_ref(uint32_t ref, bvh_node *n)
{
    if (ref & BVH_LEAF_REF) {
        n->left_first = ref & BVH_LEAF_REF_MAX_FIRST;
        n->count = ((ref >> 27) & 0xFu) + 1;
    } else {
        n->left_first = ref;
        n->count = 0;
    }
}

/* Child k of quad q as a node, its box decoded as the kernel decodes it, for enter_box. */
static bvh_node quad_child(const bvh_quad *q, int k)
{
    bvh_node n = { { 0 }, 0, { 0 }, 0 };
    bvh_quad_child_box(q, k, n.lo, n.hi);
    decode_ref(q->ref[k], &n);
    return n;
}

/* Child k of GPU node i of either layout as a node (its box, first and count), or false past the
 * node's children: the pairs' two float boxes, or the quads' boxes decoded as the kernel decodes
 * them. */
typedef struct gpu_layout {
    const bvh_pairs *pairs;   /* one of the two */
    const bvh_quads *quads;
} gpu_layout;

static bool layout_child(const gpu_layout *l, uint32_t i, int k, bvh_node *nd)
{
    if (l->pairs) {
        const bvh_pair *p = &l->pairs->nodes[i];
        if (k >= 2)
            return false;
        *nd = (bvh_node){ { p->x[2 * k], p->y[2 * k], p->z[2 * k] }, 0,
                          { p->x[2 * k + 1], p->y[2 * k + 1], p->z[2 * k + 1] }, 0 };
        decode_ref(p->ref[k], nd);
        return true;
    }
    if (k >= (int)(l->quads->nodes[i].meta >> 24))
        return false;
    *nd = quad_child(&l->quads->nodes[i], k);
    return true;
}

/* The walk over a GPU layout, as traverse walks the binary tree. */
static hit traverse_layout(const bvh *b, const gpu_layout *l, const ray *r, const float *pos,
                           uint32_t *stack)
{
    hit h = { INFINITY, UINT32_MAX, 0 };
    uint32_t top = 0;
    stack[top++] = 0;
    while (top > 0) {
        uint32_t node = stack[--top];
        bvh_node nd;
        for (int k = 0; layout_child(l, node, k, &nd); k++) {
            double enter = enter_box(r, &nd);
            if (enter == INFINITY || enter > h.t + SLAB_SLACK * h.t)
                continue;
            if (nd.count == 0) {
                stack[top++] = nd.left_first;
                continue;
            }
            for (uint32_t i = nd.left_first; i < nd.left_first + nd.count; i++) {
                double t;
                uint32_t tri = b->prim_order[i];
                if (hit_triangle(r, pos + (size_t)tri * FLOATS_PER_TRI, &t) && t < h.t)
                    h = (hit){ t, tri, 0 };
            }
        }
    }
    return h;
}

/* A ray from a random point of the (enlarged) scene box: half of them aim at a random point of
 * a random triangle, so most hit; the rest go in a random direction. */
static ray random_ray(rng *g, const bvh *b, const float *pos, uint32_t n)
{
    const bvh_node *root = &b->nodes[0];
    ray r;
    for (int a = 0; a < 3; a++) {
        double ext = (double)root->hi[a] - root->lo[a] + 1.0;
        r.o[a] = rng_range(g, root->lo[a] - ext * 0.5, root->hi[a] + ext * 0.5);
    }
    if (rng_next(g) % 2) {
        const float *v = pos + (size_t)(rng_next(g) % n) * FLOATS_PER_TRI;
        double u = rng_unit(g), w = rng_unit(g) * (1.0 - u);
        for (int a = 0; a < 3; a++)
            r.d[a] = v[a] + u * ((double)v[3 + a] - v[a]) + w * ((double)v[6 + a] - v[a]) - r.o[a];
    } else {
        for (int a = 0; a < 3; a++)
            r.d[a] = rng_range(g, -1.0, 1.0);
    }
    return r;
}

/* The BVH must find the brute-force closest hit: the same t, and the same triangle when no
 * other triangle is hit at exactly that t. Returns the number of hits, to check the rays do
 * test something. */
static uint32_t check_rays(const bvh *b, const float *pos, uint32_t n, uint32_t rays)
{
    rng g = { RAY_SEED };
    uint32_t *stack = malloc((b->node_count + 1) * sizeof *stack);
    assert_non_null(stack);
    bvh_quads quads;
    bvh_pairs pairs;
    vkrt_error err = { "" };
    if (!bvh_quads_build(b, &quads, &err) || !bvh_pairs_build(b, &pairs, &err))
        fail_msg("GPU layout failed: %s", err.msg);
    assert_int_equal(pairs.node_count, b->node_count > 1 ? (b->node_count - 1) / 2 : 1);
    /* Every reference is in exactly one leaf of the quads, and quads are fewer than binary inner
     * nodes (each replaces at least one). */
    uint32_t *seen = calloc(b->prim_count, sizeof *seen);
    assert_non_null(seen);
    for (uint32_t i = 0; i < quads.node_count; i++)
        for (int k = 0; k < (int)(quads.nodes[i].meta >> 24); k++) {
            bvh_node nd = quad_child(&quads.nodes[i], k);
            for (uint32_t t = nd.left_first; nd.count && t < nd.left_first + nd.count; t++)
                seen[t]++;
        }
    for (uint32_t i = 0; i < b->prim_count; i++)
        assert_int_equal(seen[i], 1);
    free(seen);
    assert_true(quads.node_count <= (b->node_count > 1 ? (b->node_count - 1) / 2 : 1));
    uint32_t hits = 0;
    for (uint32_t i = 0; i < rays; i++) {
        ray r = random_ray(&g, b, pos, n);
        hit ref = brute_force(&r, pos, n), got = traverse(b, &r, pos, stack);
        hit quad = traverse_layout(b, &(gpu_layout){ .quads = &quads }, &r, pos, stack);
        hit paired = traverse_layout(b, &(gpu_layout){ .pairs = &pairs }, &r, pos, stack);
        if (ref.t != got.t || ref.t != quad.t || ref.t != paired.t)
            fail_msg("ray %u: brute force t=%.17g tri %u, BVH t=%.17g tri %u, quads t=%.17g "
                     "tri %u, pairs t=%.17g tri %u", i, ref.t, ref.tri, got.t, got.tri, quad.t,
                     quad.tri, paired.t, paired.tri);
        if (ref.t != INFINITY && ref.ties == 1) {
            assert_int_equal(ref.tri, got.tri);
            assert_int_equal(ref.tri, quad.tri);
            assert_int_equal(ref.tri, paired.tri);
        }
        hits += ref.t != INFINITY;
    }
    bvh_quads_free(&quads);
    bvh_pairs_free(&pairs);
    free(stack);
    return hits;
}

/* ------------------------------------------------------------------------ helpers */

static void build_ok(bvh *b, const float *pos, uint32_t n, const bvh_build_desc *desc)
{
    vkrt_error err = { "" };
    if (!bvh_build(b, pos, n, desc, &err))
        fail_msg("bvh_build failed: %s", err.msg);
}

static uint32_t max_leaf_of(const bvh_build_desc *d)
{
    return d && d->max_leaf_size ? d->max_leaf_size : DEFAULT_MAX_LEAF;
}

static float traversal_cost_of(const bvh_build_desc *d)
{
    return d && d->traversal_cost != 0.0f ? d->traversal_cost : 1.0f;
}

/* Points of each triangle on a grid of barycentrics (POINT_STEPS + 1 per edge), checked for
 * clipping by check_points. */
enum { POINT_STEPS = 6 };

/* Whether point p lies in the box (in double, no slack: clipped boxes are rounded outwards). */
static bool box_holds(const bvh_node *nd, const double p[3])
{
    for (int a = 0; a < 3; a++)
        if (p[a] < nd->lo[a] || p[a] > nd->hi[a])
            return false;
    return true;
}

/* Whether some leaf that holds triangle tri, reached through boxes that all contain p, exists:
 * what a ray hitting tri at p needs of a tree whose leaves hold clipped triangles. */
static bool point_reaches(const bvh *b, uint32_t tri, const double p[3], uint32_t *stack)
{
    uint32_t top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const bvh_node *nd = &b->nodes[stack[--top]];
        if (!box_holds(nd, p))
            continue;
        if (nd->count == 0) {
            stack[top++] = nd->left_first;
            stack[top++] = nd->left_first + 1;
            continue;
        }
        for (uint32_t i = nd->left_first; i < nd->left_first + nd->count; i++)
            if (b->prim_order[i] == tri)
                return true;
    }
    return false;
}

/* Every point of the grid on every triangle reaches a leaf holding the triangle: fails when a
 * clipped reference's box lost part of its triangle. */
static void check_points(const bvh *b, const float *pos, uint32_t n)
{
    uint32_t *stack = malloc((b->node_count + 1) * sizeof *stack);
    assert_non_null(stack);
    for (uint32_t t = 0; t < n; t++) {
        const float *v = pos + (size_t)t * FLOATS_PER_TRI;
        for (int i = 0; i <= POINT_STEPS; i++)
            for (int j = 0; i + j <= POINT_STEPS; j++) {
                double u = (double)i / POINT_STEPS, w = (double)j / POINT_STEPS, p[3];
                /* Kept within the triangle's box: double rounding must not step off a flat
                 * triangle's plane or past a vertex's coordinate. */
                for (int a = 0; a < 3; a++)
                    p[a] = fmin(fmax(v[a] + u * ((double)v[3 + a] - v[a]) +
                                         w * ((double)v[6 + a] - v[a]),
                                     fmin(fmin(v[a], v[3 + a]), v[6 + a])),
                                fmax(fmax(v[a], v[3 + a]), v[6 + a]));
                if (!point_reaches(b, t, p, stack))
                    fail_msg("triangle %u, point (%g, %g) = (%.9g, %.9g, %.9g): no leaf on its "
                             "path holds the triangle", t, u, w, p[0], p[1], p[2]);
            }
    }
    free(stack);
}

static void assert_same_tree(const bvh *a, const bvh *b)
{
    assert_int_equal(a->node_count, b->node_count);
    assert_int_equal(a->prim_count, b->prim_count);
    assert_memory_equal(a->nodes, b->nodes, a->node_count * sizeof *a->nodes);
    assert_memory_equal(a->prim_order, b->prim_order, a->prim_count * sizeof *a->prim_order);
    assert_int_equal(a->leaf_count, b->leaf_count);
    assert_int_equal(a->max_depth, b->max_depth);
    assert_true(a->sah_cost == b->sah_cost);
}

/* Spatial-budget builds of the soups in which no node took a spatial split (printed by
 * test_crossed_clutter: the check in build_and_check must have run). */
static uint32_t unsplit_trees;

/* Builds with desc, checks the tree, casts rays when rays > 0. A tree with a spatial budget
 * whose nodes took no spatial split must be the plain build's (bvh.h; bvh-splits auto then
 * skips the plain build): checked against one. */
static void build_and_check(const float *pos, uint32_t n, const bvh_build_desc *desc,
                            uint32_t rays)
{
    bvh b;
    build_ok(&b, pos, n, desc);
    check_tree(&b, pos, n, max_leaf_of(desc), traversal_cost_of(desc),
               desc ? desc->spatial_budget : 0.0f);
    if (desc && desc->spatial_budget > 0) {
        check_points(&b, pos, n);
        if (b.spatial_splits == 0) {
            bvh_build_desc plain_desc = *desc;
            plain_desc.spatial_budget = 0.0f;
            bvh plain;
            build_ok(&plain, pos, n, &plain_desc);
            assert_same_tree(&plain, &b);
            bvh_free(&plain);
            unsplit_trees++;
        }
    } else {
        assert_int_equal(b.spatial_splits, 0);
    }
    if (rays > 0)
        check_rays(&b, pos, n, rays);
    bvh_free(&b);
}

/* The descriptors every synthetic input is built with. */
static const bvh_build_desc VARIANTS[] = {
    { 0, 0, 0, 0.0f },    /* defaults */
    { 1, 0, 1, 0.0f },    /* one triangle per leaf, one thread */
    { 4, 2, 2, 0.0f },    /* the fewest bins */
    { 16, 64, 3, 0.0f },  /* many bins, more threads than cores */
    { 8, 16, 2, 0.25f },  /* cheap traversal: deeper trees */
    { 8, 16, 2, 8.0f },   /* dear traversal: leaves as large as allowed */
    { 0, 0, 0, 0.0f, 0.3f },   /* spatial splits, defaults */
    { 1, 0, 1, 0.0f, 0.3f },   /* spatial splits, one triangle per leaf */
    { 4, 2, 2, 0.0f, 1.0f },   /* spatial splits, the fewest bins, the largest budget */
    { 16, 64, 3, 0.0f, 0.05f }, /* spatial splits, many bins, a small budget */
};
enum { VARIANT_COUNT = sizeof VARIANTS / sizeof VARIANTS[0] };

static void check_all_variants(const float *pos, uint32_t n, uint32_t rays)
{
    build_and_check(pos, n, NULL, rays);
    for (int v = 0; v < VARIANT_COUNT; v++)
        build_and_check(pos, n, &VARIANTS[v], v == 0 ? 0 : rays / VARIANT_COUNT);
}

/* ------------------------------------------------------------------------ tests */

static void test_errors(void **state)
{
    (void)state;
    vkrt_error err = { "" };
    bvh b;
    memset(&b, 0xff, sizeof b);
    float tri[FLOATS_PER_TRI] = { 0, 0, 0, 1, 0, 0, 0, 1, 0 };
    assert_false(bvh_build(&b, tri, 0, NULL, &err));
    assert_non_null(strstr(err.msg, "no triangles"));
    assert_null(b.nodes);
    assert_int_equal(b.node_count, 0);

    const bvh_build_desc bad[] = { { 0, 1, 0, 0 }, { 0, 100000, 0, 0 }, { 0, 0, 100000, 0 },
                                   { 0, 0, 0, -1.0f }, { 0, 0, 0, INFINITY } };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        err.msg[0] = 0;
        assert_false(bvh_build(&b, tri, 1, &bad[i], &err));
        assert_true(strlen(err.msg) > 0 && !strchr(err.msg, '\n'));
        assert_null(b.nodes);
        assert_null(b.prim_order);
    }

    float nan_tri[2 * FLOATS_PER_TRI] = { 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 1, NAN, 0, 0, 1, 0 };
    assert_false(bvh_build(&b, nan_tri, 2, NULL, &err));
    assert_non_null(strstr(err.msg, "triangle 1"));
    assert_false(bvh_build(&b, NULL, 3, NULL, &err));
    assert_false(bvh_build(&b, tri, 1, &bad[0], NULL)); /* a NULL err is allowed */

    bvh zero = { 0 };
    bvh_free(&zero);
    bvh_free(&zero);
}

static void test_single_triangle(void **state)
{
    (void)state;
    float tri[FLOATS_PER_TRI] = { 0, 0, 0, 1, 0, 0, 0, 1, 2 };
    bvh b;
    build_ok(&b, tri, 1, NULL);
    check_tree(&b, tri, 1, DEFAULT_MAX_LEAF, 1.0f, 0.0f);
    assert_int_equal(b.node_count, 1);
    assert_int_equal(b.nodes[0].count, 1);
    assert_int_equal(b.nodes[0].left_first, 0);
    assert_int_equal(b.max_depth, 0);
    assert_true(b.sah_cost == 1.0f);
    const float lo[3] = { 0, 0, 0 }, hi[3] = { 1, 1, 2 };
    assert_memory_equal(b.nodes[0].lo, lo, sizeof lo);
    assert_memory_equal(b.nodes[0].hi, hi, sizeof hi);
    bvh_free(&b);
    assert_null(b.nodes);
}

static void test_random_soups(void **state)
{
    (void)state;
    const uint32_t sizes[] = { 1, 2, 3, 100, 10000 };
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++) {
        float *pos = make_soup(sizes[i], SOUP_SEED + i, 100.0, 2.0);
        check_all_variants(pos, sizes[i], sizes[i] >= 100 ? SOUP_RAYS : 200);
        free(pos);
    }
}

/* With no centroid extent the builder must fall back to median splits and still terminate. */
static void test_identical_triangles(void **state)
{
    (void)state;
    enum { N = 1000 };
    float *pos = alloc_tris(N);
    const float tri[FLOATS_PER_TRI] = { 1, 2, 3, 4, 2, 3, 1, 6, 3 };
    for (uint32_t i = 0; i < N; i++)
        memcpy(pos + (size_t)i * FLOATS_PER_TRI, tri, sizeof tri);
    check_all_variants(pos, N, 500);
    bvh b;
    const bvh_build_desc one = { .max_leaf_size = 1 };
    build_ok(&b, pos, N, &one);
    assert_int_equal(b.leaf_count, N);
    assert_true(b.max_depth <= 10); /* median splits: ceil(log2(1000)) */
    bvh_free(&b);
    free(pos);
}

static void test_flat_plane(void **state)
{
    (void)state;
    uint32_t n;
    float *pos = make_plane(64, &n);
    check_all_variants(pos, n, SOUP_RAYS);
    free(pos);
}

static void test_degenerate_triangles(void **state)
{
    (void)state;
    enum { N = 3000 };
    float *pos = make_degenerate(N, SOUP_SEED);
    check_all_variants(pos, N, SOUP_RAYS);
    free(pos);
}

static void test_zero_area_root(void **state)
{
    (void)state;
    enum { N = 500 };
    float *pos = make_line(N);
    check_all_variants(pos, N, 0); /* rays cannot hit zero-area triangles */
    bvh b;
    build_ok(&b, pos, N, NULL);
    assert_true(isfinite(b.sah_cost));
    bvh_free(&b);
    free(pos);
}

static void test_huge_and_tiny(void **state)
{
    (void)state;
    enum { N = 5000 };
    float *pos = make_huge_tiny(N, SOUP_SEED);
    check_all_variants(pos, N, SOUP_RAYS);
    free(pos);
}

/* A soup in the positive octant where every fourth coordinate is zero, -0 and +0 in turn: many
 * node bounds are a min of both zeros, whose result (MINPS keeps the later operand) would depend
 * on the order the threads of the top levels (bvh_top.c) combine records in. */
static float *make_signed_zero_soup(uint32_t n)
{
    float *p = make_soup(n, SOUP_SEED + 1, 100.0, 1.0);
    for (size_t i = 0; i < (size_t)n * FLOATS_PER_TRI; i++)
        p[i] = i % 4 ? fabsf(p[i]) : (i / 4) % 2 ? -0.0f : 0.0f;
    return p;
}

/* The build is deterministic: any thread count gives the same bytes, the top levels split by
 * all threads (bvh_top.c, over 32768 triangles) included. */
static void check_threads_identical(float *pos, uint32_t n, float budget)
{
    bvh ref;
    const bvh_build_desc one = { .threads = 1, .spatial_budget = budget };
    build_ok(&ref, pos, n, &one);
    check_tree(&ref, pos, n, DEFAULT_MAX_LEAF, 1.0f, budget);
    if (budget > 0)
        assert_true(ref.prim_count > n); /* the soup makes spatial splits */
    for (uint32_t t = 2; t <= 4; t++) {
        const bvh_build_desc d = { .threads = t, .spatial_budget = budget };
        bvh b;
        build_ok(&b, pos, n, &d);
        check_tree(&b, pos, n, DEFAULT_MAX_LEAF, 1.0f, budget);
        assert_same_tree(&ref, &b);
        bvh_free(&b);
    }
    bvh_free(&ref);
    free(pos);
}

static void test_threads_identical(void **state)
{
    (void)state;
    enum { N = 60000 };
    check_threads_identical(make_soup(N, SOUP_SEED, 100.0, 1.0), N, 0.0f);
    check_threads_identical(make_signed_zero_soup(N), N, 0.0f);
}

/* SAH should beat splitting at the middle of the order by a wide margin on a soup; a sanity
 * check of the heuristic, not of the layout. Leaf-only is the SAH of one big leaf: N. */
static void test_sah_is_sensible(void **state)
{
    (void)state;
    enum { N = 10000 };
    float *pos = make_soup(N, SOUP_SEED, 100.0, 1.0);
    bvh b;
    build_ok(&b, pos, N, NULL);
    assert_true(b.sah_cost < 0.01f * N);
    assert_true(b.sah_cost > 1.0f);
    bvh_free(&b);
    free(pos);
}

/* ------------------------------------------------------------------------ spatial splits */

/* Small triangles scattered through a 20-unit box, crossed by `big` long slivers along the box's
 * diagonal, as a car's long panel triangles cross its detail: each sliver's box is most of the
 * scene, so no object split separates them from the small ones. */
static float *make_crossed_clutter(uint32_t small, uint32_t big, uint32_t *count)
{
    *count = small + big;
    float *p = alloc_tris(*count);
    rng r = { SOUP_SEED };
    for (uint32_t i = 0; i < small; i++)
        for (int a = 0; a < 3; a++) {
            double c = rng_range(&r, 0.0, 20.0);
            for (int v = 0; v < 3; v++)
                p[(size_t)i * FLOATS_PER_TRI + 3 * v + a] = (float)(c + rng_range(&r, 0.0, 0.5));
        }
    for (uint32_t k = 0; k < big; k++) {
        float y = 1.2f * k;
        const float sliver[FLOATS_PER_TRI] = { 0, y, 0, 20, y + 10, 20, 0.3f, y, 0 };
        memcpy(p + (size_t)(small + k) * FLOATS_PER_TRI, sliver, sizeof sliver);
    }
    return p;
}

/* Closed form: the right triangle (0,0,0), (4,0,0), (0,4,0) cut at x = 1 is [0,1] x [0,4] below
 * and [1,4] x [0,3] above; cut within the box y <= 2, [0,1] x [0,2] and [1,4] x [0,2]; a plane
 * past the triangle leaves one side empty. Rounded outwards by at most a float step. */
static void test_clip_triangle(void **state)
{
    (void)state;
    const float v[9] = { 0, 0, 0, 4, 0, 0, 0, 4, 0 };
    const aabb all = { v4_set3(-10, -10, -10), v4_set3(10, 10, 10) };
    const aabb low = { v4_set3(-10, -10, -10), v4_set3(10, 2, 10) };
    struct {
        const aabb *box;
        float pos, below[6], above[6];
    } cases[] = {
        { &all, 1.0f, { 0, 0, 0, 1, 4, 0 }, { 1, 0, 0, 4, 3, 0 } },
        { &low, 1.0f, { 0, 0, 0, 1, 2, 0 }, { 1, 0, 0, 4, 2, 0 } },
        { &all, 3.5f, { 0, 0, 0, 3.5f, 4, 0 }, { 3.5f, 0, 0, 4, 0.5f, 0 } },
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        aabb below, above;
        bvh_clip_triangle(v, cases[c].box, 0, cases[c].pos, &below, &above);
        float got[2][8];
        v4_store(got[0], below.lo);
        v4_store(got[0] + 4, below.hi);
        v4_store(got[1], above.lo);
        v4_store(got[1] + 4, above.hi);
        const float *want[2] = { cases[c].below, cases[c].above };
        for (int side = 0; side < 2; side++)
            for (int a = 0; a < 3; a++) {
                float lo = got[side][a], hi = got[side][4 + a];
                float wlo = want[side][a], whi = want[side][3 + a];
                /* contains the exact part, and no more than a float step beyond it */
                assert_true(lo <= wlo && lo >= nextafterf(wlo, -INFINITY));
                assert_true(hi >= whi && hi <= nextafterf(whi, INFINITY));
            }
    }
    aabb below, above;
    bvh_clip_triangle(v, &all, 0, 5.0f, &below, &above);
    float lo[4], hi[4];
    v4_store(lo, above.lo);
    v4_store(hi, above.hi);
    assert_true(lo[0] > hi[0]); /* nothing of the triangle above x = 5 */
}

/* Where slivers cross clutter, spatial splits lower the SAH cost by far (27%: 49.25 -> 36.14 when
 * written), keep within the budget, and every point of every triangle stays reachable. */
static void test_crossed_clutter(void **state)
{
    (void)state;
    uint32_t n;
    float *pos = make_crossed_clutter(4000, 16, &n);
    const bvh_build_desc spatial = { .spatial_budget = 0.3f };
    bvh plain, split;
    build_ok(&plain, pos, n, NULL);
    build_ok(&split, pos, n, &spatial);
    check_tree(&split, pos, n, DEFAULT_MAX_LEAF, 1.0f, spatial.spatial_budget);
    check_points(&split, pos, n);
    uint32_t hits = check_rays(&split, pos, n, SOUP_RAYS);
    printf("  crossed clutter: %u triangles, SAH %.2f plain, %.2f with spatial splits (%u "
           "references, +%.1f%%); %u/%u rays hit\n",
           n, (double)plain.sah_cost, (double)split.sah_cost, split.prim_count,
           100.0 * (split.prim_count - n) / n, hits, SOUP_RAYS);
    printf("  spatial-budget builds of the soups before this that took no spatial split (the plain "
           "tree, checked): %u\n", unsplit_trees);
    assert_true(hits > 0);
    assert_true(split.prim_count > n);
    assert_true(split.spatial_splits > 0);
    assert_true(unsplit_trees > 0);
    assert_true(split.sah_cost < 0.9f * plain.sah_cost);
    bvh_free(&plain);
    bvh_free(&split);
    free(pos);
}

/* Spatial splits share out their budget by node, never by thread: any thread count builds the
 * same tree. */
static void test_spatial_threads_identical(void **state)
{
    (void)state;
    uint32_t n;
    /* over 32768 triangles: the top levels are split by all threads (bvh_top.c) */
    float *pos = make_crossed_clutter(40000, 64, &n);
    check_threads_identical(pos, n, 0.3f);
    /* every fourth coordinate -0 or +0: clipped boxes must not depend on the order of mins */
    pos = make_crossed_clutter(40000, 64, &n);
    for (size_t i = 0; i < (size_t)n * FLOATS_PER_TRI; i += 4)
        pos[i] = (i / 4) % 2 ? -0.0f : 0.0f;
    check_threads_identical(pos, n, 0.3f);
}

/* ------------------------------------------------------------------------ real scenes */

static bool scene_path(const char *rel, char *path, size_t size)
{
    const char *dir = getenv("VKRT_SCENES_DIR");
    struct stat st;
    if (!dir || !*dir) {
        printf("  skipped: VKRT_SCENES_DIR is not set\n");
        return false;
    }
    snprintf(path, size, "%s/%s", dir, rel);
    if (stat(path, &st) != 0) {
        printf("  skipped: %s is missing\n", path);
        return false;
    }
    return true;
}

/* Builds threads=1 and threads=2 TIMING_RUNS times each, prints the best times, checks both
 * trees and that they are identical, and casts rays. */
/* Builds the scene's tree with 1 and 2 threads (with a spatial splits' budget: 0 for none),
 * checks both, that they are the same, and its rays against brute force. */
static void check_scene(const char *rel, uint32_t expected_tris, uint32_t rays, float budget)
{
    char path[1024];
    if (!scene_path(rel, path, sizeof path)) {
        skip();
        return;
    }
    vkrt_model mesh_model = {0};
    vkrt_error err = { "" };
    if (!vkrt_obj_load(path, &mesh_model, &err))
        fail_msg("%s", err.msg);
    const vkrt_mesh mesh = mesh_model.meshes[0];
    assert_int_equal(mesh.triangle_count, expected_tris);
    double best[2] = { INFINITY, INFINITY };
    bvh trees[2];
    for (uint32_t t = 0; t < 2; t++) {
        const bvh_build_desc d = { .threads = t + 1, .spatial_budget = budget };
        for (int run = 0; run < TIMING_RUNS; run++) {
            build_ok(&trees[t], mesh.positions, mesh.triangle_count, &d);
            best[t] = fmin(best[t], trees[t].build_ms);
            if (run + 1 < TIMING_RUNS)
                bvh_free(&trees[t]);
        }
        check_tree(&trees[t], mesh.positions, mesh.triangle_count, DEFAULT_MAX_LEAF, 1.0f, budget);
    }
    assert_same_tree(&trees[0], &trees[1]);
    if (budget > 0) {
        check_points(&trees[1], mesh.positions, mesh.triangle_count);
        printf("  %s with spatial splits: %u references (%+.1f%%)\n", rel, trees[1].prim_count,
               100.0 * ((double)trees[1].prim_count - mesh.triangle_count) / mesh.triangle_count);
        assert_true(trees[1].prim_count > mesh.triangle_count);
    }
    uint32_t hits = check_rays(&trees[1], mesh.positions, mesh.triangle_count, rays);
    printf("  %s: %u triangles, build %.1f ms (1 thread) %.1f ms (2 threads), best of %d; "
           "%u nodes, %u leaves, depth %u, SAH %.2f; %u/%u rays hit\n",
           rel, mesh.triangle_count, best[0], best[1], TIMING_RUNS, trees[1].node_count,
           trees[1].leaf_count, trees[1].max_depth, (double)trees[1].sah_cost, hits, rays);
    assert_true(hits > 0);
    bvh_free(&trees[0]);
    bvh_free(&trees[1]);
    vkrt_model_free(&mesh_model);
}

static void test_bunny(void **state)
{
    (void)state;
    check_scene("stanford-bunny/stanford-bunny.obj", 69451, BUNNY_RAYS, 0.0f);
}

/* Sponza's walls and floors cross its columns and arches: spatial splits duplicate about a tenth
 * of its triangles there (research/journal.md, "Spatial splits"). */
static void test_sponza_spatial(void **state)
{
    (void)state;
    check_scene("dabrovic-sponza/sponza.obj", 66444, BUNNY_RAYS, 0.3f); /* 6 of zero area dropped */
}

static void test_lost_empire(void **state)
{
    (void)state;
    check_scene("lost-empire/lost_empire.obj", 224998, EMPIRE_RAYS, 0.0f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_errors),
        cmocka_unit_test(test_single_triangle),
        cmocka_unit_test(test_random_soups),
        cmocka_unit_test(test_identical_triangles),
        cmocka_unit_test(test_flat_plane),
        cmocka_unit_test(test_degenerate_triangles),
        cmocka_unit_test(test_zero_area_root),
        cmocka_unit_test(test_huge_and_tiny),
        cmocka_unit_test(test_threads_identical),
        cmocka_unit_test(test_sah_is_sensible),
        cmocka_unit_test(test_clip_triangle),
        cmocka_unit_test(test_crossed_clutter),
        cmocka_unit_test(test_spatial_threads_identical),
        cmocka_unit_test(test_bunny),
        cmocka_unit_test(test_lost_empire),
        cmocka_unit_test(test_sponza_spatial),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
