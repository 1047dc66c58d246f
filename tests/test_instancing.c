/*
 * test_instancing.c: the two-level BVH (src/render/accel_instanced.h) against the same scene
 * flattened into world-space triangles (vkrt_model_world).
 *
 * The scene: one OBJ mesh (a sphere of two materials, with smooth normals and texture
 * coordinates, big enough for a tree of several levels) placed six times: a translation, two rotations, a non-uniform scale, a mirror
 * (negative determinant), a shear, and a flat non-uniform scale as the ground. Rays traced
 * through the two-level BVH (both GPU layouts) must find what a CPU brute force over the
 * flattened triangles finds (closest and any hit); a Whitted render through it must match the
 * flattened render pixel for pixel within float noise, and the two renders must cover the same
 * pixels, with and without a texture that cuts one material out. A scene of one identity
 * instance must keep the flat structure. Two meshes of swapped materials, instanced in turn, must
 * each show its own materials where primary rays hit it.
 * With VKRT_TEST_DUMP=DIR the two renders are written there as PPM images for a look.
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
#include "render/trace_api.h"
#include "output/image_write.h"
#include "scene/scene.h"
#include "scene_dir.h"

enum { W = 96, H = 72, RAYS = 2048 };

/* A sphere of 12 x 10 quads (216 triangles, enough that its tree has inner nodes of every
 * width: a mesh of one leaf would hide a wrong node link), the upper half of material a, the lower
 * of b, with its smooth normals and texture coordinates. */
static void write_scene(void)
{
    enum { SLICES = 12, STACKS = 10 };
    static char obj[64 * 1024];
    int at = snprintf(obj, sizeof obj, "mtllib scene.mtl\n");
    for (int j = 0; j <= STACKS; ++j)
        for (int i = 0; i <= SLICES; ++i) {
            double th = 3.14159265358979 * j / STACKS, ph = 2 * 3.14159265358979 * i / SLICES;
            double x = sin(th) * cos(ph), y = cos(th), z = sin(th) * sin(ph);
            at += snprintf(obj + at, sizeof obj - at, "v %.6f %.6f %.6f\nvn %.6f %.6f %.6f\nvt %.4f %.4f\n",
                           x, y, z, x, y, z, (double)i / SLICES, (double)j / STACKS);
        }
    for (int j = 0; j < STACKS; ++j) {
        at += snprintf(obj + at, sizeof obj - at, "usemtl %s\n", j < STACKS / 2 ? "a" : "b");
        for (int i = 0; i < SLICES; ++i) {
            int v = j * (SLICES + 1) + i + 1, w = v + SLICES + 1;
            /* Counter-clockwise seen from outside; the poles' slivers of zero area are kept. */
            if (j > 0)
                at += snprintf(obj + at, sizeof obj - at, "f %d/%d/%d %d/%d/%d %d/%d/%d\n", v, v,
                               v, v + 1, v + 1, v + 1, w, w, w);
            if (j < STACKS - 1)
                at += snprintf(obj + at, sizeof obj - at, "f %d/%d/%d %d/%d/%d %d/%d/%d\n", v + 1,
                               v + 1, v + 1, w + 1, w + 1, w + 1, w, w, w);
        }
    }
    assert_true(at < (int)sizeof obj);
    scene_dir_write("scene.obj", obj);
    scene_dir_write("scene.mtl", "newmtl a\nKd 0.8 0.3 0.2\nnewmtl b\nKd 0.2 0.6 0.8\n");
    scene_dir_write("scene.cfg",
                    "geometry scene.obj\nmax-depth 1\nenvironment 0.05 0.05 0.1\n"
                    "light ambient 0.05 0.05 0.05\nlight point 3 6 4 60 60 60\n"
                    "camera eye 0 4 9 look 0 0 0 up 0 1 0 fov 50\n");
}

