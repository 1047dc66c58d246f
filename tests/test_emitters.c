/*
 * test_emitters.c: unit tests for src/scene/emitters.c, the alias table over emissive triangles.
 *
 * The reference is the definition: the probability that the table yields a triangle is the sum,
 * over its entries, of keep / n for the entry itself and (1 - keep) / n for every entry aliasing
 * to it, summed here in double from the float table the GPU would read. It must equal
 * luminance(Ke) * area / total, computed here independently, to 1e-6 relative, for every
 * triangle, under distributions chosen to break a careless Vose: random, one huge among many,
 * many tiny, all equal, a geometric range over 30 decades, one alone, none.
 */
#include <setjmp.h> /* cmocka needs these before its header */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scene/emitters.h"

/* A mesh of triangles laid side by side, each with its own material. */
typedef struct mesh {
    uint32_t count;
    float *positions;
    uint32_t *material;
    float *ke;
} mesh;

static mesh mesh_new(uint32_t count)
{
    mesh m = {count, calloc((size_t)count * 9, sizeof(float)), calloc(count, sizeof(uint32_t)),
              calloc((size_t)count * 3, sizeof(float))};
    assert_non_null(m.positions);
    assert_non_null(m.material);
    assert_non_null(m.ke);
    for (uint32_t t = 0; t < count; t++)
        m.material[t] = t;
    return m;
}

static void mesh_free(mesh *m)
{
    free(m->positions);
    free(m->material);
    free(m->ke);
}

/* Triangle t gets area `area` (legs 2 and area along x and y, at z = t) and grey Ke `ke`. */
static void set_triangle(mesh *m, uint32_t t, float area, float ke)
{
    float *v = m->positions + (size_t)t * 9;
    const float corners[9] = {0, 0, (float)t, area, 0, (float)t, 0, 2, (float)t};
    memcpy(v, corners, sizeof corners);
    m->ke[(size_t)t * 3 + 0] = ke;
    m->ke[(size_t)t * 3 + 1] = ke;
    m->ke[(size_t)t * 3 + 2] = ke;
}

/* The power the table should use for triangle t, from the definition. */
static double expected_power(const mesh *m, uint32_t t)
{
    const float *v = m->positions + (size_t)t * 9;
    double a[3], b[3];
    for (int k = 0; k < 3; k++) {
        a[k] = (double)v[3 + k] - v[k];
        b[k] = (double)v[6 + k] - v[k];
    }
    double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    double area = 0.5 * sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    const float *ke = m->ke + (size_t)m->material[t] * 3;
    double lum = 0.2126 * ke[0] + 0.7152 * ke[1] + 0.0722 * ke[2];
    return lum > 0 && area > 0 ? lum * area : 0.0;
}

static void build(const mesh *m, vkrt_emitters *e)
{
    vkrt_error err = {{0}};
    bool ok = vkrt_emitters_build(m->positions, m->count, m->material, m->ke, m->count, e, &err);
    if (!ok)
        print_error("unexpected failure: %s\n", err.msg);
    assert_true(ok);
}

/* Checks the table against the definition; returns the worst relative error. */
static double check_table(const mesh *m, const vkrt_emitters *e)
{
    double total = 0.0;
    uint32_t emissive = 0;
    for (uint32_t t = 0; t < m->count; t++) {
        double p = expected_power(m, t);
        total += p;
        emissive += p > 0;
    }
    assert_int_equal(e->count, emissive);
    if (emissive == 0) {
        assert_null(e->triangle);
        assert_null(e->keep);
        assert_null(e->alias);
        assert_null(e->power);
        assert_true(e->total_power == 0.0);
        return 0.0;
    }
    assert_true(fabs(e->total_power - total) <= 1e-12 * total);

    uint32_t n = e->count;
    double *prob = calloc(n, sizeof *prob);
    assert_non_null(prob);
    for (uint32_t i = 0; i < n; i++) {
        assert_true(e->keep[i] >= 0.0f && e->keep[i] <= 1.0f);
        assert_true(e->alias[i] < n);
        prob[i] += (double)e->keep[i] / n;
        prob[e->alias[i]] += (1.0 - (double)e->keep[i]) / n;
    }
    double worst = 0.0;
    uint32_t previous = 0;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t t = e->triangle[i];
        /* Entries in triangle order, each an emissive triangle. */
        assert_true(t < m->count);
        assert_true(i == 0 || t > previous);
        previous = t;
        double want = expected_power(m, t);
        assert_true(want > 0.0);
        assert_true(fabs((double)e->power[i] - want) <= 1e-7 * want);
        double rel = fabs(prob[i] - want / total) / (want / total);
        if (rel > worst)
            worst = rel;
    }
    free(prob);
    if (worst > 1e-6)
        print_error("worst relative error %g\n", worst);
    assert_true(worst <= 1e-6);
    return worst;
}

