/*
 * test_choose.c: the `accel auto` rule on grids built from known layouts: a handful of triangles
 * gets brute force on every device; an even soup gets the grid on a CPU device reading storage
 * buffers, the kd-tree on one reading texel buffers and the BVH on a GPU; a dense cluster inside
 * a sparse shell (a small teapot-in-a-stadium) gets the BVH where the grid is weighed; past
 * accel_kdtree_limit a CPU device reading texel buffers gets the BVH.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include <cmocka.h>

#include "accel/choose.h"

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

static void test_handful_is_brute_force(void **state)
{
    (void)state;
    for (accel_device d = ACCEL_DEVICE_GPU; d <= ACCEL_DEVICE_CPU_STORAGE; ++d) {
        assert_int_equal(choose(accel_brute_force_limit(), 0, d).kind, VKRT_ACCEL_BRUTE);
        assert_int_not_equal(choose(accel_brute_force_limit() + 1, 0, d).kind, VKRT_ACCEL_BRUTE);
    }
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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_handful_is_brute_force),
        cmocka_unit_test(test_even_soup),
        cmocka_unit_test(test_dense_cluster_in_sparse_shell),
        cmocka_unit_test(test_big_scene_on_cpu_texels),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