/* Row-major 3x4 transforms. */
static void compose(const float a[12], const float b[12], float out[12])
{
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c)
            out[4 * r + c] = a[4 * r] * b[c] + a[4 * r + 1] * b[4 + c] + a[4 * r + 2] * b[8 + c] +
                             (c == 3 ? a[4 * r + 3] : 0.0f);
}

static void rotation(int axis, float degrees, float out[12])
{
    float c = cosf(degrees * 3.14159265f / 180), s = sinf(degrees * 3.14159265f / 180);
    int a = (axis + 1) % 3, b = (axis + 2) % 3;
    memset(out, 0, 12 * sizeof *out);
    out[4 * axis + axis] = 1;
    out[4 * a + a] = c;
    out[4 * a + b] = -s;
    out[4 * b + a] = s;
    out[4 * b + b] = c;
}

static void place(vkrt_instance *inst, const float linear[12], float x, float y, float z)
{
    inst->mesh = 0;
    memcpy(inst->transform, linear, sizeof inst->transform);
    inst->transform[3] = x;
    inst->transform[7] = y;
    inst->transform[11] = z;
}

/* The loaded scene's one instance replaced by the six placements, its materials resolved again
 * (they are per triangle over all instances). */
static void instance_scene(vkrt_scene *scene)
{
    enum { N = 6 };
    vkrt_instance *inst = calloc(N, sizeof *inst);
    assert_non_null(inst);
    const float identity[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    float ry[12], rx[12], rot[12], stretch[12] = {0.5f, 0, 0, 0, 0, 1.5f, 0, 0, 0, 0, 0.8f, 0};
    float mirror[12] = {-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0}, mirrored[12];
    float shear[12] = {1, 0.6f, 0, 0, 0, 1, 0, 0, 0, 0.3f, 1, 0};
    float ground[12] = {6, 0, 0, 0, 0, 0.05f, 0, 0, 0, 0, 6, 0};
    rotation(1, 30, ry);
    rotation(0, 20, rx);
    compose(ry, rx, rot);
    compose(mirror, rot, mirrored);
    place(&inst[0], identity, -2.2f, 0, 0);
    place(&inst[1], rot, 2.2f, 0.2f, 0);
    place(&inst[2], stretch, 0, 0.4f, -2.2f);
    place(&inst[3], mirrored, 0, 0.1f, 2.0f);
    place(&inst[4], shear, 2.0f, 0.5f, -2.5f);
    place(&inst[5], ground, 0, -1.6f, 0);
    free(scene->model.instances);
    scene->model.instances = inst;
    scene->model.instance_count = N;
    vkrt_error err = {{0}};
    if (!vkrt_model_finish(&scene->model, &err))
        fail_msg("%s", err.msg);
    vkrt_scene_materials_free(&scene->materials);
    if (!vkrt_scene_materials_resolve(&scene->config, &scene->model, NULL, &scene->materials,
                                      &err))
        fail_msg("%s", err.msg);
}

/* Material a cut out by a map_d of vertical stripes (left half kept, right half cut): the
 * coverage is 0 or 1 but in the texels' bilinear seams, where the stochastic test decides. */
static void write_cutout(void)
{
    enum { S = 32 };
    uint8_t rgb[S * S * 3];
    for (int i = 0; i < S * S; ++i)
        memset(rgb + 3 * i, (i % S) < S / 2 ? 255 : 0, 3);
    char path[256];
    snprintf(path, sizeof path, "%s/stripes.png", scene_dir);
    vkrt_error err = {{0}};
    if (!vkrt_image_write_png8(path, S, S, rgb, &err))
        fail_msg("%s", err.msg);
    scene_dir_write("scene.mtl", "newmtl a\nKd 0.8 0.3 0.2\nmap_d stripes.png\n"
                                 "newmtl b\nKd 0.2 0.6 0.8\n");
}

/* The scene written in scene_dir, loaded as the file says (one identity instance). */
static void load_written(vkrt_scene *scene)
{
    char path[256];
    snprintf(path, sizeof path, "%s/scene.cfg", scene_dir);
    vkrt_error err = {{0}};
    if (!vkrt_scene_load(path, scene, &err))
        fail_msg("%s", err.msg);
}

static void load_instanced(vkrt_scene *scene, bool cutout)
{
    write_scene();
    if (cutout)
        write_cutout();
    load_written(scene);
    instance_scene(scene);
}

/* ------------------------------------------------------------------------ trace */

/* Moller and Trumbore in double: the reference's own test. */
static bool intersect(const double o[3], const double d[3], const float *tri, double tmax,
                      double *t)
{
    double e1[3], e2[3], s[3], p[3], q[3];
    for (int k = 0; k < 3; ++k) {
        e1[k] = (double)tri[3 + k] - tri[k];
        e2[k] = (double)tri[6 + k] - tri[k];
        s[k] = o[k] - tri[k];
    }
    p[0] = d[1] * e2[2] - d[2] * e2[1];
    p[1] = d[2] * e2[0] - d[0] * e2[2];
    p[2] = d[0] * e2[1] - d[1] * e2[0];
    double det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
    if (det == 0)
        return false;
    double u = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) / det;
    q[0] = s[1] * e1[2] - s[2] * e1[1];
    q[1] = s[2] * e1[0] - s[0] * e1[2];
    q[2] = s[0] * e1[1] - s[1] * e1[0];
    double v = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) / det;
    double h = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) / det;
    if (u < 0 || v < 0 || u + v > 1 || !(h > 0 && h < tmax))
        return false;
    *t = h;
    return true;
}

