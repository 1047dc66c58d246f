/*
 * test_ray_sort.c: the GPU's ray sort (glsl/lib/ray_sort.glsl, vkrt_renderer_trace_sorted)
 * against the CPU's direction cells (bench_direction_cell in src/bench_rays.c).
 *
 * For 2, 8 and 16 cells per side, over random rays and rays along the axes and the diagonals
 * (directions on cell borders): the sorted rays must be the input rays, each once and unchanged;
 * their cells, computed on the CPU, must never decrease (except where a direction lies within
 * rounding of a border, where GPU division may round the other way); they must spread over most
 * cells, so the check has something to check; every ray's hit must be the one the unsorted trace
 * found for it, bit for bit; and repeated sorts in one submission (the scan zeroes the totals for
 * the next) must give the same set again.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "../glsl/shared.h"
#include "bench_rays.h"
#include "gpu_fixture.h"
#include "render/renderer.h"
#include "scene/scene.h"

/* More than one chunk of the sort (4096 rays), and not a multiple of it. */
enum { RAY_COUNT = 20011, TRIANGLES = 3000 };

/* A direction this close to a cell border, in units of the map's [-1, 1] coordinates, may land
 * in either cell on the GPU (its division need not round correctly). */
#define BORDER_SLACK 1e-5f

static uint32_t rng_state = 7;
static float uniform(void)
{
    rng_state = rng_state * 1664525u + 1013904223u;
    return (rng_state >> 8) / 16777216.0f;
}

/* Random triangles of size about 0.1 in the unit cube. */
static void make_soup(vkrt_mesh *mesh)
{
    memset(mesh, 0, sizeof *mesh);
    mesh->triangle_count = TRIANGLES;
    mesh->positions = malloc(TRIANGLES * 9 * sizeof *mesh->positions);
    mesh->material = malloc(TRIANGLES * sizeof *mesh->material);
    assert_non_null(mesh->positions);
    assert_non_null(mesh->material);
    for (uint32_t i = 0; i < TRIANGLES; ++i) {
        float c[3] = {uniform(), uniform(), uniform()};
        for (int k = 0; k < 9; ++k)
            mesh->positions[9 * i + k] = c[k % 3] + 0.1f * (uniform() - 0.5f);
        mesh->material[i] = -1;
    }
    for (int k = 0; k < 3; ++k) {
        mesh->bounds_min[k] = INFINITY;
        mesh->bounds_max[k] = -INFINITY;
    }
    for (uint32_t i = 0; i < TRIANGLES * 3; ++i)
        for (int k = 0; k < 3; ++k) {
            mesh->bounds_min[k] = fminf(mesh->bounds_min[k], mesh->positions[3 * i + k]);
            mesh->bounds_max[k] = fmaxf(mesh->bounds_max[k], mesh->positions[3 * i + k]);
        }
}

/* Rays from random points in the cube: random directions, then the 6 axes and the 12 edge and 8
 * corner diagonals of a cube, which lie on cell borders of the octahedral map. */
static void make_rays(Ray *rays)
{
    static const float special[26][3] = {
        {1, 0, 0},  {-1, 0, 0}, {0, 1, 0},   {0, -1, 0},  {0, 0, 1},   {0, 0, -1},  {1, 1, 0},
        {1, -1, 0}, {-1, 1, 0}, {-1, -1, 0}, {1, 0, 1},   {1, 0, -1},  {-1, 0, 1},  {-1, 0, -1},
        {0, 1, 1},  {0, 1, -1}, {0, -1, 1},  {0, -1, -1}, {1, 1, 1},   {1, 1, -1},  {1, -1, 1},
        {1, -1, -1}, {-1, 1, 1}, {-1, 1, -1}, {-1, -1, 1}, {-1, -1, -1}};
    for (uint32_t i = 0; i < RAY_COUNT; ++i) {
        float d[3];
        if (i % 100 < 26) {
            memcpy(d, special[i % 100], sizeof d);
        } else {
            float a = 6.2831853f * uniform(), z = 1 - 2 * uniform(), s = sqrtf(1 - z * z);
            d[0] = s * cosf(a), d[1] = s * sinf(a), d[2] = z;
        }
        float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        rays[i] = (Ray){.origin = {uniform(), uniform(), uniform(), 0},
                        .direction = {d[0] / len, d[1] / len, d[2] / len, 3.4e38f},
                        .importance = {1, 1, 1, 0},
                        .info = {i, 0, 0, 0}};
    }
}

