/*
 * test_accel.c: the grid, the BVH and the kd-tree, walked on the GPU, against brute force on the
 * GPU.
 *
 * All three share the kernels' intersection test, so for the same triangle they report the same
 * t bit for bit; they may differ only when two triangles are hit at the same distance (a shared
 * edge or vertex, coplanar overlaps). So: same hit or miss always; same triangle unless t ties.
 * Rays: camera-like rays from outside the scene's bounds, random rays from random points inside
 * them, and rays exactly along the six axis directions. Scenes: every OBJ scene in
 * ../shared/scenes (skipped with a message where that folder is absent), an icosphere and the
 * teapot-in-a-stadium scene made by tools/teapot_stadium.py. The BVH is walked four ways: both
 * GPU layouts (pairs, quads), each with the one-loop walk (the default on GPUs) and the nested one
 * (the default on CPU devices such as lavapipe), so that every default is checked on every device;
 * the shared scenes take the two defaults (pairs with one loop on GPUs, quads nested on CPU
 * devices: src/render/tuning.c) alone.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "../glsl/shared.h"
#include "gpu_fixture.h"
#include "render/renderer.h"
#include "render/tuning.h"
#include "render/trace_api.h"
#include "scene/scene.h"
#include "one_mesh.h"

enum { RAYS_PER_KIND = 1024, RAY_KINDS = 3, RAY_COUNT = RAYS_PER_KIND * RAY_KINDS };

static uint32_t rng_state = 1;
static float uniform(void)
{
    rng_state = rng_state * 1664525u + 1013904223u;
    return (rng_state >> 8) / 16777216.0f;
}

static Ray make_ray(const float o[3], const float d[3], float tmax)
{
    float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    return (Ray){.origin = {o[0], o[1], o[2], 0},
                 .direction = {d[0] / len, d[1] / len, d[2] / len, tmax},
                 .importance = {1, 1, 1, 0}};
}

/* Camera-like rays from a sphere around the bounds towards points inside them; random rays from
 * inside; rays along +-x, +-y, +-z from inside (direction components exactly 0). */
static void make_rays(const vkrt_mesh *mesh, Ray *rays)
{
    const float *lo = mesh->bounds_min, *hi = mesh->bounds_max;
    float centre[3], extent = 0;
    for (int k = 0; k < 3; ++k) {
        centre[k] = 0.5f * (lo[k] + hi[k]);
        extent = fmaxf(extent, hi[k] - lo[k]);
    }
    rng_state = 12345;
    for (int i = 0; i < RAYS_PER_KIND; ++i) {
        float o[3], target[3], d[3];
        float a = 6.2831853f * uniform(), b = acosf(1 - 2 * uniform());
        float dir_out[3] = {sinf(b) * cosf(a), cosf(b), sinf(b) * sinf(a)};
        for (int k = 0; k < 3; ++k) {
            o[k] = centre[k] + 1.5f * extent * dir_out[k];
            target[k] = lo[k] + (hi[k] - lo[k]) * uniform();
            d[k] = target[k] - o[k];
        }
        rays[i] = make_ray(o, d, 3.4e38f);
        for (int k = 0; k < 3; ++k) {
            o[k] = lo[k] + (hi[k] - lo[k]) * uniform();
            d[k] = uniform() - 0.5f;
        }
        rays[RAYS_PER_KIND + i] = make_ray(o, d, 3.4e38f);
        for (int k = 0; k < 3; ++k) {
            o[k] = lo[k] + (hi[k] - lo[k]) * uniform();
            d[k] = 0;
        }
        d[i % 3] = (i / 3) % 2 ? -1.0f : 1.0f;
        rays[2 * RAYS_PER_KIND + i] = make_ray(o, d, 3.4e38f);
    }
}

/* A structure and the way the kernels walk it. */
typedef struct tracer {
    const char *name;
    vkrt_accel_kind kind;
    uint32_t bvh_width; /* 0: the default */
    vkrt_walk walk;     /* VKRT_WALK_DEFAULT: the device's default */
    vkrt_bvh_splits splits; /* auto (0): the renderer's choice */
    bool variant; /* a walk that is no device's default: checked on the generated scenes only */
} tracer;