static uint32_t rng_state = 7;
static float uniform(void)
{
    rng_state = rng_state * 1664525u + 1013904223u;
    return (rng_state >> 8) / 16777216.0f;
}

/* Rays from a sphere around the scene towards points in it, and from points inside in random
 * directions. */
static void make_rays(const vkrt_model *model, Ray *rays)
{
    const float *lo = model->bounds_min, *hi = model->bounds_max;
    for (int i = 0; i < RAYS; ++i) {
        float o[3], d[3];
        bool outside = i % 2 == 0;
        float a = 6.2831853f * uniform(), b = acosf(1 - 2 * uniform());
        float dir_out[3] = {sinf(b) * cosf(a), cosf(b), sinf(b) * sinf(a)};
        for (int k = 0; k < 3; ++k) {
            float c = 0.5f * (lo[k] + hi[k]), target = lo[k] + (hi[k] - lo[k]) * uniform();
            o[k] = outside ? c + 14 * dir_out[k] : lo[k] + (hi[k] - lo[k]) * uniform();
            d[k] = outside ? target - o[k] : uniform() - 0.5f;
        }
        float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        rays[i] = (Ray){.origin = {o[0], o[1], o[2], 0},
                        .direction = {d[0] / len, d[1] / len, d[2] / len, 3.4e38f},
                        .importance = {1, 1, 1, 0}};
    }
}

/* The closest hit over the flattened triangles: index and t, or -1. */
static int64_t reference_hit(const vkrt_mesh *world, const Ray *ray, double tmax, double *t_out)
{
    double o[3] = {ray->origin.x, ray->origin.y, ray->origin.z};
    double d[3] = {ray->direction.x, ray->direction.y, ray->direction.z};
    int64_t best = -1;
    double best_t = tmax;
    for (uint32_t i = 0; i < world->triangle_count; ++i) {
        double t;
        if (intersect(o, d, world->positions + 9 * (size_t)i, best_t, &t)) {
            best = i;
            best_t = t;
        }
    }
    *t_out = best_t;
    return best;
}

