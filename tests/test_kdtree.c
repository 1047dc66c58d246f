/*
 * test_kdtree.c: tests of the SAH kd-tree builder (src/accel/kdtree.h; Wald and Havran 2006).
 *
 * Every tree built here goes through check_tree: the layout contract of kdtree.h (children after
 * their parent, leaf ranges inside the references, statistics that match the nodes) and the
 * property traversal relies on, checked with a clipper of the test's own in double: every leaf
 * references every triangle whose part in the leaf's box reaches the box's inside (a triangle that
 * only touches a face may be left to the neighbour across it). Then rays, random and along the
 * axes from points on the soups' planes, find the same closest hit by a walk over the leaves
 * their segment meets as by a loop over all triangles. Soups: random triangles, axis-aligned
 * quads on a few shared planes (planar events, flat cells), and degenerate triangles (points,
 * needles, repeated triangles). Builds with one and with several threads must be identical. The
 * GPU walk is held against brute force by test_accel and tests/stability.
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
#include <unistd.h>

#include <cmocka.h>

#include "accel/kdtree.h"
#include "scene/obj/obj_load.h"

enum { SOUP_RAYS = 2000, BUNNY_RAYS = 400 };

static uint64_t rng_state;

static double uniform(void)
{
    rng_state = rng_state * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(rng_state >> 11) / 9007199254740992.0;
}

/* ------------------------------------------------------------------------ soups */

/* Random triangles of size up to `size` in the unit cube. */
static float *random_soup(uint32_t n, float size)
{
    float *p = malloc((size_t)n * 9 * sizeof *p);
    assert_non_null(p);
    for (uint32_t t = 0; t < n; ++t) {
        float c[3] = {(float)uniform(), (float)uniform(), (float)uniform()};
        for (int v = 0; v < 3; ++v)
            for (int k = 0; k < 3; ++k)
                p[9 * t + 3 * v + k] = c[k] + size * (float)(uniform() - 0.5);
    }
    return p;
}

/* Axis-aligned quads (two triangles each) on the planes 0, 0.25, 0.5, 0.75 and 1 of each axis:
 * many triangles share each plane, which gives planar events and flat cells. */
static float *plane_soup(uint32_t quads)
{
    float *p = malloc((size_t)quads * 18 * sizeof *p);
    assert_non_null(p);
    for (uint32_t q = 0; q < quads; ++q) {
        int axis = (int)(uniform() * 3);
        float at = 0.25f * (float)(int)(uniform() * 5);
        float lo[2] = {(float)uniform() * 0.8f, (float)uniform() * 0.8f};
        float hi[2] = {lo[0] + 0.2f * (float)uniform() + 0.01f,
                       lo[1] + 0.2f * (float)uniform() + 0.01f};
        float corner[4][2] = {{lo[0], lo[1]}, {hi[0], lo[1]}, {hi[0], hi[1]}, {lo[0], hi[1]}};
        static const int tri[2][3] = {{0, 1, 2}, {0, 2, 3}};
        for (int t = 0; t < 2; ++t)
            for (int v = 0; v < 3; ++v) {
                float *out = p + 18 * q + 9 * t + 3 * v;
                out[axis] = at;
                out[(axis + 1) % 3] = corner[tri[t][v]][0];
                out[(axis + 2) % 3] = corner[tri[t][v]][1];
            }
    }
    return p;
}

/* Points, needles along an axis and repeated triangles among ordinary ones. */
static float *degenerate_soup(uint32_t n)
{
    float *p = random_soup(n, 0.1f);
    for (uint32_t t = 0; t < n; t += 3) {
        float *v = p + 9 * t;
        if (t % 9 == 0) {
            memcpy(v + 3, v, 3 * sizeof *v); /* a point */
            memcpy(v + 6, v, 3 * sizeof *v);
        } else if (t % 9 == 3) {
            memcpy(v + 3, v, 3 * sizeof *v); /* a needle along x */
            v[3] += 0.2f;
            memcpy(v + 6, v, 3 * sizeof *v);
        } else if (t + 1 < n) {
            memcpy(v + 9, v, 9 * sizeof *v); /* the same triangle twice */
        }
    }
    return p;
}

/* ------------------------------------------------------------------------ the test's geometry */

typedef struct dbox {
    double lo[3], hi[3];
} dbox;

/* The centroid of triangle v's part inside closed box b, clipped in double; false when there is
 * none. A convex set in a box that is not in a plane of one of its faces has its centroid
 * strictly inside the box, so "centroid strictly inside" says "the part reaches the inside". */