/* Brute force first: the reference the others are held to. */
static const tracer tracers[] = {
    {"brute", VKRT_ACCEL_BRUTE, 0, VKRT_WALK_DEFAULT},
    {"grid", VKRT_ACCEL_GRID, 0, VKRT_WALK_DEFAULT},
    {"bvh pairs, one loop", VKRT_ACCEL_BVH, 2, VKRT_WALK_ONE_LOOP},
    {"bvh pairs, nested", VKRT_ACCEL_BVH, 2, VKRT_WALK_NESTED, .variant = true},
    {"bvh quads, one loop", VKRT_ACCEL_BVH, 4, VKRT_WALK_ONE_LOOP, .variant = true},
    {"bvh quads, nested", VKRT_ACCEL_BVH, 4, VKRT_WALK_NESTED},
    {"kdtree", VKRT_ACCEL_KDTREE, 0, VKRT_WALK_DEFAULT},
    {"bvh pairs, spatial splits", VKRT_ACCEL_BVH, 2, VKRT_WALK_DEFAULT, VKRT_BVH_SPLITS_ON},
};
enum { TRACERS = sizeof tracers / sizeof *tracers };
static const tracer *const brute = &tracers[0];

/* A renderer that traces up to count rays a call with the structure and walk of t. Renderer
 * creation (lavapipe compiling the kernels) costs more than tracing thousands of rays, so one
 * renderer traces both a scene's rays and its segments. */
static vkrt_renderer *renderer_as(gpu_context *ctx, const vkrt_scene *scene, const tracer *t,
                                  uint32_t count)
{
    vkrt_error err = {{0}};
    vkrt_renderer *r = NULL;
    vkrt_render_desc desc = {.width = count, .height = 1, .accel = t->kind,
                             .bvh_splits = t->splits,
                             .tuning = {.bvh_width = t->bvh_width, .walk = t->walk}};
    if (!vkrt_renderer_create(&r, ctx, scene, &desc, &err))
        fail_msg("renderer (%s): %s", t->name, err.msg);
    return r;
}

static void trace_with(vkrt_renderer *r, const tracer *t, const Ray *rays, uint32_t count,
                       bool any_hit, Hit *hits)
{
    vkrt_error err = {{0}};
    if (!vkrt_renderer_trace(r, rays, count, any_hit, hits, 1, NULL, &err))
        fail_msg("trace (%s): %s", t->name, err.msg);
}

static void trace_as(gpu_context *ctx, const vkrt_scene *scene, const tracer *t, const Ray *rays,
                     uint32_t count, bool any_hit, Hit *hits, vkrt_accel_kind *built)
{
    vkrt_renderer *r = renderer_as(ctx, scene, t, count);
    trace_with(r, t, rays, count, any_hit, hits);
    if (built)
        *built = vkrt_renderer_accel_stats(r)->kind;
    vkrt_renderer_destroy(r);
}

/* Hits of kind must equal brute force's: same hit or miss, same t, same triangle unless tied. */
static void compare_hits(const char *name, const char *kind, const Hit *ref, const Hit *hits,
                         uint32_t count)
{
    uint32_t wrong = 0, ties = 0;
    for (uint32_t i = 0; i < count; ++i) {
        bool ref_hit = ref[i].triangle != VKRT_NO_HIT, hit = hits[i].triangle != VKRT_NO_HIT;
        bool same = ref_hit == hit;
        if (same && ref_hit && ref[i].triangle != hits[i].triangle) {
            /* Another triangle at the same distance: a tie, unless t differs. */
            same = fabsf(ref[i].t - hits[i].t) <= 1e-6f * fmaxf(1.0f, fabsf(ref[i].t));
            ties += same;
        } else if (same && ref_hit) {
            same = ref[i].t == hits[i].t;
        }
        if (!same) {
            if (wrong < 5)
                print_message("%s %s ray %u: brute %u t=%.9g, %s %u t=%.9g\n", name, kind, i,
                              ref[i].triangle, ref[i].t, kind, hits[i].triangle, hits[i].t);
            ++wrong;
        }
    }
    print_message("%s: %s agrees with brute force on %u of %u rays (%u ties)\n", name, kind,
                  count - wrong, count, ties);
    if (wrong)
        fail_msg("%s: %s differs from brute force on %u rays", name, kind, wrong);
}

