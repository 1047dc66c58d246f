/*
 * test_intersect.c: the kernels' ray-triangle test (glsl/lib/intersect.glsl), run on the GPU
 * against hand-computed cases, and the watertightness it promises.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "../glsl/shared.h"
#include "gpu_fixture.h"

typedef struct Case {
    vec4 origin;    /* w: tmin */
    vec4 direction; /* w: tmax */
    vec4 v0, v1, v2;
} Case;

typedef struct Result {
    float hit, t, u, v;
} Result;

static const char *kernel =
    "#include \"lib/intersect.glsl\"\n"
    "layout(local_size_x_id = 0) in;\n"
    "struct Case { vec4 origin; vec4 direction; vec4 v0; vec4 v1; vec4 v2; };\n"
    "layout(std430, binding = 0) readonly buffer Cases { Case cases[]; };\n"
    "layout(std430, binding = 1) writeonly buffer Results { vec4 results[]; };\n"
    "layout(push_constant) uniform Push { uint count; };\n"
    "void main() {\n"
    "  uint i = gl_GlobalInvocationID.x;\n"
    "  if (i >= count) return;\n"
    "  Case c = cases[i];\n"
    "  RayShear s = ray_shear_make(c.origin.xyz, c.direction.xyz);\n"
    "  float t, u, v;\n"
    "  bool hit = intersect_triangle(s, c.v0.xyz, c.v1.xyz, c.v2.xyz, c.origin.w, c.direction.w, t, u, v);\n"
    "  results[i] = vec4(hit ? 1.0 : 0.0, t, u, v);\n"
    "}\n";

static void run_cases(const Case *cases, uint32_t count, Result *results)
{
    gpu_context ctx;
    fixture_context_create(&ctx);
    vkrt_error err = {{0}};
    gpu_buffer bufs[2];
    assert_true(gpu_buffer_create(&ctx, &bufs[0], count * sizeof *cases, "cases", &err));
    assert_true(gpu_buffer_create(&ctx, &bufs[1], count * sizeof *results, "results", &err));
    assert_true(gpu_buffer_upload(&ctx, &bufs[0], cases, count * sizeof *cases, &err));
    fixture_run_kernel(&ctx, kernel, bufs, 2, &count, sizeof count, count);
    assert_true(gpu_buffer_download(&ctx, &bufs[1], results, count * sizeof *results, &err));
    gpu_buffer_destroy(&ctx, &bufs[1]);
    gpu_buffer_destroy(&ctx, &bufs[0]);
    fixture_context_destroy(&ctx);
}

static vec4 v3(float x, float y, float z, float w)
{
    return (vec4){x, y, z, w};
}

#define FAR 3.4e38f

/* The unit right triangle in the z = 0 plane. */
#define UNIT_TRI v3(0, 0, 0, 0), v3(1, 0, 0, 0), v3(0, 1, 0, 0)