static bool clipped_centroid(const float *v, const dbox *b, double c[3])
{
    double poly[2][12][3];
    int n = 3, cur = 0;
    for (int i = 0; i < 9; ++i)
        poly[0][i / 3][i % 3] = v[i];
    for (int plane = 0; plane < 6 && n > 0; ++plane) {
        int k = plane / 2;
        bool above = plane % 2 == 0;
        double at = above ? b->lo[k] : b->hi[k];
        int m = 0;
        for (int i = 0; i < n; ++i) {
            double *p = poly[cur][i], *q = poly[cur][(i + 1) % n];
            bool pin = above ? p[k] >= at : p[k] <= at, qin = above ? q[k] >= at : q[k] <= at;
            if (pin)
                memcpy(poly[1 - cur][m++], p, sizeof(double[3]));
            if (pin != qin) {
                double s = (at - p[k]) / (q[k] - p[k]);
                for (int j = 0; j < 3; ++j)
                    poly[1 - cur][m][j] = p[j] + s * (q[j] - p[j]);
                poly[1 - cur][m++][k] = at;
            }
        }
        n = m;
        cur = 1 - cur;
    }
    if (n == 0)
        return false;
    for (int k = 0; k < 3; ++k) {
        c[k] = 0;
        for (int i = 0; i < n; ++i)
            c[k] += poly[cur][i][k] / n;
    }
    return true;
}

/* Moller-Trumbore in double, edges inclusive; the hit's t, or INFINITY. */
static double hit_triangle(const double o[3], const double d[3], const float *v)
{
    double e1[3], e2[3], s[3], p[3], q[3];
    for (int k = 0; k < 3; ++k) {
        e1[k] = (double)v[3 + k] - v[k];
        e2[k] = (double)v[6 + k] - v[k];
        s[k] = o[k] - v[k];
    }
    p[0] = d[1] * e2[2] - d[2] * e2[1];
    p[1] = d[2] * e2[0] - d[0] * e2[2];
    p[2] = d[0] * e2[1] - d[1] * e2[0];
    double det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
    if (det == 0)
        return INFINITY;
    double u = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) / det;
    q[0] = s[1] * e1[2] - s[2] * e1[1];
    q[1] = s[2] * e1[0] - s[0] * e1[2];
    q[2] = s[0] * e1[1] - s[1] * e1[0];
    double w = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) / det;
    double t = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) / det;
    if (u < 0 || w < 0 || u + w > 1 || !(t > 1e-9))
        return INFINITY;
    return t;
}

/* Whether the ray meets closed box b (with a little slack, for rays along its faces). */
static bool ray_meets_box(const double o[3], const double d[3], const dbox *b)
{
    double t0 = 0, t1 = INFINITY;
    for (int k = 0; k < 3; ++k) {
        double slack = 1e-9 * (1 + fabs(b->lo[k]) + fabs(b->hi[k]));
        if (d[k] == 0) {
            if (o[k] < b->lo[k] - slack || o[k] > b->hi[k] + slack)
                return false;
            continue;
        }
        double a = (b->lo[k] - slack - o[k]) / d[k], c = (b->hi[k] + slack - o[k]) / d[k];
        t0 = fmax(t0, fmin(a, c));
        t1 = fmin(t1, fmax(a, c));
    }
    return t0 <= t1;
}

/* ------------------------------------------------------------------------ the checks */

typedef struct walk_state {
    const kdtree *t;
    const float *positions;
    uint32_t n;
    uint32_t leaves, inner, refs, empty, deepest;
    uint32_t next_expected; /* depth first: each node comes after the previous one visited */
} walk_state;