static void compare_any(const char *name, const char *kind, const Hit *ref, const Hit *hits,
                        uint32_t count)
{
    uint32_t wrong = 0;
    for (uint32_t i = 0; i < count; ++i)
        wrong += (ref[i].triangle != VKRT_NO_HIT) != (hits[i].triangle != VKRT_NO_HIT);
    if (wrong)
        fail_msg("%s: %s any-hit differs from brute force on %u of %u rays", name, kind, wrong,
                 count);
}

/* Shadow-like segments: from each ray's origin to half its brute-force hit distance (clear) and
 * to twice it (blocked), exercising tmax. */
static uint32_t make_segments(const Ray *rays, const Hit *ref, uint32_t count, Ray *segments)
{
    uint32_t n = 0;
    for (uint32_t i = 0; i < count && n + 2 <= count; ++i) {
        if (ref[i].triangle == VKRT_NO_HIT)
            continue;
        segments[n] = rays[i];
        segments[n++].direction.w = 0.5f * ref[i].t;
        segments[n] = rays[i];
        segments[n++].direction.w = 2.0f * ref[i].t;
    }
    return n;
}

/* every_walk: also the walks no device takes by default (tracer.variant). */
static void check_scene_mesh(const char *name, vkrt_scene *scene, bool every_walk)
{
    gpu_context ctx;
    fixture_context_create(&ctx);
    Ray *rays = calloc(RAY_COUNT, sizeof *rays), *segments = calloc(RAY_COUNT, sizeof *segments);
    Hit *ref = calloc(RAY_COUNT, sizeof *ref), *hits = calloc(RAY_COUNT, sizeof *hits);
    Hit *ref_any = calloc(RAY_COUNT, sizeof *ref_any);
    assert_true(rays && segments && ref && hits && ref_any);
    make_rays(&scene->model.meshes[0], rays);
    vkrt_renderer *r = renderer_as(&ctx, scene, brute, RAY_COUNT);
    trace_with(r, brute, rays, RAY_COUNT, false, ref);
    uint32_t n = make_segments(rays, ref, RAY_COUNT, segments);
    if (n)
        trace_with(r, brute, segments, n, true, ref_any);
    vkrt_renderer_destroy(r);
    for (int k = 1; k < TRACERS; ++k) {
        const tracer *t = &tracers[k];
        if (t->variant && !every_walk)
            continue;
        r = renderer_as(&ctx, scene, t, RAY_COUNT);
        trace_with(r, t, rays, RAY_COUNT, false, hits);
        compare_hits(name, t->name, ref, hits, RAY_COUNT);
        if (n) {
            trace_with(r, t, segments, n, true, hits);
            compare_any(name, t->name, ref_any, hits, n);
        }
        vkrt_renderer_destroy(r);
    }
    free(rays);
    free(segments);
    free(ref);
    free(hits);
    free(ref_any);
    fixture_context_destroy(&ctx);
}

static void check_obj(const char *path)
{
    vkrt_scene scene = {0};
    vkrt_error err = {{0}};
    if (!vkrt_obj_load(path, &scene.model, &err))
        fail_msg("%s", err.msg);
    /* The shared scenes take each device's default walk (pairs one loop, quads nested): lavapipe
     * compiling two more renderers a scene was a minute of CI, and the generated scenes hold
     * every walk to brute force. */
    check_scene_mesh(path, &scene, false);
    vkrt_model_free(&scene.model);
}