static void trace(gpu_context *ctx, const vkrt_scene *scene, uint32_t width, const Ray *rays,
                  bool any_hit, Hit *hits)
{
    vkrt_error err = {{0}};
    vkrt_renderer *r = NULL;
    vkrt_render_desc desc = {.width = RAYS, .height = 1, .accel = VKRT_ACCEL_BVH,
                             .instancing = VKRT_INSTANCING_TWO_LEVEL,
                             .tuning = {.bvh_width = width}};
    if (!vkrt_renderer_create(&r, ctx, scene, &desc, &err))
        fail_msg("renderer: %s", err.msg);
    const vkrt_accel_stats *s = vkrt_renderer_accel_stats(r);
    assert_true(s->two_level);
    assert_int_equal(s->instances, 6);
    assert_int_equal(s->triangles, 216);
    assert_int_equal(s->instanced_triangles, 6 * 216);
    if (!vkrt_renderer_trace(r, rays, RAYS, any_hit, hits, 1, NULL, &err))
        fail_msg("trace: %s", err.msg);
    vkrt_renderer_destroy(r);
}

/* Closest hits of the two-level BVH against the brute force over the flattened triangles: the
 * same triangle and t within float noise, but for rays that graze an edge, which the two tests
 * (watertight float, double Moller-Trumbore) may decide apart: at most 1 in 200. Any-hit on
 * segments ending before and after the reference's hit: blocked exactly when it says. */
static void two_level_finds_the_flattened_hits(void **state)
{
    (void)state;
    vkrt_scene scene = {0};
    load_instanced(&scene, false);
    vkrt_mesh world;
    bool copied;
    vkrt_error err = {{0}};
    assert_true(vkrt_model_world(&scene.model, &world, &copied, &err));
    Ray *rays = calloc(RAYS, sizeof *rays), *segments = calloc(RAYS, sizeof *segments);
    Hit *hits = calloc(RAYS, sizeof *hits);
    int64_t *ref = calloc(RAYS, sizeof *ref);
    double *ref_t = calloc(RAYS, sizeof *ref_t);
    assert_true(rays && segments && hits && ref && ref_t);
    make_rays(&scene.model, rays);
    uint32_t hit_count = 0;
    for (int i = 0; i < RAYS; ++i) {
        ref[i] = reference_hit(&world, &rays[i], INFINITY, &ref_t[i]);
        hit_count += ref[i] >= 0;
    }
    print_message("%u of %u rays hit the flattened scene\n", hit_count, RAYS);
    assert_true(hit_count > RAYS / 4);
    gpu_context ctx;
    fixture_context_create(&ctx);
    const uint32_t widths[] = {2, 4};
    for (int w = 0; w < 2; ++w) {
        trace(&ctx, &scene, widths[w], rays, false, hits);
        uint32_t wrong = 0;
        for (int i = 0; i < RAYS; ++i) {
            bool hit = hits[i].triangle != VKRT_NO_HIT;
            bool same = hit == (ref[i] >= 0);
            if (same && hit)
                same = hits[i].triangle == (uint32_t)ref[i] &&
                       fabs(hits[i].t - ref_t[i]) <= 1e-4 * fmax(1.0, ref_t[i]);
            if (!same && wrong++ < 5)
                print_message("width %u ray %d: reference %lld t=%.7g, two-level %u t=%.7g\n",
                              widths[w], i, (long long)ref[i], ref_t[i], hits[i].triangle,
                              hits[i].t);
        }
        print_message("width %u: %u of %u closest hits differ\n", widths[w], wrong, RAYS);
        assert_true(wrong <= RAYS / 200);
        /* Segments to 0.99 and 1.01 of the reference's hit: clear, then blocked. */
        uint32_t n = 0;
        for (int i = 0; i < RAYS && n + 2 <= RAYS; ++i) {
            if (ref[i] < 0)
                continue;
            segments[n] = rays[i];
            segments[n++].direction.w = (float)(0.99 * ref_t[i]);
            segments[n] = rays[i];
            segments[n++].direction.w = (float)(1.01 * ref_t[i]);
        }
        trace(&ctx, &scene, widths[w], segments, true, hits);
        wrong = 0;
        for (uint32_t i = 0; i < n; ++i)
            wrong += (hits[i].triangle != VKRT_NO_HIT) != (i % 2 == 1);
        print_message("width %u: %u of %u shadow segments differ\n", widths[w], wrong, n);
        assert_true(wrong <= n / 200);
    }
    fixture_context_destroy(&ctx);
    free(rays);
    free(segments);
    free(hits);
    free(ref);
    free(ref_t);
    if (copied)
        vkrt_mesh_free(&world);
    vkrt_scene_free(&scene);
}

