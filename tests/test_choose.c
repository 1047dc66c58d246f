/*
 * test_choose.c: the `accel auto` rule on grids built from known layouts: a handful of triangles
 * gets brute force on a CPU device and the BVH on a GPU; an even soup gets the grid on a CPU device reading storage
 * buffers, the kd-tree on one reading texel buffers and the BVH on a GPU; a dense cluster inside
 * a sparse shell (a small teapot-in-a-stadium) gets the BVH where the grid is weighed; past
 * accel_kdtree_limit a CPU device reading texel buffers gets the BVH. On a GPU, the kd-tree is
 * weighed, and taken, for crossing tubes of long thin triangles (tools/sliver_cylinder.py's
 * layout, smaller), and not weighed for the even soup, from the SAH costs of real builds.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include <cmocka.h>

#include <math.h>

#include "accel/bvh.h"
#include "accel/choose.h"
#include "accel/kdtree.h"

static uint32_t rng = 7;
static float uniform(void)
{
    rng = rng * 1664525u + 1013904223u;
    return (rng >> 8) / 16777216.0f;
}

/* n small triangles: `dense` of them inside a cube of side 0.01 at the origin, the rest spread
 * over a cube of side 100. */
static float *soup(uint32_t n, uint32_t dense)
{
    float *p = malloc(9 * sizeof *p * n);
    assert_non_null(p);
    for (uint32_t t = 0; t < n; ++t) {
        float scale = t < dense ? 0.01f : 100.0f, size = t < dense ? 0.001f : 0.5f;
        float c[3] = {scale * uniform(), scale * uniform(), scale * uniform()};
        for (int v = 0; v < 3; ++v)
            for (int k = 0; k < 3; ++k)
                p[9 * t + 3 * v + k] = c[k] + (v == k ? size : 0);
    }
    return p;
}

static accel_choice choose(uint32_t n, uint32_t dense, accel_device device)
{
    static const char *const names[] = {"GPU", "CPU, texel loads", "CPU, storage loads"};
    float *p = soup(n, dense);
    grid g = {0};
    vkrt_error err;
    bool needs = accel_choice_needs_grid(n, device);
    if (needs && !grid_build(&g, p, n, NULL, &err))
        fail_msg("%s", err.msg);
    accel_choice c = accel_choose(n, device, needs ? &g : NULL);
    print_message("%u triangles, %u dense, %s: %s\n", n, dense, names[device], c.reason);
    grid_free(&g);
    free(p);
    return c;
}

/* A handful of triangles: brute force on a CPU device; on a GPU the BVH even so (the H200 traced
 * a 36-triangle box's camera rays 3.3x faster through it than by brute force). */
static void test_handful_is_brute_force(void **state)
{
    (void)state;
    for (accel_device d = ACCEL_DEVICE_GPU + 1; d <= ACCEL_DEVICE_CPU_STORAGE; ++d) {
        assert_int_equal(choose(accel_brute_force_limit(), 0, d).kind, VKRT_ACCEL_BRUTE);
        assert_int_not_equal(choose(accel_brute_force_limit() + 1, 0, d).kind, VKRT_ACCEL_BRUTE);
    }
    assert_int_equal(choose(36, 0, ACCEL_DEVICE_GPU).kind, VKRT_ACCEL_BVH);
    assert_int_equal(choose(1, 0, ACCEL_DEVICE_GPU).kind, VKRT_ACCEL_BVH);
}

static void test_even_soup(void **state)
{
    (void)state;
    assert_int_equal(choose(20000, 0, ACCEL_DEVICE_CPU_STORAGE).kind, VKRT_ACCEL_GRID);
    assert_int_equal(choose(20000, 0, ACCEL_DEVICE_CPU_TEXELS).kind, VKRT_ACCEL_KDTREE);
    assert_int_equal(choose(20000, 0, ACCEL_DEVICE_GPU).kind, VKRT_ACCEL_BVH);
    assert_false(accel_choice_needs_grid(20000, ACCEL_DEVICE_GPU));
    assert_false(accel_choice_needs_grid(20000, ACCEL_DEVICE_CPU_TEXELS));
}

static void test_dense_cluster_in_sparse_shell(void **state)
{
    (void)state;
    assert_int_equal(choose(20000, 15000, ACCEL_DEVICE_CPU_STORAGE).kind, VKRT_ACCEL_BVH);
    assert_int_equal(choose(20000, 15000, ACCEL_DEVICE_GPU).kind, VKRT_ACCEL_BVH);
}