/* True when d's map coordinates lie within BORDER_SLACK of a border between cells. */
static bool near_border(const float d[3], uint32_t cells)
{
    float l1 = fabsf(d[0]) + fabsf(d[1]) + fabsf(d[2]), u = d[0] / l1, v = d[1] / l1;
    if (d[2] < 0) {
        float fu = (1 - fabsf(v)) * (u < 0 ? -1.0f : 1.0f), fv = (1 - fabsf(u)) * (v < 0 ? -1.0f : 1.0f);
        u = fu, v = fv;
    }
    float cu = (u * 0.5f + 0.5f) * cells, cv = (v * 0.5f + 0.5f) * cells;
    float slack = BORDER_SLACK * cells;
    return fabsf(cu - roundf(cu)) < slack || fabsf(cv - roundf(cv)) < slack || d[2] == 0;
}

/* sorted must hold every ray of rays once, unchanged, in nondecreasing CPU cells. */
static void check_sorted(const Ray *rays, const Ray *sorted, uint32_t cells)
{
    bool *seen = calloc(RAY_COUNT, sizeof *seen);
    bool *used = calloc(cells * cells, sizeof *used);
    assert_non_null(seen);
    assert_non_null(used);
    uint32_t previous = 0, against_order = 0, distinct = 0;
    for (uint32_t i = 0; i < RAY_COUNT; ++i) {
        uint32_t id = sorted[i].info.x;
        assert_true(id < RAY_COUNT);
        assert_false(seen[id]);
        seen[id] = true;
        assert_memory_equal(&sorted[i], &rays[id], sizeof(Ray));
        const float d[3] = {sorted[i].direction.x, sorted[i].direction.y, sorted[i].direction.z};
        uint32_t cell = bench_direction_cell(d, cells);
        if (cell < previous && !near_border(d, cells)) {
            if (against_order < 5)
                print_message("cells %u: ray %u (slot %u) in cell %u after cell %u\n", cells, id,
                              i, cell, previous);
            ++against_order;
        }
        if (!near_border(d, cells))
            previous = cell;
        distinct += !used[cell];
        used[cell] = true;
    }
    print_message("cells %u: %u rays in %u of %u cells, %u against the order\n", cells, RAY_COUNT,
                  distinct, cells * cells, against_order);
    assert_int_equal(against_order, 0);
    assert_true(distinct > cells * cells / 2);
    free(seen);
    free(used);
}

static void check_sort(void)
{
    gpu_context ctx;
    fixture_context_create(&ctx);
    vkrt_scene scene = {0};
    make_soup(&scene.mesh);
    Ray *rays = malloc(RAY_COUNT * sizeof *rays), *sorted = malloc(RAY_COUNT * sizeof *sorted);
    Hit *ref = malloc(RAY_COUNT * sizeof *ref), *hits = malloc(RAY_COUNT * sizeof *hits);
    assert_true(rays && sorted && ref && hits);
    make_rays(rays);
    const uint32_t cell_counts[] = {2, 8, 16};
    for (size_t c = 0; c < sizeof cell_counts / sizeof *cell_counts; ++c) {
        uint32_t cells = cell_counts[c];
        vkrt_error err = {{0}};
        vkrt_renderer r;
        vkrt_render_desc desc = {.width = RAY_COUNT, .height = 1, .accel = VKRT_ACCEL_BVH,
                                 .sort_cells = cells};
        if (!vkrt_renderer_create(&r, &ctx, &scene, &desc, &err))
            fail_msg("renderer: %s", err.msg);
        if (c == 0 && !vkrt_renderer_trace(&r, rays, RAY_COUNT, false, ref, 1, NULL, &err))
            fail_msg("trace: %s", err.msg);
        if (!vkrt_renderer_trace_sorted(&r, rays, RAY_COUNT, true, hits, sorted, 1, NULL, &err))
            fail_msg("sorted trace: %s", err.msg);
        check_sorted(rays, sorted, cells);
        uint32_t hit_count = 0;
        for (uint32_t i = 0; i < RAY_COUNT; ++i) {
            const Hit *want = &ref[sorted[i].info.x];
            assert_int_equal(hits[i].triangle, want->triangle);
            assert_true(hits[i].t == want->t);
            hit_count += hits[i].triangle != VKRT_NO_HIT;
        }
        assert_true(hit_count > RAY_COUNT / 10);
        /* Sort alone, three times over in one submission. */
        memset(sorted, 0, RAY_COUNT * sizeof *sorted);
        if (!vkrt_renderer_trace_sorted(&r, rays, RAY_COUNT, false, NULL, sorted, 3, NULL, &err))
            fail_msg("sort: %s", err.msg);
        check_sorted(rays, sorted, cells);
        vkrt_renderer_destroy(&r);
    }
    free(rays);
    free(sorted);
    free(ref);
    free(hits);
    vkrt_mesh_free(&scene.mesh);
    fixture_context_destroy(&ctx);
}