/* ------------------------------------------------------------------------ render */

static void render(const vkrt_scene *scene, vkrt_instancing instancing, float *rgb,
                   vkrt_accel_stats *stats)
{
    const vkrt_render_desc desc = {.width = W, .height = H, .samples = 1,
                                   .instancing = instancing};
    fixture_render(scene, &desc, rgb, stats);
}

static void dump(const char *name, const float *rgb)
{
    const char *dir = getenv("VKRT_TEST_DUMP");
    if (!dir || !*dir)
        return;
    char path[512];
    snprintf(path, sizeof path, "%s/%s.ppm", dir, name);
    FILE *f = fopen(path, "wb");
    if (!f)
        return;
    fprintf(f, "P6\n%d %d\n255\n", W, H);
    for (int i = 0; i < W * H * 3; ++i) {
        float x = rgb[i] <= 0 ? 0 : rgb[i] >= 1 ? 1 : powf(rgb[i], 1 / 2.2f);
        fputc((int)(255 * x + 0.5f), f);
    }
    fclose(f);
}

/* The background's colour (the scene's environment): a pixel of it saw no triangle. */
static bool background(const float *p)
{
    return p[0] == 0.05f && p[1] == 0.05f && p[2] == 0.1f;
}

/* The flattened and the two-level renders of the scene (with material a cut out or not): the
 * same pixels covered (but for cut-out seams, where the stochastic test may go either way),
 * values the same within float noise (but for shadow rays that graze an edge or a seam). */
static void compare_renders(bool cutout, float *flat)
{
    vkrt_scene scene = {0};
    load_instanced(&scene, cutout);
    float *two = calloc(W * H * 3, sizeof *two);
    assert_non_null(two);
    vkrt_accel_stats flat_stats, two_stats;
    render(&scene, VKRT_INSTANCING_FLAT, flat, &flat_stats);
    render(&scene, VKRT_INSTANCING_AUTO, two, &two_stats);
    assert_false(flat_stats.two_level);
    assert_true(two_stats.two_level); /* auto: 48 triangles instanced over 8 */
    dump(cutout ? "instancing_cutout_flat" : "instancing_flat", flat);
    dump(cutout ? "instancing_cutout_two_level" : "instancing_two_level", two);
    int coverage = 0, covered = 0, differ = 0;
    double sum = 0, max_diff = 0;
    for (int i = 0; i < W * H; ++i) {
        const float *a = flat + 3 * i, *b = two + 3 * i;
        coverage += background(a) != background(b);
        covered += !background(a);
        for (int c = 0; c < 3; ++c) {
            double d = fabs((double)a[c] - b[c]);
            sum += a[c];
            max_diff = d > max_diff ? d : max_diff;
            differ += d > 1e-3 + 1e-3 * fabs(a[c]);
        }
    }
    print_message("covered %d of %d pixels; coverage differs at %d, values at %d (largest "
                  "difference %g), mean %g\n",
                  covered, W * H, coverage, differ, max_diff, sum / (W * H * 3));
    assert_true(covered > W * H / 3);
    assert_true(sum / (W * H * 3) > 0.05);
    assert_true(coverage <= (cutout ? W * H / 200 : 0));
    /* A shadow ray that grazes an edge may go either way between the two: a few pixels; more
     * with the cut-out, whose stochastic seams follow the sphere's many edges. */
    assert_true(differ <= W * H * 3 / (cutout ? 50 : 500));
    free(two);
    vkrt_scene_free(&scene);
}