/* The kd-tree's build is what limits it on a CPU device: past accel_kdtree_limit, the BVH. */
static void test_big_scene_on_cpu_texels(void **state)
{
    (void)state;
    uint32_t n = accel_kdtree_limit();
    assert_int_equal(accel_choose(n, ACCEL_DEVICE_CPU_TEXELS, NULL).kind, VKRT_ACCEL_KDTREE);
    assert_int_equal(accel_choose(n + 1, ACCEL_DEVICE_CPU_TEXELS, NULL).kind, VKRT_ACCEL_BVH);
}

/* tubes crossing tubes of `sides` x `rings` slivers each, as tools/sliver_cylinder.py makes them
 * (without its ground); *count gets the triangle count. */
static float *slivers(uint32_t tubes, uint32_t sides, uint32_t rings, uint32_t *count)
{
    const double pi = 3.14159265358979, length = 16.0;
    *count = tubes * sides * rings * 2;
    float *p = malloc(9 * sizeof *p * *count), *out = p;
    assert_non_null(p);
    for (uint32_t i = 0; i < tubes; ++i) {
        double turn = pi * i / tubes, tz = 0.5 + turn, tx = 0.35 * ((int)(i % 3) - 1);
        double off[3] = {2.0 * cos(turn), 0.0, 2.0 * sin(turn)};
        for (uint32_t r = 0; r < rings; ++r)
            for (uint32_t k = 0; k < sides; ++k) {
                /* The strip's corners: (ring, side) at a, b, c, d as the tool orders them. */
                uint32_t corner[4][2] = {{r, k}, {r, (k + 1) % sides}, {r + 1, (k + 1) % sides},
                                         {r + 1, k}};
                static const int tri[2][3] = {{0, 1, 2}, {0, 2, 3}};
                for (int t = 0; t < 2; ++t)
                    for (int v = 0; v < 3; ++v) {
                        const uint32_t *c = corner[tri[t][v]];
                        double y = -length / 2 + length * c[0] / rings, a = 2 * pi * c[1] / sides;
                        double x = cos(a), z = sin(a);
                        double x1 = x * cos(tz) - y * sin(tz), y1 = x * sin(tz) + y * cos(tz);
                        double y2 = y1 * cos(tx) - z * sin(tx), z2 = y1 * sin(tx) + z * cos(tx);
                        *out++ = (float)(x1 + off[0]);
                        *out++ = (float)(y2 + off[1]);
                        *out++ = (float)(z2 + off[2]);
                    }
            }
    }
    return p;
}

/* What `auto` on a GPU does after choosing the BVH: the BVH with the GPU's settings (leaves of 2,
 * node cost 0.5: tuning.c), the kd-tree when the rule says it is worth trying; true if the
 * kd-tree is taken. */
static bool gpu_takes_kdtree(const float *p, uint32_t n)
{
    vkrt_error err;
    bvh b;
    const bvh_build_desc desc = {.max_leaf_size = 2, .traversal_cost = 0.5f};
    if (!bvh_build(&b, p, n, &desc, &err))
        fail_msg("%s", err.msg);
    float bvh_cost = b.sah_cost;
    bvh_free(&b);
    bool worth = accel_kdtree_worth_trying(n, bvh_cost);
    print_message("%u triangles: BVH SAH cost %.1f (%.2f per doubling): kd-tree %s\n", n,
                  (double)bvh_cost, bvh_cost / log2((double)n), worth ? "weighed" : "not weighed");
    if (!worth)
        return false;
    kdtree t;
    if (!kdtree_build(&t, p, n, NULL, &err))
        fail_msg("%s", err.msg);
    print_message("  kd-tree SAH cost %.1f\n", (double)t.sah_cost);
    bool wins = accel_kdtree_wins(t.sah_cost, bvh_cost);
    kdtree_free(&t);
    return wins;
}

static void test_slivers_on_gpu(void **state)
{
    (void)state;
    uint32_t n;
    float *p = slivers(4, 500, 6, &n);
    assert_true(gpu_takes_kdtree(p, n));
    free(p);
    p = soup(n, 0);
    assert_false(gpu_takes_kdtree(p, n));
    free(p);
    /* Past the kd-tree's limit it is never weighed, nor for a handful. */
    assert_false(accel_kdtree_worth_trying(accel_kdtree_limit() + 1, 1e9f));
    assert_false(accel_kdtree_worth_trying(accel_brute_force_limit(), 1e9f));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_handful_is_brute_force),
        cmocka_unit_test(test_even_soup),
        cmocka_unit_test(test_dense_cluster_in_sparse_shell),
        cmocka_unit_test(test_big_scene_on_cpu_texels),
        cmocka_unit_test(test_slivers_on_gpu),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
