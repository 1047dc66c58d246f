/*
 * test_bvh_lanes.c: the BVH builder's SIMD lanes (SSE2 on x86-64) against its plain-C lanes.
 *
 * src/accel/bvh.c and bvh_split.c do their box arithmetic in 4-lane vectors (bvh_lanes.h), with
 * an SSE2 version and a portable one that other architectures compile. Both must give the same tree, byte for byte, or the
 * GPU's traversal would differ between a user's x86 machine and an ARM render node. This test
 * links the same source twice: once as the library has it, once compiled with
 * BVH_SCALAR_LANES (meson renames that copy's functions to *_scalar), and compares the trees over
 * inputs that stress rounding: random soups over many scales, points, slivers, flat planes, and
 * the Stanford bunny when $VKRT_SCENES_DIR has it; plain builds and builds with spatial splits.
 * And that a record's lanes carry no subnormal number where its index lies in memory.
 */
#define _POSIX_C_SOURCE 200809L
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
#include "accel/bvh_lanes.h"
#include "scene/obj/obj_load.h"

/* The plain-C copy, built from the same bvh.c and bvh_split.c (tests/meson.build). */
bool bvh_build_scalar(bvh *out, const float *positions, uint32_t triangle_count,
                      const bvh_build_desc *desc, vkrt_error *err);
void bvh_free_scalar(bvh *b);

enum { FLOATS_PER_TRI = 9 };

/* splitmix64, fixed seeds: the same inputs on every platform. */
static uint64_t next(uint64_t *s)
{
    uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

static float unit(uint64_t *s)
{
    return (float)(next(s) >> 40) * (1.0f / 16777216.0f);
}

/* n triangles mixing scales from 1e-6 to 1e6, with a quarter of them degenerate (a point, two
 * equal corners, collinear corners) and some on one shared plane. */
static float *make_mixed(uint32_t n, uint64_t seed)
{
    float *p = malloc((size_t)n * FLOATS_PER_TRI * sizeof *p);
    assert_non_null(p);
    for (uint32_t i = 0; i < n; i++) {
        float *t = p + (size_t)i * FLOATS_PER_TRI;
        float scale = (float)(1e-6 * (double)(1ull << (next(&seed) % 40)));
        float c[3] = { unit(&seed) * 100.0f, unit(&seed) * 100.0f, unit(&seed) * 100.0f };
        for (int k = 0; k < FLOATS_PER_TRI; k++)
            t[k] = c[k % 3] + (unit(&seed) - 0.5f) * scale;
        switch (next(&seed) % 8) {
        case 0: /* a point */
            memcpy(t + 3, t, 3 * sizeof *t);
            memcpy(t + 6, t, 3 * sizeof *t);
            break;
        case 1: /* two equal corners */
            memcpy(t + 6, t + 3, 3 * sizeof *t);
            break;
        case 2: /* collinear corners */
            for (int a = 0; a < 3; a++)
                t[6 + a] = t[a] + (t[3 + a] - t[a]) * 0.5f;
            break;
        case 3: /* on the plane z = 50 */
            t[2] = t[5] = t[8] = 50.0f;
            break;
        default:
            break;
        }
    }
    return p;
}

/* Builds with both lanes, with a spatial splits' budget (0: none; bvh_spatial.c clips triangles
 * in lanes too), and compares the trees. */
static void assert_same_builds(const float *pos, uint32_t n, uint32_t threads, float budget)
{
    const bvh_build_desc d = { .threads = threads, .spatial_budget = budget };
    vkrt_error err = { "" };
    bvh simd, plain;
    if (!bvh_build(&simd, pos, n, &d, &err) || !bvh_build_scalar(&plain, pos, n, &d, &err))
        fail_msg("%s", err.msg);
    assert_int_equal(simd.node_count, plain.node_count);
    assert_memory_equal(simd.nodes, plain.nodes, simd.node_count * sizeof *simd.nodes);
    assert_int_equal(simd.prim_count, plain.prim_count);
    assert_memory_equal(simd.prim_order, plain.prim_order, simd.prim_count * sizeof *simd.prim_order);
    assert_true(simd.sah_cost == plain.sah_cost);
    /* A tree of one leaf would make the comparison vacuous. */
    assert_true(n < 2 || simd.node_count > 1);
    bvh_free(&simd);
    bvh_free_scalar(&plain);
}

static void test_mixed_soups(void **state)
{
    (void)state;
    const uint32_t sizes[] = { 1, 2, 3, 17, 1000, 40000 };
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++) {
        float *pos = make_mixed(sizes[i], 1000 + i);
        assert_same_builds(pos, sizes[i], 1, 0.0f);
        assert_same_builds(pos, sizes[i], 2, 0.0f);
        assert_same_builds(pos, sizes[i], 2, 0.3f);
        free(pos);
    }
}

static void test_bunny(void **state)
{
    (void)state;
    const char *dir = getenv("VKRT_SCENES_DIR");
    char path[1024];
    struct stat st;
    snprintf(path, sizeof path, "%s/stanford-bunny/stanford-bunny.obj", dir ? dir : "");
    if (!dir || !*dir || stat(path, &st) != 0) {
        printf("  skipped: %s is missing\n", path);
        skip();
        return;
    }
    vkrt_model mesh_model = {0};
    vkrt_error err = { "" };
    if (!vkrt_obj_load(path, &mesh_model, &err))
        fail_msg("%s", err.msg);
    const vkrt_mesh mesh = mesh_model.meshes[0];
    assert_same_builds(mesh.positions, mesh.triangle_count, 2, 0.0f);
    assert_same_builds(mesh.positions, mesh.triangle_count, 2, 0.3f);
    vkrt_model_free(&mesh_model);
}

/* ref_load gives lane 3 (where a record keeps its index) as +0 in its bounds and centroid: an
 * index read as a float is subnormal below 2^23, and arithmetic on subnormals costs Intel cores a
 * microcode assist per operation (bvh_lanes.h). Bit patterns, not values: a subnormal is not 0. */
static void test_index_lane_is_zero(void **state)
{
    (void)state;
    const uint32_t indices[] = { 0, 1, 12345, (1u << 23) - 1, 1u << 23, (1u << 24) + 7, 0x7FFFFFFFu };
    for (size_t i = 0; i < sizeof indices / sizeof indices[0]; i++) {
        prim_ref r = { .lo = { -1.0f, 2.0f, 3.0f }, .index = indices[i], .hi = { 4.0f, 5.0f, 6.0f } };
        ref_lanes l = ref_load(&r);
        float lanes[3][4];
        v4_store(lanes[0], l.lo);
        v4_store(lanes[1], l.hi);
        v4_store(lanes[2], l.c);
        for (int v = 0; v < 3; v++) {
            uint32_t bits;
            memcpy(&bits, &lanes[v][3], sizeof bits);
            assert_int_equal(bits, 0);
        }
        assert_true(lanes[0][0] == -1.0f && lanes[1][2] == 6.0f && lanes[2][1] == 3.5f);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mixed_soups),
        cmocka_unit_test(test_bunny),
        cmocka_unit_test(test_index_lane_is_zero),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