static void two_level_renders_as_flattened(void **state)
{
    (void)state;
    float *plain = calloc(W * H * 3, sizeof *plain), *cut = calloc(W * H * 3, sizeof *cut);
    assert_true(plain && cut);
    compare_renders(false, plain);
    compare_renders(true, cut);
    /* The cut-out took part of material a away: many pixels changed. */
    int changed = 0;
    for (int i = 0; i < W * H; ++i)
        changed += memcmp(plain + 3 * i, cut + 3 * i, 3 * sizeof *plain) != 0;
    print_message("the cut-out changed %d of %d pixels\n", changed, W * H);
    assert_true(changed > W * H / 50);
    free(plain);
    free(cut);
}

/* ------------------------------------------------------------------------ materials */

/* A copy of mesh with its own arrays (the scene frees each mesh), materials a and b swapped. */
static vkrt_mesh swapped_copy(const vkrt_mesh *mesh)
{
    vkrt_mesh out = *mesh;
    size_t n = mesh->triangle_count;
    out.positions = malloc(n * 9 * sizeof(float));
    out.normals = malloc(n * 9 * sizeof(float));
    out.texcoords = malloc(n * 6 * sizeof(float));
    out.material = malloc(n * sizeof(int32_t));
    out.tangents = NULL;
    assert_true(out.positions && out.normals && out.texcoords && out.material);
    memcpy(out.positions, mesh->positions, n * 9 * sizeof(float));
    memcpy(out.normals, mesh->normals, n * 9 * sizeof(float));
    memcpy(out.texcoords, mesh->texcoords, n * 6 * sizeof(float));
    for (size_t k = 0; k < n; ++k)
        out.material[k] = mesh->material[k] == 0 ? 1 : 0;
    return out;
}

/* Two meshes of the same sphere, the second with its materials swapped (b above, a below), and
 * a third no instance uses, placed in a row as 1, 0, 1, 0, 1, 0 (the first instance's mesh is
 * not the model's first), each turned about z by its own angle. */
static void two_mesh_scene(vkrt_scene *scene)
{
    write_scene();
    load_written(scene);
    vkrt_error err = {{0}};
    vkrt_model *m = &scene->model;
    assert_int_equal(m->mesh_count, 1);
    assert_int_equal(m->material_count, 2);
    assert_string_equal(m->materials[0].name, "a");
    vkrt_mesh *meshes = realloc(m->meshes, 3 * sizeof *meshes);
    assert_non_null(meshes);
    m->meshes = meshes;
    meshes[1] = swapped_copy(&meshes[0]);
    meshes[2] = swapped_copy(&meshes[0]);
    m->mesh_count = 3;
    enum { N = 6 };
    vkrt_instance *inst = calloc(N, sizeof *inst);
    assert_non_null(inst);
    for (int i = 0; i < N; ++i) {
        float turn[12];
        rotation(2, 35.0f * i, turn);
        for (int k = 0; k < 12; ++k)
            turn[k] *= 0.8f;
        place(&inst[i], turn, -4.5f + 1.8f * i, 0, 0);
        inst[i].mesh = i % 2 == 0 ? 1 : 0;
    }
    free(m->instances);
    m->instances = inst;
    m->instance_count = N;
    if (!vkrt_model_finish(m, &err))
        fail_msg("%s", err.msg);
    vkrt_scene_materials_free(&scene->materials);
    if (!vkrt_scene_materials_resolve(&scene->config, m, NULL, &scene->materials, &err))
        fail_msg("%s", err.msg);
}

/* Each pixel's colour against the material its primary hit's triangle has in the model (the
 * record its mesh names for it, not what the renderer uploaded): material a is red, b blue.
 * The hits come from the trace API, through the pixel centres raygen.comp shoots at one sample;
 * a pixel at an edge may go either way. Both structures, and the two-level one by its auto
 * choice. */