static void test_shared_scenes(void **state)
{
    (void)state;
    const char *dir = getenv("VKRT_SCENES_DIR");
    static const char *const objs[] = {
        "cornell-box/CornellBox-Original.obj", "cornell-box/CornellBox-Sphere.obj",
        "stanford-bunny/stanford-bunny.obj",   "utah-teapot/teapot.obj",
        "stanford-armadillo/armadillo.obj",    "mori-knob/testObj.obj",
        "dabrovic-sponza/sponza.obj",          "sibenik-cathedral/sibenik.obj",
        "lost-empire/lost_empire.obj",
    };
    char path[4096];
    if (!dir || access(dir, R_OK) != 0) {
        print_message("skipped: VKRT_SCENES_DIR (../shared/scenes) is not there\n");
        skip();
    }
    /* tools/check-sanitizers sets this: the sanitizers watch the host code, which the scenes
     * above exercise as the shared ones do, and lavapipe's brute force over the shared scenes
     * takes minutes that the plain test run has already spent. */
    const char *quick = getenv("VKRT_SKIP_SHARED_SCENES");
    if (quick && *quick && strcmp(quick, "0") != 0) {
        print_message("skipped: VKRT_SKIP_SHARED_SCENES is set\n");
        skip();
    }
    for (size_t i = 0; i < sizeof objs / sizeof *objs; ++i) {
        snprintf(path, sizeof path, "%s/%s", dir, objs[i]);
        if (access(path, R_OK) != 0) {
            print_message("skipped %s: not found\n", path);
            continue;
        }
        check_obj(path);
    }
}

/* The teapot in a stadium (tools/teapot_stadium.py): all structures agree, and auto never picks
 * the grid, which puts the dense object into a few crowded cells: the kd-tree on a CPU device
 * reading texel buffers (lavapipe's default), the BVH elsewhere (src/accel/choose.c). */
static void test_teapot_in_stadium(void **state)
{
    (void)state;
    const char *cfg = getenv("VKRT_STADIUM_CFG");
    if (!cfg || access(cfg, R_OK) != 0)
        fail_msg("VKRT_STADIUM_CFG (the generated stadium scene) is missing");
    vkrt_scene scene;
    vkrt_error err = {{0}};
    if (!vkrt_scene_load(cfg, &scene, &err))
        fail_msg("%s", err.msg);
    check_scene_mesh("teapot-in-stadium", &scene, true);
    gpu_context ctx;
    fixture_context_create(&ctx);
    Ray ray = make_ray((float[]){0, 0, 5}, (float[]){0, 0, -1}, 3.4e38f);
    Hit hit;
    vkrt_accel_kind built;
    const tracer automatic = {"auto", VKRT_ACCEL_AUTO, 0, VKRT_WALK_DEFAULT};
    trace_as(&ctx, &scene, &automatic, &ray, 1, false, &hit, &built);
    vkrt_tuning tuning = vkrt_tuning_for(&ctx, NULL);
    fixture_context_destroy(&ctx);
    assert_int_equal(built, tuning.kdtree_competes ? VKRT_ACCEL_KDTREE : VKRT_ACCEL_BVH);
    vkrt_scene_free(&scene);
}