/* xorshift64*, so the random cases are the same on every run. */
static uint64_t rng_state = 0x9E3779B97F4A7C15ull;
static double uniform(void)
{
    rng_state ^= rng_state >> 12;
    rng_state ^= rng_state << 25;
    rng_state ^= rng_state >> 27;
    return (double)((rng_state * 0x2545F4914F6CDD1Dull) >> 11) * 0x1.0p-53;
}

/* ---------------------------------------------------------------------------------------------
 * Distributions
 * ------------------------------------------------------------------------------------------- */

static void test_random(void **state)
{
    (void)state;
    for (uint32_t n = 1; n <= 5000; n *= 7) {
        mesh m = mesh_new(n);
        for (uint32_t t = 0; t < n; t++) {
            /* A third of the triangles do not emit. */
            float ke = uniform() < 0.33 ? 0.0f : (float)(uniform() * 20.0);
            set_triangle(&m, t, (float)(0.01 + uniform() * 5.0), ke);
        }
        /* Coloured Ke: luminance, not the sum or the maximum, weighs it. */
        if (n > 2) {
            m.ke[3] = 17.0f, m.ke[4] = 12.0f, m.ke[5] = 4.0f;
            m.ke[6] = 0.0f, m.ke[7] = 0.0f, m.ke[8] = 1.0f;
        }
        vkrt_emitters e;
        build(&m, &e);
        check_table(&m, &e);
        vkrt_emitters_free(&e);
        mesh_free(&m);
    }
}

static void test_one_huge(void **state)
{
    (void)state;
    uint32_t n = 10000;
    for (uint32_t where = 0; where < n; where += n - 1) {
        mesh m = mesh_new(n);
        for (uint32_t t = 0; t < n; t++)
            set_triangle(&m, t, 1.0f, t == where ? 1e12f : 1.0f);
        vkrt_emitters e;
        build(&m, &e);
        check_table(&m, &e);
        vkrt_emitters_free(&e);
        mesh_free(&m);
    }
}

static void test_many_tiny(void **state)
{
    (void)state;
    uint32_t n = 20000;
    mesh m = mesh_new(n);
    for (uint32_t t = 0; t < n; t++)
        set_triangle(&m, t, t % 1000 == 0 ? 1.0f : 1e-6f, t % 3 == 0 ? 1e-12f : 1.0f);
    vkrt_emitters e;
    build(&m, &e);
    check_table(&m, &e);
    vkrt_emitters_free(&e);
    mesh_free(&m);
}

static void test_equal(void **state)
{
    (void)state;
    uint32_t n = 4099;
    mesh m = mesh_new(n);
    for (uint32_t t = 0; t < n; t++)
        set_triangle(&m, t, 0.5f, 3.0f);
    vkrt_emitters e;
    build(&m, &e);
    check_table(&m, &e);
    vkrt_emitters_free(&e);
    mesh_free(&m);
}

/* Powers 2^-k and 10^-k: every entry but a few is small, and large entries turn small in a
 * cascade, each carrying the rounding of the last. */
static void test_geometric(void **state)
{
    (void)state;
    uint32_t n = 120;
    mesh m = mesh_new(n);
    for (uint32_t t = 0; t < n; t++)
        set_triangle(&m, t, 1.0f, ldexpf(1.0f, -(int)t));
    vkrt_emitters e;
    build(&m, &e);
    check_table(&m, &e);
    vkrt_emitters_free(&e);

    for (uint32_t t = 0; t < n; t++)
        set_triangle(&m, t, (float)pow(10.0, -(double)(t % 30)), (float)(1 + t % 7));
    build(&m, &e);
    check_table(&m, &e);
    vkrt_emitters_free(&e);
    mesh_free(&m);
}