/* Checks node i with box b at depth `depth`, then its children. */
static void check_node(walk_state *w, uint32_t i, dbox b, uint32_t depth)
{
    const kdtree *t = w->t;
    assert_true(i < t->node_count);
    assert_int_equal(i, w->next_expected);
    ++w->next_expected;
    const kd_node *nd = &t->nodes[i];
    if (depth > w->deepest)
        w->deepest = depth;
    if (nd->axis == KD_LEAF) {
        ++w->leaves;
        w->refs += nd->b;
        w->empty += nd->b == 0;
        assert_true((uint64_t)nd->a + nd->b <= t->ref_count);
        assert_int_equal(depth <= t->max_depth, 1);
        /* Every triangle reaching the leaf's inside is referenced. */
        for (uint32_t tri = 0; tri < w->n; ++tri) {
            /* Cheaply first: a triangle whose box stays off the leaf's inside cannot reach it. */
            const float *v = w->positions + 9 * (size_t)tri;
            bool apart = false;
            for (int k = 0; k < 3 && !apart; ++k)
                apart = (v[k] <= b.lo[k] && v[3 + k] <= b.lo[k] && v[6 + k] <= b.lo[k]) ||
                        (v[k] >= b.hi[k] && v[3 + k] >= b.hi[k] && v[6 + k] >= b.hi[k]);
            if (apart)
                continue;
            double c[3];
            if (!clipped_centroid(w->positions + 9 * (size_t)tri, &b, c))
                continue;
            bool inside = true;
            for (int k = 0; k < 3; ++k)
                inside = inside && c[k] > b.lo[k] && c[k] < b.hi[k];
            if (!inside)
                continue;
            bool found = false;
            for (uint32_t r = nd->a; r < nd->a + nd->b && !found; ++r)
                found = t->refs[r] == tri;
            if (!found)
                fail_msg("leaf %u does not reference triangle %u, whose part reaches its inside", i,
                         tri);
        }
        return;
    }
    ++w->inner;
    assert_true(nd->axis < 3);
    assert_true(nd->split >= b.lo[nd->axis] && nd->split <= b.hi[nd->axis]);
    assert_int_equal(nd->a, i + 1);
    dbox l = b, r = b;
    l.hi[nd->axis] = nd->split;
    r.lo[nd->axis] = nd->split;
    check_node(w, nd->a, l, depth + 1);
    assert_int_equal(nd->b, w->next_expected);
    check_node(w, nd->b, r, depth + 1);
}

static dbox root_box(const kdtree *t)
{
    dbox b;
    for (int k = 0; k < 3; ++k) {
        b.lo[k] = t->lo[k];
        b.hi[k] = t->hi[k];
    }
    return b;
}

static void check_tree(const kdtree *t, const float *positions, uint32_t n)
{
    walk_state w = {.t = t, .positions = positions, .n = n};
    check_node(&w, 0, root_box(t), 0);
    assert_int_equal(w.next_expected, t->node_count);
    assert_int_equal(w.leaves, t->leaf_count);
    assert_int_equal(w.empty, t->empty_leaves);
    assert_int_equal(w.refs, t->ref_count);
    assert_int_equal(w.deepest, t->max_depth);
    assert_true(t->max_depth <= KDTREE_MAX_DEPTH);
    for (uint32_t r = 0; r < t->ref_count; ++r)
        assert_true(t->refs[r] < n);
}

/* The closest hit over the leaves the ray meets, found by walking the boxes. */
static double walk_closest(const kdtree *t, const float *positions, uint32_t i, dbox b,
                           const double o[3], const double d[3])
{
    if (!ray_meets_box(o, d, &b))
        return INFINITY;
    const kd_node *nd = &t->nodes[i];
    if (nd->axis == KD_LEAF) {
        double best = INFINITY;
        for (uint32_t r = nd->a; r < nd->a + nd->b; ++r)
            best = fmin(best, hit_triangle(o, d, positions + 9 * (size_t)t->refs[r]));
        return best;
    }
    dbox l = b, r = b;
    l.hi[nd->axis] = nd->split;
    r.lo[nd->axis] = nd->split;
    return fmin(walk_closest(t, positions, nd->a, l, o, d),
                walk_closest(t, positions, nd->b, r, o, d));
}

/* Random rays from inside the bounds, and rays along the axes from points whose coordinates lie
 * on the soups' planes (0.25 steps): the same closest hit as brute force. */
static void check_rays(const kdtree *t, const float *positions, uint32_t n, uint32_t rays)
{
    uint32_t hits = 0;
    for (uint32_t i = 0; i < rays; ++i) {
        double o[3], d[3];
        for (int k = 0; k < 3; ++k) {
            o[k] = t->lo[k] + (t->hi[k] - t->lo[k]) * uniform();
            d[k] = uniform() - 0.5;
        }
        if (i % 2) {
            for (int k = 0; k < 3; ++k) {
                o[k] = 0.25 * (int)(uniform() * 5);
                d[k] = 0;
            }
            o[i % 3] = (i / 3) % 2 ? -1.0 : 2.0;
            d[i % 3] = (i / 3) % 2 ? 1.0 : -1.0;
        }
        double brute = INFINITY;
        for (uint32_t tri = 0; tri < n; ++tri)
            brute = fmin(brute, hit_triangle(o, d, positions + 9 * (size_t)tri));
        double walked = walk_closest(t, positions, 0, root_box(t), o, d);
        if (walked != brute)
            fail_msg("ray %u: brute force %.17g, kd-tree %.17g", i, brute, walked);
        hits += brute < INFINITY;
    }
    print_message("%u of %u rays hit; the kd-tree agrees on all\n", hits, rays);
}

