/*
 * test_grid.c: tests of the compact uniform grid builder (src/accel/grid.h).
 *
 * 1. Invariants on synthetic inputs (random soups with a fixed seed, a flat plane, triangles on
 *    cell boundaries, degenerate triangles): cell_start is a non-decreasing prefix sum ending at
 *    ref_count, refs are valid and strictly increasing within a cell (so no duplicates), no cell
 *    outside a triangle's bounding-box cell range references it, and every cell that a triangle
 *    truly touches references it. "Truly touches" is checked independently of the builder's
 *    separating axis test: points are sampled on a barycentric lattice over each triangle
 *    (vertices and edges included) and put into cells with the point-to-cell formula the GPU uses,
 *    clamp(floor((p - lo) / cell_size), 0, dims - 1) in float.
 * 2. A CPU 3D-DDA (Amanatides and Woo, "A Fast Voxel Traversal Algorithm for Ray Tracing", 1987)
 *    with a double-precision Möller-Trumbore test, compared against brute force on random rays
 *    (from outside and inside the grid, and along the axes with direction components exactly 0).
 *    Two acceptance rules are checked: the strict one (a hit counts only if its t lies within the
 *    visited cell's [t_enter, t_exit], widened by a tiny epsilon because the cell boundaries and t
 *    are rounded differently) and the one glsl/lib/traverse_grid.glsl uses (keep the closest hit
 *    as a candidate wherever it lies; stop once it is no farther than the current cell's exit).
 * 3. Real scenes from $VKRT_SCENES_DIR (skipped when unset or missing): the Stanford bunny and the
 *    lost empire, invariants plus statistics. $VKRT_GRID_SWEEP=1 adds a density sweep timed with
 *    the CPU DDA; $VKRT_GRID_OBJ=path prints the statistics of any OBJ (the stadium tool's).
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

#include "accel/grid.h"
#include "clock.h"
#include "scene/obj/obj_load.h"

#define SEED 0x9e3779b97f4a7c15ull
#define DDA_RAYS 3000
#define MAX_LATTICE 48   /* barycentric lattice subdivisions, at most */
#define T_EPS_REL 1e-9   /* widening of a cell's [t_enter, t_exit] in the strict rule */

/* ------------------------------------------------------------------------ helpers */

typedef struct rng {
    uint64_t s;
} rng;