static void test_hand_computed_cases(void **state)
{
    (void)state;
    const float d = sqrtf(27.0f);
    const Case cases[] = {
        /* 0: straight down onto (0.25, 0.25): t = 1, barycentrics of v1 and v2 are 0.25. */
        {v3(0.25f, 0.25f, 1, 0), v3(0, 0, -1, FAR), UNIT_TRI},
        /* 1: from below: triangles are two-sided, t = 2. */
        {v3(0.25f, 0.25f, -2, 0), v3(0, 0, 1, FAR), UNIT_TRI},
        /* 2: outside the hypotenuse (u + v = 1.5): miss. */
        {v3(0.75f, 0.75f, 1, 0), v3(0, 0, -1, FAR), UNIT_TRI},
        /* 3: exactly on the edge v0-v1: edges are inclusive, hit with v = 0. */
        {v3(0.5f, 0, 1, 0), v3(0, 0, -1, FAR), UNIT_TRI},
        /* 4: exactly through vertex v0: hit, u = v = 0. */
        {v3(0, 0, 1, 0), v3(0, 0, -1, FAR), UNIT_TRI},
        /* 5: parallel to the plane, in it: det = 0, no hit. */
        {v3(0.25f, 0.25f, 0, 0), v3(1, 0, 0, FAR), UNIT_TRI},
        /* 6: pointing away: the hit would be at t = -1, miss. */
        {v3(0.25f, 0.25f, 1, 0), v3(0, 0, 1, FAR), UNIT_TRI},
        /* 7: the hit at t = 1 lies beyond tmax = 0.5: miss. */
        {v3(0.25f, 0.25f, 1, 0), v3(0, 0, -1, 0.5f), UNIT_TRI},
        /* 8: degenerate (collinear) triangle: never a hit. */
        {v3(0.5f, 0, 1, 0), v3(0, 0, -1, FAR), v3(0, 0, 0, 0), v3(1, 0, 0, 0), v3(2, 0, 0, 0)},
        /* 9: oblique: from the origin towards (1, 1, 5) on the triangle (0,0,5) (4,0,5) (0,4,5):
         * t = |(1,1,5)| = sqrt(27), barycentrics 1/4 and 1/4. */
        {v3(0, 0, 0, 0), v3(1 / d, 1 / d, 5 / d, FAR), v3(0, 0, 5, 0), v3(4, 0, 5, 0),
         v3(0, 4, 5, 0)},
        /* 10: tmin excludes the hit at t = 1 (the shadow-ray case of a surface behind us). */
        {v3(0.25f, 0.25f, 1, 1.5f), v3(0, 0, -1, FAR), UNIT_TRI},
        /* 11: far from the origin (1e5): hit at t = 2 within float precision there. */
        {v3(1e5f + 0.25f, 1e5f + 0.25f, 1e5f + 2, 0), v3(0, 0, -1, FAR), v3(1e5f, 1e5f, 1e5f, 0),
         v3(1e5f + 1, 1e5f, 1e5f, 0), v3(1e5f, 1e5f + 1, 1e5f, 0)},
    };
    const Result expected[] = {
        {1, 1, 0.25f, 0.25f}, {1, 2, 0.25f, 0.25f}, {0, 0, 0, 0}, {1, 1, 0.5f, 0},
        {1, 1, 0, 0},         {0, 0, 0, 0},         {0, 0, 0, 0}, {0, 0, 0, 0},
        {0, 0, 0, 0},         {1, d, 0.25f, 0.25f}, {0, 0, 0, 0}, {1, 2, 0.25f, 0.25f},
    };
    const uint32_t count = sizeof cases / sizeof *cases;
    Result results[sizeof cases / sizeof *cases];
    run_cases(cases, count, results);
    for (uint32_t i = 0; i < count; ++i) {
        if (results[i].hit != expected[i].hit)
            fail_msg("case %u: hit %g, expected %g", i, results[i].hit, expected[i].hit);
        if (!expected[i].hit)
            continue;
        /* Float arithmetic on these exact inputs: a few ULPs at magnitude 1, and at 1e5 the
         * spacing of floats is 0.0078, so t and barycentrics carry that much there. */
        float tol = i == 11 ? 0.02f : 1e-5f;
        if (fabsf(results[i].t - expected[i].t) > tol * fmaxf(1, expected[i].t) ||
            fabsf(results[i].u - expected[i].u) > tol ||
            fabsf(results[i].v - expected[i].v) > tol)
            fail_msg("case %u: t %.7g u %.7g v %.7g, expected t %.7g u %.7g v %.7g", i,
                     results[i].t, results[i].u, results[i].v, expected[i].t, expected[i].u,
                     expected[i].v);
    }
}

/* Rays aimed exactly at points of the diagonal shared by the two triangles of a unit square,
 * from many directions: a test that is not watertight lets some slip between the triangles. */
static void test_shared_edge_is_watertight(void **state)
{
    (void)state;
    enum { rays = 2000 };
    Case *cases = calloc(2 * rays, sizeof *cases);
    Result *results = calloc(2 * rays, sizeof *results);
    assert_non_null(cases);
    assert_non_null(results);
    uint32_t seed = 12345;
    for (int i = 0; i < rays; ++i) {
        float s = (i + 0.5f) / rays;
        /* A direction from a simple LCG, pointing down through the plane. */
        seed = seed * 1664525u + 1013904223u;
        float dx = ((seed >> 8) / 16777216.0f - 0.5f) * 1.5f;
        seed = seed * 1664525u + 1013904223u;
        float dy = ((seed >> 8) / 16777216.0f - 0.5f) * 1.5f;
        float len = sqrtf(dx * dx + dy * dy + 1);
        vec4 dir = v3(dx / len, dy / len, -1 / len, FAR);
        /* The origin lies back along the ray from the target point (s, s, 0) of the edge. */
        vec4 origin = v3(s - 3 * dir.x, s - 3 * dir.y, -3 * dir.z, 0);
        cases[2 * i] = (Case){origin, dir, v3(0, 0, 0, 0), v3(1, 0, 0, 0), v3(1, 1, 0, 0)};
        cases[2 * i + 1] = (Case){origin, dir, v3(0, 0, 0, 0), v3(1, 1, 0, 0), v3(0, 1, 0, 0)};
    }
    run_cases(cases, 2 * rays, results);
    int leaks = 0;
    for (int i = 0; i < rays; ++i)
        if (!results[2 * i].hit && !results[2 * i + 1].hit)
            ++leaks;
    free(cases);
    free(results);
    if (leaks)
        fail_msg("%d of %d rays through the shared edge hit neither triangle", leaks, rays);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_hand_computed_cases),
        cmocka_unit_test(test_shared_edge_is_watertight),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