static void build_and_check(const char *name, const float *positions, uint32_t n, uint32_t rays)
{
    kdtree t1, t4;
    vkrt_error err = {{0}};
    if (!kdtree_build(&t1, positions, n, &(kdtree_build_desc){.threads = 1}, &err))
        fail_msg("%s: %s", name, err.msg);
    if (!kdtree_build(&t4, positions, n, &(kdtree_build_desc){.threads = 4}, &err))
        fail_msg("%s: %s", name, err.msg);
    print_message("%s: %u triangles, %u nodes, %u leaves (%u empty), %u references, depth %u, "
                  "SAH %.1f\n",
                  name, n, t1.node_count, t1.leaf_count, t1.empty_leaves, t1.ref_count,
                  t1.max_depth, t1.sah_cost);
    /* The same tree whatever the threads. */
    assert_int_equal(t1.node_count, t4.node_count);
    assert_int_equal(t1.ref_count, t4.ref_count);
    assert_memory_equal(t1.nodes, t4.nodes, t1.node_count * sizeof *t1.nodes);
    assert_memory_equal(t1.refs, t4.refs, t1.ref_count * sizeof *t1.refs);
    check_tree(&t1, positions, n);
    check_rays(&t1, positions, n, rays);
    kdtree_free(&t1);
    kdtree_free(&t4);
}

static void test_random_soup(void **state)
{
    (void)state;
    rng_state = 1;
    float *p = random_soup(2000, 0.08f);
    build_and_check("random soup", p, 2000, SOUP_RAYS);
    free(p);
}

/* Enough triangles that nodes spawn subtrees on threads (SPAWN_MIN_TRIANGLES, 4096), below the
 * root's first splits too, so the thread-count check above compares threaded builds. */
static void test_large_soup(void **state)
{
    (void)state;
    rng_state = 6;
    float *p = random_soup(16000, 0.05f);
    build_and_check("large soup", p, 16000, SOUP_RAYS / 4);
    free(p);
}

static void test_plane_soup(void **state)
{
    (void)state;
    rng_state = 2;
    float *p = plane_soup(600);
    build_and_check("axis-aligned quads", p, 1200, SOUP_RAYS);
    free(p);
}

static void test_degenerate_soup(void **state)
{
    (void)state;
    rng_state = 3;
    float *p = degenerate_soup(1500);
    build_and_check("degenerate soup", p, 1500, SOUP_RAYS);
    free(p);
}

/* No triangles, one triangle, and all triangles in one plane (a flat root box). */
static void test_small_inputs(void **state)
{
    (void)state;
    kdtree t;
    vkrt_error err = {{0}};
    assert_true(kdtree_build(&t, NULL, 0, NULL, &err));
    assert_int_equal(t.node_count, 1);
    assert_int_equal(t.nodes[0].axis, KD_LEAF);
    assert_int_equal(t.nodes[0].b, 0);
    kdtree_free(&t);
    const float one[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    assert_true(kdtree_build(&t, one, 1, NULL, &err));
    check_tree(&t, one, 1);
    kdtree_free(&t);
    rng_state = 4;
    float *p = plane_soup(500);
    for (uint32_t i = 0; i < 500 * 6; ++i)
        p[3 * i + 1] = 0.5f; /* every vertex on y = 0.5 */
    build_and_check("one plane", p, 1000, 500);
    free(p);
}

/* A real mesh, when the shared scenes are there: the contract and the rays. */
static void test_bunny(void **state)
{
    (void)state;
    const char *dir = getenv("VKRT_SCENES_DIR");
    char path[4096];
    snprintf(path, sizeof path, "%s/stanford-bunny/stanford-bunny.obj", dir ? dir : "");
    if (!dir || access(path, R_OK) != 0) {
        print_message("skipped: %s is not there\n", path);
        skip();
    }
    vkrt_model mesh_model = {0};
    vkrt_error err = {{0}};
    if (!vkrt_obj_load(path, &mesh_model, &err))
        fail_msg("%s", err.msg);
    const vkrt_mesh mesh = mesh_model.meshes[0];
    kdtree t;
    if (!kdtree_build(&t, mesh.positions, mesh.triangle_count, NULL, &err))
        fail_msg("%s", err.msg);
    print_message("bunny: %u triangles, %u nodes, %u leaves, %u references, depth %u, %.1f ms\n",
                  mesh.triangle_count, t.node_count, t.leaf_count, t.ref_count, t.max_depth,
                  t.build_ms);
    rng_state = 5;
    check_rays(&t, mesh.positions, mesh.triangle_count, BUNNY_RAYS);
    kdtree_free(&t);
    vkrt_model_free(&mesh_model);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_random_soup),     cmocka_unit_test(test_large_soup),
        cmocka_unit_test(test_plane_soup),
        cmocka_unit_test(test_degenerate_soup), cmocka_unit_test(test_small_inputs),
        cmocka_unit_test(test_bunny),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