/* splitmix64: small, fixed-seed, identical everywhere. */
static uint64_t rng_next(rng *r)
{
    uint64_t z = (r->s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

static double rng_unit(rng *r)
{
    return (double)(rng_next(r) >> 11) * (1.0 / 9007199254740992.0);
}

static double rng_range(rng *r, double lo, double hi)
{
    return lo + (hi - lo) * rng_unit(r);
}

/* The GPU's point-to-cell formula, written again here on purpose (not taken from grid.c). */
static uint32_t cell_of(float p, float lo, float cs, uint32_t dims)
{
    float f = floorf((p - lo) / cs);
    if (!(f >= 0.0f))
        return 0;
    if (f >= (float)dims)
        return dims - 1;
    return (uint32_t)f;
}

static uint32_t cell_index(const grid *g, const uint32_t c[3])
{
    return c[0] + g->dims[0] * (c[1] + g->dims[1] * c[2]);
}

static void tri_cell_range(const grid *g, const float *t, uint32_t c0[3], uint32_t c1[3])
{
    for (int a = 0; a < 3; ++a) {
        float mn = fminf(t[a], fminf(t[3 + a], t[6 + a]));
        float mx = fmaxf(t[a], fmaxf(t[3 + a], t[6 + a]));
        c0[a] = cell_of(mn, g->lo[a], g->cell_size[a], g->dims[a]);
        c1[a] = cell_of(mx, g->lo[a], g->cell_size[a], g->dims[a]);
    }
}

/* Whether sorted cell `cell` holds triangle tri (binary search: refs are sorted per cell). */
static bool cell_has(const grid *g, uint32_t cell, uint32_t tri)
{
    uint32_t lo = g->cell_start[cell], hi = g->cell_start[cell + 1];
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (g->refs[mid] < tri)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo < g->cell_start[cell + 1] && g->refs[lo] == tri;
}

/* Lattice subdivisions for a triangle: enough for a few samples per cell it spans. */
static int lattice_for(const uint32_t c0[3], const uint32_t c1[3], int minimum)
{
    uint32_t span = 0;
    for (int a = 0; a < 3; ++a)
        span = c1[a] - c0[a] > span ? c1[a] - c0[a] : span;
    int s = (int)(3 * span + 2);
    return s < minimum ? minimum : (s > MAX_LATTICE ? MAX_LATTICE : s);
}

/* All invariants of the top comment; returns the number of failures (0 expected) and prints the
 * first few. min_lattice: barycentric subdivisions per triangle at least. */
static int check_invariants(const grid *g, const float *pos, uint32_t n, int min_lattice)
{
    int failures = 0;
#define FAIL(...) do { if (failures++ < 10) print_error(__VA_ARGS__); } while (0)
    if (g->cell_count != g->dims[0] * g->dims[1] * g->dims[2])
        FAIL("cell_count %u != product of dims\n", g->cell_count);
    if (g->cell_start[0] != 0)
        FAIL("cell_start[0] = %u\n", g->cell_start[0]);
    if (g->cell_start[g->cell_count] != g->ref_count)
        FAIL("cell_start[last] %u != ref_count %u\n", g->cell_start[g->cell_count], g->ref_count);
    uint32_t max_refs = 0, occupied = 0;
    for (uint32_t c = 0; c < g->cell_count; ++c) {
        uint32_t b = g->cell_start[c], e = g->cell_start[c + 1];
        if (e < b) {
            FAIL("cell_start decreases at cell %u\n", c);
            continue;
        }
        max_refs = e - b > max_refs ? e - b : max_refs;
        occupied += e > b;
        uint32_t cc[3] = { c % g->dims[0], (c / g->dims[0]) % g->dims[1],
                           c / (g->dims[0] * g->dims[1]) };
        for (uint32_t r = b; r < e; ++r) {
            uint32_t t = g->refs[r];
            if (t >= n) {
                FAIL("cell %u: ref %u out of range\n", c, t);
                continue;
            }
            if (r > b && g->refs[r - 1] >= t)
                FAIL("cell %u: refs not strictly increasing (duplicate?) at %u\n", c, t);
            uint32_t c0[3], c1[3];
            tri_cell_range(g, pos + 9 * (size_t)t, c0, c1);
            for (int a = 0; a < 3; ++a)
                if (cc[a] < c0[a] || cc[a] > c1[a])
                    FAIL("cell %u references triangle %u outside its bbox range\n", c, t);
        }
    }
    if (max_refs != g->max_cell_refs)
        FAIL("max_cell_refs %u, recount %u\n", g->max_cell_refs, max_refs);
    if (occupied != g->occupied_cells)
        FAIL("occupied_cells %u, recount %u\n", g->occupied_cells, occupied);
    /* Every sampled point's cell holds the triangle. */
    for (uint32_t t = 0; t < n; ++t) {
        const float *v = pos + 9 * (size_t)t;
        uint32_t c0[3], c1[3];
        tri_cell_range(g, v, c0, c1);
        int s = lattice_for(c0, c1, min_lattice);
        for (int i = 0; i <= s; ++i)
            for (int j = 0; j <= s - i; ++j) {
                double u = (double)i / s, w = (double)j / s;
                uint32_t cc[3];
                for (int a = 0; a < 3; ++a) {
                    double p = v[a] + u * ((double)v[3 + a] - v[a]) + w * ((double)v[6 + a] - v[a]);
                    cc[a] = cell_of((float)p, g->lo[a], g->cell_size[a], g->dims[a]);
                }
                if (!cell_has(g, cell_index(g, cc), t))
                    FAIL("triangle %u touches cell (%u %u %u) but is not in it\n", t, cc[0], cc[1],
                         cc[2]);
            }
    }
#undef FAIL
    return failures;
}

static grid build_ok(const float *pos, uint32_t n, float density)
{
    grid g;
    vkrt_error err = { { 0 } };
    grid_build_desc desc = { .density = density, .max_cells = 0 };
    bool ok = grid_build(&g, pos, n, &desc, &err);
    if (!ok)
        print_error("grid_build: %s\n", err.msg);
    assert_true(ok);
    return g;
}

static void build_and_check(const float *pos, uint32_t n, float density, int min_lattice)
{
    grid g = build_ok(pos, n, density);
    assert_int_equal(check_invariants(&g, pos, n, min_lattice), 0);
    grid_free(&g);
}

/* ------------------------------------------------------------------------ synthetic scenes */

static float *random_soup(uint32_t n, double box, double size, uint64_t seed)
{
    rng r = { seed };
    float *p = malloc((size_t)n * 9 * sizeof *p);
    assert_non_null(p);
    for (uint32_t t = 0; t < n; ++t) {
        double c[3] = { rng_range(&r, -box, box), rng_range(&r, -box, box), rng_range(&r, -box, box) };
        for (int k = 0; k < 3; ++k)
            for (int a = 0; a < 3; ++a)
                p[9 * t + 3 * k + a] = (float)(c[a] + rng_range(&r, -size, size));
    }
    return p;
}

/* A w x w grid of quads in the plane y = height, two triangles each. */
static float *plane_mesh(uint32_t w, float height, uint32_t *n_out)
{
    uint32_t n = 2 * w * w;
    float *p = malloc((size_t)n * 9 * sizeof *p);
    assert_non_null(p);
    float *q = p;
    for (uint32_t i = 0; i < w; ++i)
        for (uint32_t j = 0; j < w; ++j) {
            float x0 = (float)i, x1 = (float)(i + 1), z0 = (float)j, z1 = (float)(j + 1);
            float quad[18] = { x0, height, z0, x1, height, z0, x1, height, z1,
                               x0, height, z0, x1, height, z1, x0, height, z1 };
            memcpy(q, quad, sizeof quad);
            q += 18;
        }
    *n_out = n;
    return p;
}

static void test_no_triangles(void **state)
{
    (void)state;
    grid g;
    vkrt_error err = { { 0 } };
    float dummy[9] = { 0 };
    assert_false(grid_build(&g, dummy, 0, NULL, &err));
    assert_non_null(strstr(err.msg, "no triangles"));
    assert_null(g.cell_start);
    assert_int_equal(g.cell_count, 0);
    grid_free(&g); /* safe on the zeroed struct */
}

static void test_non_finite(void **state)
{
    (void)state;
    grid g;
    vkrt_error err = { { 0 } };
    float p[18] = { 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 1, NAN, 0, 0, 1, 0 };
    assert_false(grid_build(&g, p, 2, NULL, &err));
    assert_non_null(strstr(err.msg, "triangle 1"));
    assert_null(g.refs);
}

static void test_default_density(void **state)
{
    (void)state;
    float d = grid_default_density();
    assert_true(d >= 0.5f && d <= 16.0f);
    uint32_t n = 1000;
    float *p = random_soup(n, 10, 1, SEED);
    grid g = build_ok(p, n, 0.0f);
    /* About density * N cells (rounding per axis moves it by a factor of at most ~2). */
    assert_true(g.cell_count >= d * n / 3 && g.cell_count <= d * n * 3);
    grid_free(&g);
    free(p);
}

static void test_random_soups(void **state)
{
    (void)state;
    const uint32_t sizes[] = { 1, 10, 1000, 20000 };
    for (size_t i = 0; i < sizeof sizes / sizeof *sizes; ++i) {
        float *p = random_soup(sizes[i], 10.0, 1.5, SEED + i);
        build_and_check(p, sizes[i], 0.0f, 4);
        build_and_check(p, sizes[i], 8.0f, 4);
        free(p);
    }
    /* Large triangles crossing many cells exercise the separating axis test. */
    float *p = random_soup(200, 10.0, 8.0, SEED + 99);
    build_and_check(p, 200, 4.0f, 16);
    grid g = build_ok(p, 200, 4.0f);
    uint64_t bbox_cells = 0;
    for (uint32_t t = 0; t < 200; ++t) {
        uint32_t c0[3], c1[3];
        tri_cell_range(&g, p + 9 * t, c0, c1);
        bbox_cells += (uint64_t)(c1[0] - c0[0] + 1) * (c1[1] - c0[1] + 1) * (c1[2] - c0[2] + 1);
    }
    print_message("big triangles: %u refs vs %llu bbox cells\n", g.ref_count,
                  (unsigned long long)bbox_cells);
    assert_true(g.ref_count < bbox_cells); /* the exact test culled something */
    grid_free(&g);
    free(p);
}

static void test_flat_plane(void **state)
{
    (void)state;
    uint32_t n;
    float *p = plane_mesh(40, 2.5f, &n);
    grid g = build_ok(p, n, 2.0f);
    print_message("flat plane: %u triangles, dims %u %u %u\n", n, g.dims[0], g.dims[1], g.dims[2]);
    assert_int_equal(g.dims[1], 1);
    assert_true(g.cell_count >= n && g.cell_count <= 4 * n); /* density rule on the 2 live axes */
    assert_int_equal(check_invariants(&g, p, n, 4), 0);
    grid_free(&g);
    free(p);
}

/* Axis-aligned triangles lying on the planes of cell boundaries: with a 10 x 10 quad plane and
 * unit-sized triangles set in the three axis planes at integer coordinates, many vertices and
 * whole triangles fall on (or within rounding of) the boundaries of a grid over [0, 10]^3. */
static void test_boundary_triangles(void **state)
{
    (void)state;
    uint32_t n = 0, cap = 3000;
    float *p = malloc((size_t)cap * 9 * sizeof *p);
    assert_non_null(p);
    for (int axis = 0; axis < 3; ++axis)
        for (int k = 0; k <= 10; k += 1)
            for (int i = 0; i < 10; ++i)
                for (int j = 0; j < 10; j += 3) {
                    float v[3][3];
                    int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
                    for (int m = 0; m < 3; ++m)
                        v[m][axis] = (float)k;
                    v[0][a1] = (float)i, v[0][a2] = (float)j;
                    v[1][a1] = (float)(i + 1), v[1][a2] = (float)j;
                    v[2][a1] = (float)i, v[2][a2] = (float)(j + 1);
                    memcpy(p + 9 * n++, v, sizeof v);
                }
    assert_true(n <= cap);
    for (float d = 0.25f; d <= 8.0f; d *= 2.0f)
        build_and_check(p, n, d, 8);
    free(p);
}

static void test_degenerate_triangles(void **state)
{
    (void)state;
    rng r = { SEED + 7 };
    uint32_t n = 600;
    float *p = malloc((size_t)n * 9 * sizeof *p);
    assert_non_null(p);
    for (uint32_t t = 0; t < n; ++t) {
        float a[3], b[3];
        for (int k = 0; k < 3; ++k) {
            a[k] = (float)rng_range(&r, -5, 5);
            b[k] = (float)rng_range(&r, -5, 5);
        }
        float *v = p + 9 * t;
        switch (t % 3) {
        case 0: /* a point */
            memcpy(v, a, sizeof a), memcpy(v + 3, a, sizeof a), memcpy(v + 6, a, sizeof a);
            break;
        case 1: /* a segment with a repeated vertex */
            memcpy(v, a, sizeof a), memcpy(v + 3, b, sizeof b), memcpy(v + 6, b, sizeof b);
            break;
        default: /* three collinear points */
            for (int k = 0; k < 3; ++k) {
                v[k] = a[k];
                v[3 + k] = (float)(a[k] + 0.3 * (b[k] - a[k]));
                v[6 + k] = b[k];
            }
        }
    }
    build_and_check(p, n, 2.0f, 32);
    /* A single point for the whole scene: zero extent on every axis. */
    float point[9] = { 1, 2, 3, 1, 2, 3, 1, 2, 3 };
    grid g = build_ok(point, 1, 0.0f);
    assert_int_equal(g.cell_count, 1);
    assert_int_equal(g.ref_count, 1);
    grid_free(&g);
    free(p);
}

static void test_max_cells(void **state)
{
    (void)state;
    float *p = random_soup(5000, 10, 1, SEED + 3);
    grid g;
    vkrt_error err = { { 0 } };
    grid_build_desc desc = { .density = 64.0f, .max_cells = 1000 };
    assert_true(grid_build(&g, p, 5000, &desc, &err));
    assert_true(g.cell_count <= 1000 && g.cell_count > 500);
    assert_int_equal(check_invariants(&g, p, 5000, 2), 0);
    grid_free(&g);
    free(p);
}

/* ------------------------------------------------------------------------ traversal */

/* Möller-Trumbore in double: the hit distance in (tmin, tmax), or false. */
static bool intersect(const double o[3], const double d[3], const float *tri, double tmin,
                      double tmax, double *t_out)
{
    double e1[3], e2[3], s[3], pv[3], qv[3];
    for (int a = 0; a < 3; ++a) {
        e1[a] = (double)tri[3 + a] - tri[a];
        e2[a] = (double)tri[6 + a] - tri[a];
        s[a] = o[a] - tri[a];
    }
    pv[0] = d[1] * e2[2] - d[2] * e2[1];
    pv[1] = d[2] * e2[0] - d[0] * e2[2];
    pv[2] = d[0] * e2[1] - d[1] * e2[0];
    double det = e1[0] * pv[0] + e1[1] * pv[1] + e1[2] * pv[2];
    if (det == 0.0)
        return false;
    double inv = 1.0 / det;
    double u = (s[0] * pv[0] + s[1] * pv[1] + s[2] * pv[2]) * inv;
    if (u < 0.0 || u > 1.0)
        return false;
    qv[0] = s[1] * e1[2] - s[2] * e1[1];
    qv[1] = s[2] * e1[0] - s[0] * e1[2];
    qv[2] = s[0] * e1[1] - s[1] * e1[0];
    double v = (d[0] * qv[0] + d[1] * qv[1] + d[2] * qv[2]) * inv;
    if (v < 0.0 || u + v > 1.0)
        return false;
    double t = (e2[0] * qv[0] + e2[1] * qv[1] + e2[2] * qv[2]) * inv;
    if (!(t > tmin && t < tmax))
        return false;
    *t_out = t;
    return true;
}

typedef struct ray_hit {
    double t;
    int64_t tri; /* -1: none */
} ray_hit;

static ray_hit brute_force(const float *pos, uint32_t n, const double o[3], const double d[3])
{
    ray_hit h = { INFINITY, -1 };
    for (uint32_t i = 0; i < n; ++i) {
        double t;
        if (intersect(o, d, pos + 9 * (size_t)i, 0.0, h.t, &t))
            h = (ray_hit){ t, i };
    }
    return h;
}

typedef struct dda_stats {
    uint64_t steps, tests;
} dda_stats;

/* The 3D-DDA. strict: the Amanatides-Woo rule (accept only hits inside the visited cell's
 * t-interval, widened by T_EPS_REL); otherwise the candidate rule of traverse_grid.glsl. Cell
 * boundaries are computed from their index each step (lo + i * cell_size), not accumulated. */
static ray_hit grid_traverse(const grid *g, const float *pos, const double o[3], const double d[3],
                             bool strict, dda_stats *st)
{
    ray_hit h = { INFINITY, -1 };
    double t_enter = 0.0, t_exit = INFINITY;
    for (int a = 0; a < 3; ++a) {
        if (d[a] == 0.0) {
            if (o[a] < g->lo[a] || o[a] > g->hi[a])
                return h;
            continue;
        }
        double t0 = (g->lo[a] - o[a]) / d[a], t1 = (g->hi[a] - o[a]) / d[a];
        t_enter = fmax(t_enter, fmin(t0, t1));
        t_exit = fmin(t_exit, fmax(t0, t1));
    }
    if (t_enter > t_exit)
        return h;
    int64_t cell[3], step[3], dims[3];
    double t_next[3];
    for (int a = 0; a < 3; ++a) {
        dims[a] = g->dims[a];
        double p = o[a] + d[a] * t_enter;
        double f = floor((p - g->lo[a]) / g->cell_size[a]);
        cell[a] = f < 0 ? 0 : (f >= (double)dims[a] ? dims[a] - 1 : (int64_t)f);
        step[a] = d[a] > 0 ? 1 : (d[a] < 0 ? -1 : 0);
    }
    double t_cell_enter = t_enter;
    for (;;) {
        for (int a = 0; a < 3; ++a) {
            int64_t b = cell[a] + (step[a] > 0);
            t_next[a] = step[a] ? ((double)g->lo[a] + (double)b * g->cell_size[a] - o[a]) / d[a]
                                : INFINITY;
        }
        double t_cell_exit = fmin(t_next[0], fmin(t_next[1], t_next[2]));
        double eps = T_EPS_REL * (fabs(t_cell_exit < INFINITY ? t_cell_exit : t_cell_enter) + 1.0);
        uint32_t c = (uint32_t)(cell[0] + dims[0] * (cell[1] + dims[1] * cell[2]));
        st->steps++;
        for (uint32_t r = g->cell_start[c]; r < g->cell_start[c + 1]; ++r) {
            uint32_t i = g->refs[r];
            double t;
            st->tests++;
            if (!intersect(o, d, pos + 9 * (size_t)i, 0.0, h.t, &t))
                continue;
            if (strict && (t < t_cell_enter - eps || t > t_cell_exit + eps))
                continue; /* hit outside this cell: a later cell will find it if it is closest */
            if (t < h.t || (t == h.t && i < h.tri))
                h = (ray_hit){ t, i };
        }
        if (h.tri >= 0 && h.t <= t_cell_exit + (strict ? eps : 0.0))
            return h;
        if (t_cell_exit >= t_exit)
            return h;
        int a = t_next[0] <= t_next[1] && t_next[0] <= t_next[2] ? 0 : (t_next[1] <= t_next[2] ? 1 : 2);
        cell[a] += step[a];
        if (cell[a] < 0 || cell[a] >= dims[a])
            return h;
        t_cell_enter = t_cell_exit;
    }
}

/* A ray: kind 0 from outside the bounds towards a point inside, 1 from inside in a random
 * direction, 2 from inside along a random axis (the other direction components exactly 0),
 * 3 like 2 but from a grid vertex column (origin on cell boundaries in the two other axes). */
static void random_ray(rng *r, const grid *g, int kind, double o[3], double d[3])
{
    double c[3], ext[3];
    for (int a = 0; a < 3; ++a) {
        c[a] = 0.5 * ((double)g->lo[a] + g->hi[a]);
        ext[a] = (double)g->hi[a] - g->lo[a];
    }
    double target[3];
    for (int a = 0; a < 3; ++a) {
        target[a] = c[a] + rng_range(r, -0.5, 0.5) * ext[a];
        o[a] = c[a] + rng_range(r, -0.5, 0.5) * ext[a];
    }
    if (kind == 0) {
        for (int a = 0; a < 3; ++a)
            o[a] = c[a] + rng_range(r, -1.5, 1.5) * (ext[a] + 1.0);
        for (int a = 0; a < 3; ++a)
            d[a] = target[a] - o[a];
    } else if (kind == 1) {
        for (int a = 0; a < 3; ++a)
            d[a] = rng_range(r, -1, 1);
    } else {
        int axis = (int)(rng_next(r) % 3);
        for (int a = 0; a < 3; ++a)
            d[a] = 0.0;
        d[axis] = rng_unit(r) < 0.5 ? -1.0 : 1.0;
        if (kind == 3)
            for (int a = 0; a < 3; ++a)
                if (a != axis)
                    o[a] = (double)g->lo[a] + (double)(rng_next(r) % (g->dims[a] + 1)) * g->cell_size[a];
    }
}

/* Compares both DDA rules against brute force on count rays; returns the mismatches. */
static int compare_traversal(const grid *g, const float *pos, uint32_t n, uint32_t count, uint64_t seed)
{
    rng r = { seed };
    int bad = 0;
    dda_stats st = { 0, 0 };
    for (uint32_t k = 0; k < count; ++k) {
        double o[3], d[3];
        random_ray(&r, g, (int)(k % 4), o, d);
        ray_hit ref = brute_force(pos, n, o, d);
        for (int strict = 0; strict < 2; ++strict) {
            ray_hit h = grid_traverse(g, pos, o, d, strict, &st);
            bool same = h.tri == ref.tri || (h.tri >= 0 && ref.tri >= 0 && h.t == ref.t);
            if (!same && bad++ < 10)
                print_error("ray %u (kind %u, %s): grid t=%.17g tri %lld, brute t=%.17g tri %lld\n",
                            k, k % 4, strict ? "strict" : "candidate", h.t, (long long)h.tri,
                            ref.t, (long long)ref.tri);
        }
    }
    return bad;
}

static void traverse_case(const float *p, uint32_t n, float density, uint64_t seed)
{
    grid g = build_ok(p, n, density);
    assert_int_equal(compare_traversal(&g, p, n, DDA_RAYS, seed), 0);
    grid_free(&g);
}

static void test_traversal(void **state)
{
    (void)state;
    float *p = random_soup(2000, 10.0, 1.0, SEED + 11);
    traverse_case(p, 2000, 2.0f, SEED + 12);
    traverse_case(p, 2000, 8.0f, SEED + 13);
    free(p);
    p = random_soup(300, 10.0, 6.0, SEED + 14);
    traverse_case(p, 300, 4.0f, SEED + 15);
    free(p);
    uint32_t n;
    p = plane_mesh(20, 0.0f, &n);
    traverse_case(p, n, 2.0f, SEED + 16);
    free(p);
}

/* ------------------------------------------------------------------------ real scenes */

static bool scene_path(const char *rel, char *out, size_t size)
{
    const char *dir = getenv("VKRT_SCENES_DIR");
    struct stat sb;
    if (!dir || !*dir)
        return false;
    snprintf(out, size, "%s/%s", dir, rel);
    return stat(out, &sb) == 0;
}

static void print_stats(const char *name, const grid *g, uint32_t n)
{
    print_message("%s: %u triangles, dims %u x %u x %u = %u cells, %u refs (%.2f per triangle), "
                  "max cell refs %u, occupied %.1f%%, build %.1f ms\n",
                  name, n, g->dims[0], g->dims[1], g->dims[2], g->cell_count, g->ref_count,
                  (double)g->ref_count / n, g->max_cell_refs,
                  100.0 * g->occupied_cells / g->cell_count, g->build_ms);
}

/* Density sweep ($VKRT_GRID_SWEEP=1): CPU DDA (candidate rule) time and work on random rays. */
static void density_sweep(const char *name, const vkrt_mesh *m)
{
    const float densities[] = { 0.5f, 1.0f, 2.0f, 4.0f, 8.0f, 16.0f };
    for (size_t i = 0; i < sizeof densities / sizeof *densities; ++i) {
        grid g = build_ok(m->positions, m->triangle_count, densities[i]);
        rng r = { SEED };
        dda_stats st = { 0, 0 };
        const uint32_t rays = 100000;
        double t0 = vkrt_clock_ms();
        for (uint32_t k = 0; k < rays; ++k) {
            double o[3], d[3];
            random_ray(&r, &g, (int)(k % 2), o, d);
            grid_traverse(&g, m->positions, o, d, false, &st);
        }
        double ms = vkrt_clock_ms() - t0;
        print_message("%s sweep: density %4.1f cells %8u build %6.1f ms, %6.2f steps %7.2f tests "
                      "per ray, %.0f ns per ray\n", name, (double)densities[i], g.cell_count,
                      g.build_ms, (double)st.steps / rays, (double)st.tests / rays, ms * 1e6 / rays);
        grid_free(&g);
    }
}

static void real_scene(const char *rel, const char *name)
{
    char path[1024];
    if (!scene_path(rel, path, sizeof path)) {
        print_message("skipping %s: set VKRT_SCENES_DIR to the shared scenes folder\n", rel);
        skip();
    }
    vkrt_model m_model = {0};
    vkrt_error err = { { 0 } };
    if (!vkrt_obj_load(path, &m_model, &err))
        fail_msg("%s", err.msg);
    const vkrt_mesh m = m_model.meshes[0];
    grid g = build_ok(m.positions, m.triangle_count, 0.0f);
    /* Best of a few builds for the timing (the first pays for page faults). */
    double best = g.build_ms;
    for (int k = 0; k < 3; ++k) {
        grid h = build_ok(m.positions, m.triangle_count, 0.0f);
        best = fmin(best, h.build_ms);
        grid_free(&h);
    }
    print_stats(name, &g, m.triangle_count);
    print_message("%s: best build of 4: %.1f ms\n", name, best);
    assert_int_equal(check_invariants(&g, m.positions, m.triangle_count, 3), 0);
    assert_int_equal(compare_traversal(&g, m.positions, m.triangle_count, 300, SEED + 21), 0);
    const char *sweep = getenv("VKRT_GRID_SWEEP");
    if (sweep && strcmp(sweep, "1") == 0)
        density_sweep(name, &m);
    grid_free(&g);
    vkrt_model_free(&m_model);
}

static void test_bunny(void **state)
{
    (void)state;
    real_scene("stanford-bunny/stanford-bunny.obj", "bunny");
}

static void test_lost_empire(void **state)
{
    (void)state;
    real_scene("lost-empire/lost_empire.obj", "lost empire");
}

/* $VKRT_GRID_OBJ=path: statistics of any OBJ (used for the stadium scene). */
static void test_env_obj(void **state)
{
    (void)state;
    const char *path = getenv("VKRT_GRID_OBJ");
    if (!path || !*path) {
        print_message("skipping: set VKRT_GRID_OBJ to an OBJ file to print its grid statistics\n");
        skip();
    }
    vkrt_model m_model = {0};
    vkrt_error err = { { 0 } };
    if (!vkrt_obj_load(path, &m_model, &err))
        fail_msg("%s", err.msg);
    const vkrt_mesh m = m_model.meshes[0];
    grid g = build_ok(m.positions, m.triangle_count, 0.0f);
    print_stats(path, &g, m.triangle_count);
    assert_int_equal(check_invariants(&g, m.positions, m.triangle_count, 2), 0);
    grid_free(&g);
    vkrt_model_free(&m_model);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_no_triangles),
        cmocka_unit_test(test_non_finite),
        cmocka_unit_test(test_default_density),
        cmocka_unit_test(test_random_soups),
        cmocka_unit_test(test_flat_plane),
        cmocka_unit_test(test_boundary_triangles),
        cmocka_unit_test(test_degenerate_triangles),
        cmocka_unit_test(test_max_cells),
        cmocka_unit_test(test_traversal),
        cmocka_unit_test(test_bunny),
        cmocka_unit_test(test_lost_empire),
        cmocka_unit_test(test_env_obj),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