static void each_mesh_keeps_its_materials(void **state)
{
    (void)state;
    vkrt_scene scene = {0};
    two_mesh_scene(&scene);
    const vkrt_model *m = &scene.model;
    Ray *rays = calloc(W * H, sizeof *rays);
    Hit *hits = calloc(W * H, sizeof *hits);
    float *rgb = calloc(W * H * 3, sizeof *rgb);
    assert_true(rays && hits && rgb);
    bench_primary_rays(&scene.cameras[0], W, H, rays);
    const vkrt_instancing modes[] = {VKRT_INSTANCING_AUTO, VKRT_INSTANCING_FLAT};
    for (int mode = 0; mode < 2; ++mode) {
        vkrt_render_desc desc = {.width = W, .height = H, .samples = 1,
                                 .instancing = modes[mode]};
        vkrt_error err = {{0}};
        vkrt_renderer *r = NULL;
        gpu_context ctx;
        fixture_context_create(&ctx);
        if (!vkrt_renderer_create(&r, &ctx, &scene, &desc, &err))
            fail_msg("renderer: %s", err.msg);
        assert_true(vkrt_renderer_accel_stats(r)->two_level == (mode == 0));
        if (!vkrt_renderer_trace(r, rays, W * H, false, hits, 1, NULL, &err))
            fail_msg("trace: %s", err.msg);
        vkrt_renderer_destroy(r);
        fixture_context_destroy(&ctx);
        vkrt_accel_stats stats;
        fixture_render(&scene, &desc, rgb, &stats);
        dump(mode == 0 ? "materials_two_level" : "materials_flat", rgb);
        /* checked[instance][material]: pixels seen of each. */
        int checked[6][2] = {{0}}, wrong = 0, hit = 0;
        for (int i = 0; i < W * H; ++i) {
            uint32_t t = hits[i].triangle;
            if (t == VKRT_NO_HIT)
                continue;
            uint32_t pixel = rays[i].info.x, instance = t / 216, k = t % 216;
            assert_true(instance < 6);
            int32_t want = m->meshes[m->instances[instance].mesh].material[k];
            assert_true(want == 0 || want == 1);
            const float *p = rgb + 3 * pixel;
            int seen = p[0] > p[2] ? 0 : 1;
            checked[instance][want]++;
            ++hit;
            if (seen != want && wrong++ < 5)
                print_message("pixel %u: instance %u triangle %u is %s, its colour %g %g %g\n",
                              pixel, instance, k, want == 0 ? "a" : "b", p[0], p[1], p[2]);
        }
        print_message("%s: %d of %d hit pixels of the wrong material\n",
                      mode == 0 ? "two-level" : "flat", wrong, hit);
        for (int i = 0; i < 6; ++i)
            assert_true(checked[i][0] > 20 && checked[i][1] > 20);
        assert_true(wrong <= hit / 100);
    }
    free(rays);
    free(hits);
    free(rgb);
    vkrt_scene_free(&scene);
}

/* One identity instance is today's flat scene: no two-level structure, whatever auto says. */
static void one_instance_stays_flat(void **state)
{
    (void)state;
    write_scene();
    vkrt_scene scene = {0};
    load_written(&scene);
    float *rgb = calloc(W * H * 3, sizeof *rgb);
    assert_non_null(rgb);
    vkrt_accel_stats stats;
    render(&scene, VKRT_INSTANCING_AUTO, rgb, &stats);
    assert_false(stats.two_level);
    free(rgb);
    vkrt_scene_free(&scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(two_level_finds_the_flattened_hits),
        cmocka_unit_test(two_level_renders_as_flattened),
        cmocka_unit_test(each_mesh_keeps_its_materials),
        cmocka_unit_test(one_instance_stays_flat),
    };
    return cmocka_run_group_tests(tests, scene_dir_make, scene_dir_remove);
}