/* An icosphere of radius 1 subdivided `levels` times: a closed mesh with shared edges. */
static void icosphere(vkrt_mesh *mesh, int levels)
{
    const float t = (1.0f + sqrtf(5.0f)) / 2.0f;
    float base[12][3] = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                         {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    static const int faces[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                     {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                     {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                     {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
    uint32_t count = 20;
    for (int l = 0; l < levels; ++l)
        count *= 4;
    float *tris = calloc((size_t)count * 9, sizeof *tris);
    assert_non_null(tris);
    for (int f = 0; f < 20; ++f)
        for (int c = 0; c < 3; ++c)
            for (int k = 0; k < 3; ++k)
                tris[9 * f + 3 * c + k] = base[faces[f][c]][k];
    uint32_t n = 20;
    float *next = calloc((size_t)count * 9, sizeof *next);
    for (int l = 0; l < levels; ++l) {
        for (uint32_t f = 0; f < n; ++f) {
            float *v = tris + 9 * f, m[3][3];
            for (int e = 0; e < 3; ++e)
                for (int k = 0; k < 3; ++k)
                    m[e][k] = 0.5f * (v[3 * e + k] + v[3 * ((e + 1) % 3) + k]);
            const float *quad[4][3] = {{v, m[0], m[2]}, {m[0], v + 3, m[1]},
                                       {m[2], m[1], v + 6}, {m[0], m[1], m[2]}};
            for (int q = 0; q < 4; ++q)
                for (int c = 0; c < 3; ++c)
                    memcpy(next + 9 * (4 * f + q) + 3 * c, quad[q][c], 3 * sizeof(float));
        }
        n *= 4;
        float *swap = tris;
        tris = next;
        next = swap;
    }
    free(next);
    /* Project every vertex to the unit sphere; shared vertices project identically. */
    for (uint32_t i = 0; i < n * 3; ++i) {
        float *p = tris + 3 * i, len = sqrtf(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        p[0] /= len, p[1] /= len, p[2] /= len;
    }
    memset(mesh, 0, sizeof *mesh);
    mesh->triangle_count = n;
    mesh->positions = tris;
    mesh->material = calloc(n, sizeof *mesh->material);
    for (uint32_t i = 0; i < n; ++i)
        mesh->material[i] = -1;
    for (int k = 0; k < 3; ++k) {
        mesh->bounds_min[k] = -1;
        mesh->bounds_max[k] = 1;
    }
}

/* Rays aimed exactly at the vertices and edge midpoints of a closed mesh all hit it, no farther
 * than their target: a non-watertight test lets some slip through the cracks. */
static void check_watertight(const char *name, vkrt_scene *scene, bool from_inside)
{
    const vkrt_mesh *mesh = &scene->model.meshes[0];
    uint32_t count = mesh->triangle_count < RAY_COUNT / 2 ? mesh->triangle_count : RAY_COUNT / 2;
    Ray *rays = calloc(2 * count, sizeof *rays);
    Hit *hits = calloc(2 * count, sizeof *hits);
    float centre[3];
    for (int k = 0; k < 3; ++k)
        centre[k] = 0.5f * (mesh->bounds_min[k] + mesh->bounds_max[k]);
    float extent = fmaxf(mesh->bounds_max[0] - mesh->bounds_min[0],
                         fmaxf(mesh->bounds_max[1] - mesh->bounds_min[1],
                               mesh->bounds_max[2] - mesh->bounds_min[2]));
    uint32_t stride = mesh->triangle_count / count;
    for (uint32_t i = 0; i < count; ++i) {
        const float *v = mesh->positions + 9 * (size_t)(i * stride);
        float targets[2][3];
        for (int k = 0; k < 3; ++k) {
            targets[0][k] = v[k];                      /* a vertex */
            targets[1][k] = 0.5f * (v[k] + v[3 + k]);  /* an edge's midpoint */
        }
        for (int j = 0; j < 2; ++j) {
            float o[3], d[3];
            for (int k = 0; k < 3; ++k) {
                d[k] = targets[j][k] - centre[k];
                /* Outside: start beyond the target, looking back at it, from a slanted spot. */
                o[k] = from_inside ? centre[k] : targets[j][k] + 2 * extent * d[k] + (k == 1 ? 0.1f * extent : 0);
            }
            for (int k = 0; k < 3; ++k)
                d[k] = targets[j][k] - o[k];
            float dist = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            rays[2 * i + j] = make_ray(o, d, 3.4e38f);
            rays[2 * i + j].importance.w = dist; /* remembered for the check below */
        }
    }
    /* A target (an edge's midpoint above all) is rounded to the coordinates' float grid, so a ray
     * may pass beside the edge and meet the neighbouring triangle a few steps of that grid
     * farther: about 2e-3 for the sphere far from the origin, 5e-7 for the one around it. */
    float coords = 0;
    for (int k = 0; k < 3; ++k)
        coords = fmaxf(coords, fmaxf(fabsf(mesh->bounds_min[k]), fabsf(mesh->bounds_max[k])));
    float slack = 1e-6f + 4 * (nextafterf(coords, INFINITY) - coords);
    gpu_context ctx;
    fixture_context_create(&ctx);
    for (int k = 0; k < TRACERS; ++k) {
        const tracer *t = &tracers[k];
        trace_as(&ctx, scene, t, rays, 2 * count, false, hits, NULL);
        uint32_t leaks = 0;
        for (uint32_t i = 0; i < 2 * count; ++i) {
            float dist = rays[i].importance.w;
            if (hits[i].triangle == VKRT_NO_HIT || hits[i].t > dist * (1 + 1e-5f) + slack) {
                if (leaks < 3)
                    print_message("%s %s: ray %u at a %s leaked (t %g, target at %g)\n", name,
                                  t->name, i, i % 2 ? "edge" : "vertex", hits[i].t, dist);
                ++leaks;
            }
        }
        print_message("%s %s: %u of %u rays at vertices and edges leaked\n", name, t->name,
                      leaks, 2 * count);
        assert_int_equal(leaks, 0);
    }
    fixture_context_destroy(&ctx);
    free(rays);
    free(hits);
}

static void test_icosphere_watertight(void **state)
{
    (void)state;
    vkrt_scene scene = {0};
    vkrt_mesh sphere;
    icosphere(&sphere, 4);
    one_mesh_model(&scene.model, sphere);
    check_watertight("icosphere (inside)", &scene, true);
    check_watertight("icosphere (outside)", &scene, false);
    /* The same sphere thousands of radii from the origin: a ray's distances to the boxes' planes
     * are then small beside origin * inverse direction, the product the slab tests round once per
     * ray (glsl/lib/traverse_bvh.glsl, SlabRay), so a margin too small for its error lets rays
     * through the boxes' edges and corners, where the triangles' vertices lie. The offsets are
     * exact in float, and shared vertices stay shared. */
    const float offset[3] = {4096.5f, -3000.25f, 2048.125f};
    for (uint32_t i = 0; i < 3 * scene.model.meshes[0].triangle_count; ++i)
        for (int k = 0; k < 3; ++k)
            scene.model.meshes[0].positions[3 * i + k] += offset[k];
    for (int k = 0; k < 3; ++k) {
        scene.model.meshes[0].bounds_min[k] += offset[k];
        scene.model.meshes[0].bounds_max[k] += offset[k];
    }
    vkrt_error err = {{0}};
    assert_true(vkrt_model_finish(&scene.model, &err));
    check_watertight("icosphere far from the origin (inside)", &scene, true);
    check_watertight("icosphere far from the origin (outside)", &scene, false);
    vkrt_model_free(&scene.model);
}

/* A triangle corner or an edge, keyed by exact float positions so shared ones compare equal. */
typedef struct corner {
    float p[3];
    uint32_t triangle;
} corner;

static int compare_positions(const float *a, const float *b)
{
    for (int k = 0; k < 3; ++k)
        if (a[k] != b[k])
            return a[k] < b[k] ? -1 : 1;
    return 0;
}

static int compare_corners(const void *a, const void *b)
{
    return compare_positions(((const corner *)a)->p, ((const corner *)b)->p);
}

static void face_normal(const float *v, float n[3])
{
    float e1[3], e2[3];
    for (int k = 0; k < 3; ++k) {
        e1[k] = v[3 + k] - v[k];
        e2[k] = v[6 + k] - v[k];
    }
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    float len = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int k = 0; k < 3; ++k)
        n[k] = len > 0 ? n[k] / len : 0;
}

/* True if the triangles around a vertex close into a fan: every neighbouring vertex is shared by
 * exactly two of them. Vertices on a hole's rim (the bunny's base is open) are not closed, and a
 * ray at them may rightly pass. */
static bool closed_fan(const vkrt_mesh *mesh, const corner *fan, uint32_t count)
{
    enum { MAX_FAN = 32 };
    if (count > MAX_FAN)
        return false;
    float neighbours[2 * MAX_FAN][3];
    uint32_t n = 0;
    for (uint32_t q = 0; q < count; ++q) {
        const float *v = mesh->positions + 9 * (size_t)fan[q].triangle;
        for (int corner_index = 0; corner_index < 3; ++corner_index)
            if (compare_positions(v + 3 * corner_index, fan[q].p) != 0)
                memcpy(neighbours[n++], v + 3 * corner_index, sizeof neighbours[0]);
    }
    for (uint32_t a = 0; a < n; ++a) {
        uint32_t same = 0;
        for (uint32_t b = 0; b < n; ++b)
            same += compare_positions(neighbours[a], neighbours[b]) == 0;
        if (same != 2)
            return false;
    }
    return true;
}

/* Rays at the vertices of an open, bumpy mesh (the bunny has holes): each ray comes down the
 * vertex's mean normal onto it, from a short distance, and only vertices whose incident triangles
 * all face that ray are used (there the surface around the vertex covers it as seen by the ray,
 * so a hit is owed). A cracked test lets rays slip between the triangles around the vertex. */
static void test_bunny_watertight(void **state)
{
    (void)state;
    const char *dir = getenv("VKRT_SCENES_DIR");
    char path[4096];
    snprintf(path, sizeof path, "%s/stanford-bunny/stanford-bunny.obj", dir ? dir : "");
    if (!dir || access(path, R_OK) != 0) {
        print_message("skipped: %s is not there\n", path);
        skip();
    }
    vkrt_scene scene = {0};
    vkrt_error err = {{0}};
    if (!vkrt_obj_load(path, &scene.model, &err))
        fail_msg("%s", err.msg);
    const vkrt_mesh *mesh = &scene.model.meshes[0];
    uint32_t corners = 3 * mesh->triangle_count;
    corner *c = calloc(corners, sizeof *c);
    Ray *rays = calloc(RAY_COUNT, sizeof *rays);
    Hit *hits = calloc(RAY_COUNT, sizeof *hits);
    assert_true(c && rays && hits);
    for (uint32_t i = 0; i < corners; ++i) {
        memcpy(c[i].p, mesh->positions + 3 * (size_t)i, sizeof c[i].p);
        c[i].triangle = i / 3;
    }
    qsort(c, corners, sizeof *c, compare_corners);
    float extent = mesh->bounds_max[1] - mesh->bounds_min[1];
    uint32_t count = 0, vertices = 0;
    for (uint32_t i = 0; i < corners && count < RAY_COUNT;) {
        uint32_t j = i;
        float mean[3] = {0, 0, 0};
        while (j < corners && compare_positions(c[j].p, c[i].p) == 0) {
            float n[3];
            face_normal(mesh->positions + 9 * (size_t)c[j].triangle, n);
            for (int k = 0; k < 3; ++k)
                mean[k] += n[k];
            ++j;
        }
        ++vertices;
        float len = sqrtf(mean[0] * mean[0] + mean[1] * mean[1] + mean[2] * mean[2]);
        bool usable = len > 0 && j - i >= 3 && vertices % 7 == 0; /* every 7th vertex */
        for (uint32_t q = i; usable && q < j; ++q) {
            float n[3];
            face_normal(mesh->positions + 9 * (size_t)c[q].triangle, n);
            usable = n[0] * mean[0] + n[1] * mean[1] + n[2] * mean[2] > 0.2f * len;
        }
        usable = usable && closed_fan(mesh, c + i, j - i);
        if (usable) {
            float o[3], d[3], back = 1e-3f * extent;
            for (int k = 0; k < 3; ++k) {
                o[k] = c[i].p[k] + back * mean[k] / len;
                d[k] = c[i].p[k] - o[k];
            }
            rays[count] = make_ray(o, d, 3.4e38f);
            rays[count++].importance.w = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        }
        i = j;
    }
    gpu_context ctx;
    fixture_context_create(&ctx);
    for (int k = 0; k < TRACERS; ++k) {
        const tracer *t = &tracers[k];
        trace_as(&ctx, &scene, t, rays, count, false, hits, NULL);
        uint32_t leaks = 0;
        for (uint32_t i = 0; i < count; ++i)
            if (hits[i].triangle == VKRT_NO_HIT ||
                hits[i].t > rays[i].importance.w * (1 + 1e-3f)) {
                if (leaks < 3)
                    print_message("bunny %s: ray %u at (%.9g %.9g %.9g) dir (%.9g %.9g %.9g): hit "
                                  "%u at t %g, vertex at %g\n",
                                  t->name, i, rays[i].origin.x, rays[i].origin.y,
                                  rays[i].origin.z, rays[i].direction.x, rays[i].direction.y,
                                  rays[i].direction.z, hits[i].triangle, hits[i].t,
                                  rays[i].importance.w);
                ++leaks;
            }
        print_message("bunny %s: %u of %u rays onto vertices leaked\n", t->name, leaks, count);
        assert_int_equal(leaks, 0);
    }
    fixture_context_destroy(&ctx);
    free(c);
    free(rays);
    free(hits);
    vkrt_model_free(&scene.model);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_icosphere_watertight),
        cmocka_unit_test(test_bunny_watertight),
        cmocka_unit_test(test_teapot_in_stadium),
        cmocka_unit_test(test_shared_scenes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