static void test_single_and_none(void **state)
{
    (void)state;
    mesh m = mesh_new(5);
    for (uint32_t t = 0; t < 5; t++)
        set_triangle(&m, t, 1.0f, t == 3 ? 2.0f : 0.0f);
    vkrt_emitters e;
    build(&m, &e);
    check_table(&m, &e);
    assert_int_equal(e.count, 1);
    assert_int_equal(e.triangle[0], 3);
    assert_float_equal(e.keep[0], 1.0f, 0);
    assert_int_equal(e.alias[0], 0);
    vkrt_emitters_free(&e);

    /* No emitter: an empty table, and success. */
    m.ke[9] = 0.0f, m.ke[10] = 0.0f, m.ke[11] = 0.0f;
    memset(&e, 0xAB, sizeof e);
    build(&m, &e);
    check_table(&m, &e);
    vkrt_emitters_free(&e);

    /* No triangles at all. */
    vkrt_error err = {{0}};
    memset(&e, 0xAB, sizeof e);
    assert_true(vkrt_emitters_build(NULL, 0, NULL, NULL, 0, &e, &err));
    assert_int_equal(e.count, 0);
    assert_null(e.keep);
    vkrt_emitters_free(&e);
    vkrt_emitters_free(NULL);
    mesh_free(&m);
}

/* Degenerate triangles (a point, collinear corners) can never be hit: they are not in the table,
 * and the others keep their original indices. */
static void test_zero_area_skipped(void **state)
{
    (void)state;
    mesh m = mesh_new(6);
    for (uint32_t t = 0; t < 6; t++)
        set_triangle(&m, t, 1.0f + (float)t, 5.0f);
    set_triangle(&m, 1, 0.0f, 5.0f); /* two corners coincide */
    float *v = m.positions + 4 * 9;  /* collinear corners */
    const float line[9] = {0, 0, 0, 1, 1, 1, 2, 2, 2};
    memcpy(v, line, sizeof line);
    vkrt_emitters e;
    build(&m, &e);
    check_table(&m, &e);
    assert_int_equal(e.count, 4);
    const uint32_t want[4] = {0, 2, 3, 5};
    for (int i = 0; i < 4; i++)
        assert_int_equal(e.triangle[i], want[i]);
    vkrt_emitters_free(&e);
    mesh_free(&m);
}

/* Triangles share materials through the index; an index past the materials is an error. */
static void test_shared_materials_and_errors(void **state)
{
    (void)state;
    mesh m = mesh_new(8);
    for (uint32_t t = 0; t < 8; t++) {
        set_triangle(&m, t, 1.0f + (float)t, 0.0f);
        m.material[t] = t % 2;
    }
    m.ke[0] = 1.0f, m.ke[1] = 2.0f, m.ke[2] = 3.0f; /* material 0 emits, material 1 does not */
    vkrt_emitters e;
    vkrt_error err = {{0}};
    assert_true(vkrt_emitters_build(m.positions, 8, m.material, m.ke, 2, &e, &err));
    check_table(&m, &e);
    assert_int_equal(e.count, 4);
    vkrt_emitters_free(&e);

    m.material[5] = 2;
    memset(&e, 0xAB, sizeof e);
    assert_false(vkrt_emitters_build(m.positions, 8, m.material, m.ke, 2, &e, &err));
    assert_string_equal(err.msg, "emitters: triangle 5 has material 2, out of range (2 materials)");
    assert_int_equal(e.count, 0);
    assert_null(e.keep);

    m.material[5] = 1;
    m.ke[4] = -1.0f;
    assert_false(vkrt_emitters_build(m.positions, 8, m.material, m.ke, 2, &e, &err));
    assert_non_null(strstr(err.msg, "material 1 has a negative or non-finite Ke"));
    m.ke[4] = INFINITY;
    assert_false(vkrt_emitters_build(m.positions, 8, m.material, m.ke, 2, &e, &err));
    assert_int_equal(e.count, 0);

    /* A power past the float range. */
    m.ke[4] = 3e38f;
    set_triangle(&m, 1, 1e10f, 3e38f);
    assert_false(vkrt_emitters_build(m.positions, 8, m.material, m.ke, 2, &e, &err));
    assert_non_null(strstr(err.msg, "emitters: triangle 1: its power"));
    assert_null(e.triangle);
    mesh_free(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_random),
        cmocka_unit_test(test_one_huge),
        cmocka_unit_test(test_many_tiny),
        cmocka_unit_test(test_equal),
        cmocka_unit_test(test_geometric),
        cmocka_unit_test(test_single_and_none),
        cmocka_unit_test(test_zero_area_skipped),
        cmocka_unit_test(test_shared_materials_and_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