static void test_sort(void **state)
{
    (void)state;
    check_sort();
}

/* A few rays in 16x16 cells: the sort's scratch (totals, starts, places) is larger than the ray
 * slot buffer of so few rays would be, and must still fit (validation and robust access would
 * hide nothing here: the sorted rays are checked). */
static void test_few_rays(void **state)
{
    (void)state;
    gpu_context ctx;
    fixture_context_create(&ctx);
    vkrt_scene scene = {0};
    make_soup(&scene.mesh);
    enum { FEW = 37 };
    Ray rays[FEW], sorted[FEW];
    Hit hits[FEW];
    for (uint32_t i = 0; i < FEW; ++i) {
        float a = 0.17f * i, z = 1 - 2 * (i + 0.5f) / FEW, s = sqrtf(1 - z * z);
        rays[i] = (Ray){.origin = {0.5f, 0.5f, 0.5f, 0},
                        .direction = {s * cosf(a), s * sinf(a), z, 3.4e38f},
                        .importance = {1, 1, 1, 0},
                        .info = {i, 0, 0, 0}};
    }
    vkrt_error err = {{0}};
    vkrt_renderer r;
    vkrt_render_desc desc = {.width = FEW, .height = 1, .accel = VKRT_ACCEL_BVH, .sort_cells = 16};
    if (!vkrt_renderer_create(&r, &ctx, &scene, &desc, &err))
        fail_msg("renderer: %s", err.msg);
    if (!vkrt_renderer_trace_sorted(&r, rays, FEW, true, hits, sorted, 2, NULL, &err))
        fail_msg("sorted trace: %s", err.msg);
    bool seen[FEW] = {false};
    uint32_t previous = 0;
    for (uint32_t i = 0; i < FEW; ++i) {
        uint32_t id = sorted[i].info.x;
        assert_true(id < FEW);
        assert_false(seen[id]);
        seen[id] = true;
        assert_memory_equal(&sorted[i], &rays[id], sizeof(Ray));
        const float d[3] = {sorted[i].direction.x, sorted[i].direction.y, sorted[i].direction.z};
        uint32_t cell = bench_direction_cell(d, 16);
        assert_true(cell >= previous || near_border(d, 16));
        previous = cell;
    }
    vkrt_renderer_destroy(&r);
    vkrt_mesh_free(&scene.mesh);
    fixture_context_destroy(&ctx);
}

/* A renderer made without the sort refuses to sort, and bad cell counts are refused. */
static void test_refusals(void **state)
{
    (void)state;
    gpu_context ctx;
    fixture_context_create(&ctx);
    vkrt_scene scene = {0};
    make_soup(&scene.mesh);
    Ray ray = {.direction = {0, 0, 1, 1}};
    Hit hit;
    vkrt_error err = {{0}};
    vkrt_renderer r;
    vkrt_render_desc desc = {.width = 16, .height = 1, .accel = VKRT_ACCEL_BVH};
    if (!vkrt_renderer_create(&r, &ctx, &scene, &desc, &err))
        fail_msg("renderer: %s", err.msg);
    assert_false(vkrt_renderer_trace_sorted(&r, &ray, 1, true, &hit, NULL, 1, NULL, &err));
    assert_non_null(strstr(err.msg, "sort_cells"));
    vkrt_renderer_destroy(&r);
    desc.sort_cells = 17;
    assert_false(vkrt_renderer_create(&r, &ctx, &scene, &desc, &err));
    assert_non_null(strstr(err.msg, "17 cells"));
    vkrt_mesh_free(&scene.mesh);
    fixture_context_destroy(&ctx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sort),
        cmocka_unit_test(test_few_rays),
        cmocka_unit_test(test_refusals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
