/*
 * main.c: rtpipe-bench, the driver's own ray tracing (VK_KHR_ray_tracing_pipeline) tracing the
 * rays `vkrt bench` traces, on the same scenes, timed the same way, so that vkrt's compute
 * kernels can be held against it on the same GPU.
 *
 * Rays (src/bench_rays.c, shared with vkrt bench): primary rays through the pixel centres of the
 * scene's first camera; from their hits, shadow rays (any hit) and cosine-distributed diffuse
 * bounce rays (closest hit). Like vkrt bench, the secondary rays are made from this tracer's own
 * primary hits, so they match vkrt's up to the rounding of the hit points' barycentrics and the
 * odd ray that hits another triangle at an edge.
 * Timing: src/bench_timing.c, as vkrt bench's: a probe run, a warm-up worth 300 ms of GPU time
 * (repeated while it fell short) and then 11 runs back to back in one submission, GPU timestamps
 * between them; the median of the timed runs, with the fastest and slowest in the JSON.
 *
 * Instanced scenes (several instances, or one that is not the identity): by default the driver's
 * own instancing, one BLAS per mesh and a TLAS over the instances (rtpipe_accel.h), hits numbered
 * in vkrt bench's order, so that the hits and blocked counts and the secondary rays are vkrt's;
 * --instancing flat traces the world-space triangles in one BLAS instead (vkrt bench's
 * --instancing flat). A scene of one identity instance takes the flat form either way, as it
 * always did. The two-level form has not yet run on a ray tracing GPU: where it was written
 * (lavapipe) it only compiles; the lead's first run checks that its hits and blocked counts
 * equal vkrt bench's on the same scene.
 *
 * Exit status: 0 done; 1 a failure (scene, Vulkan, ...); 2 a bad command line; 77 the device has
 * no ray tracing pipeline (automake's and meson's "skipped", lavapipe's case).
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../../glsl/shared.h"
#include "bench_rays.h"
#include "bench_timing.h"
#include "error.h"
#include "rtpipe_accel.h"
#include "rtpipe_device.h"
#include "rtpipe_shaders.h"
#include "rtpipe_trace.h"
#include "scene/scene.h"

enum { exit_failure = 1, exit_usage = 2, exit_unsupported = 77 };
enum { max_scenes = 64 };

/* --instancing: auto (flat for one identity instance, else two-level), flat, two-level. */
typedef enum instancing { INSTANCING_AUTO, INSTANCING_FLAT, INSTANCING_TWO_LEVEL } instancing;

typedef struct options {
    const char *scenes[max_scenes];
    uint32_t scene_count;
    const char *json;
    const char *check_shaders_dir; /* --check-shaders [DIR]: compile (and write the SPIR-V into DIR), exit */
    bool check_shaders;
    bool check_scenes; /* --check-scenes: the two-level plans' hit numbering (check_plan), exit */
    uint32_t width, height;
    int device;
    instancing instancing;
    bool validation;
} options;

typedef struct bench_row {
    const char *scene;
    uint32_t triangles, width, height;
    double build_ms, build_ms_first, blas_ms, tlas_ms;
    size_t bytes, scratch_bytes, blas_bytes, tlas_bytes;
    bool two_level;
    uint32_t instances, meshes; /* in the TLAS; BLASes */
    uint64_t unique_triangles;  /* over the BLASes */
    rtpipe_hit_numbering numbering;
    uint32_t primary_timed, shadow_timed, diffuse_timed;
    bench_times primary, shadow, diffuse;
    uint32_t hits, blocked;
} bench_row;

static const char usage[] =
    "usage: rtpipe-bench SCENE... [--json OUT.json] [--width W --height H] [--device N]\n"
    "                    [--instancing auto|flat|two-level] [--validation]\n"
    "       rtpipe-bench --check-shaders [DIR]   compile the shaders (and write DIR/*.spv), exit\n"
    "       rtpipe-bench --check-scenes SCENE... check the two-level hit numbering on the CPU\n"
    "Traces vkrt bench's primary, shadow and diffuse rays with the driver's ray tracing pipeline\n"
    "(VK_KHR_ray_tracing_pipeline) and prints Mrays/s. SCENE: a scene.cfg or a scene file alone\n"
    "(.obj, .gltf, .glb), as vkrt bench takes. --instancing: two-level (a BLAS per mesh, a TLAS\n"
    "over the instances; auto's choice for instanced scenes) or flat (the world-space triangles\n"
    "in one BLAS; auto's for one identity instance). Exit status: 0 done, 1 failed, 2 bad\n"
    "command line, 77 the device has no ray tracing pipeline.\n";

static bool parse_uint(const char *text, uint32_t *out)
{
    char *end;
    unsigned long v = strtoul(text, &end, 10);
    if (end == text || *end || v == 0 || v > 65536 || text[0] == '-')
        return false;
    *out = (uint32_t)v;
    return true;
}

static bool parse_options(int argc, char **argv, options *o, vkrt_error *err)
{
    memset(o, 0, sizeof *o);
    o->device = -1;
    const char *env = getenv("VKRT_VALIDATION");
    o->validation = env && *env && strcmp(env, "0") != 0;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        bool has_value = i + 1 < argc;
        if (strcmp(a, "--json") == 0 && has_value) {
            o->json = argv[++i];
        } else if (strcmp(a, "--width") == 0 && has_value) {
            if (!parse_uint(argv[++i], &o->width))
                return vkrt_error_set(err, "--width %s: want a whole number in 1..65536", argv[i]);
        } else if (strcmp(a, "--height") == 0 && has_value) {
            if (!parse_uint(argv[++i], &o->height))
                return vkrt_error_set(err, "--height %s: want a whole number in 1..65536", argv[i]);
        } else if (strcmp(a, "--device") == 0 && has_value) {
            char *end;
            long d = strtol(argv[++i], &end, 10);
            if (end == argv[i] || *end || d < 0 || d > 255)
                return vkrt_error_set(err, "--device %s: want a device index (vkrt --list-devices)",
                                      argv[i]);
            o->device = (int)d;
        } else if (strcmp(a, "--instancing") == 0 && has_value) {
            const char *v = argv[++i];
            if (strcmp(v, "auto") == 0)
                o->instancing = INSTANCING_AUTO;
            else if (strcmp(v, "flat") == 0)
                o->instancing = INSTANCING_FLAT;
            else if (strcmp(v, "two-level") == 0)
                o->instancing = INSTANCING_TWO_LEVEL;
            else
                return vkrt_error_set(err, "--instancing: '%s' is not one of auto, flat, two-level",
                                      v);
        } else if (strcmp(a, "--validation") == 0) {
            o->validation = true;
        } else if (strcmp(a, "--check-shaders") == 0) {
            o->check_shaders = true;
            if (has_value && argv[i + 1][0] != '-')
                o->check_shaders_dir = argv[++i];
        } else if (strcmp(a, "--check-scenes") == 0) {
            o->check_scenes = true;
        } else if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            return vkrt_error_set(err, "help");
        } else if (a[0] == '-') {
            return vkrt_error_set(err, "unknown option %s (or it lacks its value)", a);
        } else if (o->scene_count == max_scenes) {
            return vkrt_error_set(err, "more than %d scenes", max_scenes);
        } else {
            o->scenes[o->scene_count++] = a;
        }
    }
    if (!o->check_shaders && o->scene_count == 0)
        return vkrt_error_set(err, "no scene given");
    return true;
}

/* One trace of the pipeline, for bench_time_trace. */
typedef struct pipeline_trace {
    rtpipe_device *dev;
    rtpipe_tracer *tracer;
    const Ray *rays;
    uint32_t count;
    bool any_hit;
    Hit *hits;
} pipeline_trace;

static bool run_pipeline_trace(void *user, uint32_t repeats, double *ms, vkrt_error *err)
{
    pipeline_trace *p = user;
    return rtpipe_tracer_trace(p->dev, p->tracer, p->rays, p->count, p->any_hit, p->hits, repeats,
                               ms, err);
}

static bool timed_trace(rtpipe_device *dev, rtpipe_tracer *t, const Ray *rays, uint32_t count,
                        bool any_hit, Hit *hits, bench_times *times, vkrt_error *err)
{
    pipeline_trace p = {dev, t, rays, count, any_hit, hits};
    return bench_time_trace(run_pipeline_trace, &p, VKRT_WARMUP_MS, times, err);
}

/* The secondary rays index the mesh with the hits' triangles: a driver's bad index must not. */
static bool check_hits(const Hit *hits, uint32_t count, uint32_t triangles, vkrt_error *err)
{
    for (uint32_t i = 0; i < count; ++i)
        if (hits[i].triangle != VKRT_NO_HIT && hits[i].triangle >= triangles)
            return vkrt_error_set(err, "ray %u hit triangle %u of %u: the driver's result is "
                                       "wrong", i, hits[i].triangle, triangles);
    return true;
}

/* Whether the model is one instance with the identity transform: its mesh is then the world's
 * triangles as they are (vkrt_model_world copies nothing). */
static bool one_identity_instance(const vkrt_model *model)
{
    return model->instance_count == 1 &&
           memcmp(model->instances[0].transform, vkrt_identity_transform,
                  sizeof vkrt_identity_transform) == 0;
}

/* The structures --instancing asks for: two-level over the model's meshes and instances, or flat
 * over vkrt_model_world's triangles. */
static bool create_accel(rtpipe_device *dev, const vkrt_model *model, instancing how,
                         rtpipe_accel *accel, vkrt_error *err)
{
    if (how == INSTANCING_TWO_LEVEL || (how == INSTANCING_AUTO && !one_identity_instance(model)))
        return rtpipe_accel_create_instanced(dev, model, accel, err);
    vkrt_mesh world;
    bool copied;
    if (!vkrt_model_world(model, &world, &copied, err))
        return false;
    bool ok = rtpipe_accel_create(dev, world.positions, world.triangle_count, accel, err);
    if (copied)
        vkrt_mesh_free(&world);
    return ok;
}

static bool bench_scene(rtpipe_device *dev, const rtpipe_shaders *shaders,
                        const vkrt_scene *scene, instancing how, bench_row *row, vkrt_error *err)
{
    rtpipe_accel accel;
    if (!create_accel(dev, &scene->model, how, &accel, err))
        return false;
    /* Over all instances, as vkrt bench counts them and numbers hits. */
    row->triangles = scene->model.triangle_count;
    row->two_level = accel.two_level;
    row->instances = accel.instances;
    row->meshes = accel.blas_count;
    row->unique_triangles = accel.unique_triangles;
    row->numbering = accel.numbering;
    row->blas_bytes = (size_t)accel.blas_bytes;
    row->tlas_bytes = (size_t)accel.tlas_bytes;
    row->build_ms = accel.build_ms;
    row->build_ms_first = accel.build_ms_first;
    row->blas_ms = accel.blas_ms;
    row->tlas_ms = accel.tlas_ms;
    row->bytes = (size_t)(accel.blas_bytes + accel.tlas_bytes);
    row->scratch_bytes = (size_t)accel.scratch_bytes;
    if ((uint64_t)row->width * row->height > (1u << 28)) {
        rtpipe_accel_destroy(dev, &accel);
        return vkrt_error_set(err, "%u x %u rays are too many", row->width, row->height);
    }
    uint32_t pixels = row->width * row->height;
    rtpipe_tracer tracer;
    if (!rtpipe_tracer_create(dev, shaders, &accel, pixels, &tracer, err)) {
        rtpipe_accel_destroy(dev, &accel);
        return false;
    }
    Ray *primary = malloc(pixels * sizeof *primary), *secondary = malloc(pixels * sizeof *secondary);
    Hit *hits = malloc(pixels * sizeof *hits), *primary_hits = malloc(pixels * sizeof *hits);
    bool ok = primary && secondary && hits && primary_hits;
    if (!ok)
        vkrt_error_set(err, "out of memory for %u rays", pixels);
    if (ok) {
        bench_primary_rays(&scene->cameras[0], row->width, row->height, primary);
        ok = timed_trace(dev, &tracer, primary, pixels, false, primary_hits, &row->primary, err) &&
             check_hits(primary_hits, pixels, row->triangles, err);
        row->primary_timed = pixels;
    }
    if (ok) {
        for (uint32_t i = 0; i < pixels; ++i)
            row->hits += primary_hits[i].triangle != VKRT_NO_HIT;
        uint32_t n = bench_shadow_rays(scene, primary, primary_hits, pixels, secondary);
        row->shadow_timed = n;
        ok = n == 0 || timed_trace(dev, &tracer, secondary, n, true, hits, &row->shadow, err);
        for (uint32_t i = 0; ok && i < n; ++i)
            row->blocked += hits[i].triangle != VKRT_NO_HIT;
    }
    if (ok) {
        uint32_t n = bench_diffuse_rays(scene, primary, primary_hits, pixels, secondary);
        row->diffuse_timed = n;
        ok = ok && (n == 0 || timed_trace(dev, &tracer, secondary, n, false, hits, &row->diffuse, err));
    }
    free(primary);
    free(secondary);
    free(hits);
    free(primary_hits);
    rtpipe_tracer_destroy(dev, &tracer);
    rtpipe_accel_destroy(dev, &accel);
    return ok;
}

static double mrays(uint32_t rays, double ms)
{
    return ms > 0 ? rays / (ms * 1e3) : 0;
}

static void print_header(void)
{
    printf("%-28s %9s %9s %8s %10s %10s %10s %8s %8s\n", "scene", "triangles", "build_ms", "MiB",
           "primary", "shadow", "diffuse", "hits", "blocked");
    printf("%-28s %9s %9s %8s %10s %10s %10s %8s %8s\n", "", "", "", "", "Mrays/s", "Mrays/s",
           "Mrays/s", "", "");
}

static const char *const numbering_names[] = {
    [RTPIPE_HIT_PRIMITIVE] = "primitive",
    [RTPIPE_HIT_CUSTOM_INDEX] = "custom-index",
    [RTPIPE_HIT_INSTANCE_BUFFER] = "instance-buffer",
};

static void print_row(const bench_row *b)
{
    printf("%-28s %9u %9.2f %8.2f %10.4g %10.4g %10.4g %8u %8u\n", b->scene, b->triangles,
           b->build_ms, b->bytes / 1048576.0, mrays(b->primary_timed, b->primary.median_ms),
           mrays(b->shadow_timed, b->shadow.median_ms),
           mrays(b->diffuse_timed, b->diffuse.median_ms), b->hits, b->blocked);
    if (b->two_level)
        printf("  two-level: %u instances of %u meshes (%llu unique triangles), BLAS %.2f MiB, "
               "TLAS %.2f MiB, BLAS build %.2f ms, TLAS build %.2f ms, hits numbered by %s\n",
               b->instances, b->meshes, (unsigned long long)b->unique_triangles,
               b->blas_bytes / 1048576.0, b->tlas_bytes / 1048576.0, b->blas_ms, b->tlas_ms,
               numbering_names[b->numbering]);
}

/* NVIDIA packs its driver version as 10 bits major, 8 minor, 8 patch, 6 more; others (Mesa) use
 * Vulkan's VK_MAKE_API_VERSION layout. */
static void driver_text(const VkPhysicalDeviceProperties *p, char *out, size_t size)
{
    uint32_t v = p->driverVersion;
    if (p->vendorID == 0x10DE)
        snprintf(out, size, "%u.%u.%u", v >> 22, (v >> 14) & 0xFF, (v >> 6) & 0xFF);
    else
        snprintf(out, size, "%u.%u.%u", VK_API_VERSION_MAJOR(v), VK_API_VERSION_MINOR(v),
                 VK_API_VERSION_PATCH(v));
}

/* A string for JSON: quotes and backslashes escaped, control characters dropped. */
static void json_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s; ++s) {
        if (*s == '"' || *s == '\\')
            fputc('\\', f);
        if ((unsigned char)*s >= 0x20)
            fputc(*s, f);
    }
    fputc('"', f);
}

static void json_times(FILE *f, const char *kind, uint32_t rays, const bench_times *t)
{
    fprintf(f,
            "\"%s_rays_timed\": %u, \"%s_ms\": %.4f, \"%s_ms_min\": %.4f, \"%s_ms_max\": %.4f, "
            "\"%s_mrays_per_s\": %.3f, ",
            kind, rays, kind, t->median_ms, kind, t->min_ms, kind, t->max_ms, kind,
            mrays(rays, t->median_ms));
}

/* The fields of vkrt bench's JSON (src/bench.c), so research/bench_table.py reads both; accel is
 * "rtpipe", and the ray tracing limits and build details are added. */
static bool write_json(const char *path, const rtpipe_device *dev, const bench_row *rows,
                       uint32_t count, vkrt_error *err)
{
    char tmp[4200];
    if (snprintf(tmp, sizeof tmp, "%s.tmp", path) >= (int)sizeof tmp)
        return vkrt_error_set(err, "%s: path too long", path);
    FILE *f = fopen(tmp, "w");
    if (!f)
        return vkrt_error_set(err, "%s: cannot write", path);
    const VkPhysicalDeviceProperties *p = &dev->ctx.properties;
    char driver[64];
    driver_text(p, driver, sizeof driver);
    fprintf(f, "{\n  \"device\": ");
    json_string(f, p->deviceName);
    fprintf(f, ",\n  \"driver_version\": %u,\n  \"driver\": \"%s\",\n  \"api_version\": \"%u.%u.%u\",\n",
            p->driverVersion, driver, VK_API_VERSION_MAJOR(p->apiVersion),
            VK_API_VERSION_MINOR(p->apiVersion), VK_API_VERSION_PATCH(p->apiVersion));
    fprintf(f, "  \"tracer\": \"VK_KHR_ray_tracing_pipeline\",\n"
               "  \"shader_group_handle_size\": %u,\n  \"max_ray_dispatch_invocation_count\": %u,\n"
               "  \"build_runs\": %d,\n",
            dev->pipeline.shaderGroupHandleSize, dev->pipeline.maxRayDispatchInvocationCount,
            RTPIPE_BUILD_RUNS);
    fprintf(f, "  \"warmup_ms\": %.0f,\n  \"timed_runs\": %d,\n  \"statistic\": \"median\",\n"
               "  \"results\": [\n", VKRT_WARMUP_MS, BENCH_TIMED_RUNS);
    for (uint32_t i = 0; i < count; ++i) {
        const bench_row *b = &rows[i];
        fprintf(f, "    {\"scene\": ");
        json_string(f, b->scene);
        fprintf(f,
                ", \"accel\": \"rtpipe\", \"reason\": \"the driver's ray tracing pipeline, "
                "PREFER_FAST_TRACE\", \"triangles\": %u, \"width\": %u, \"height\": %u, "
                "\"build_ms\": %.3f, \"build_ms_first\": %.3f, \"blas_ms\": %.3f, "
                "\"tlas_ms\": %.3f, \"bytes\": %zu, \"scratch_bytes\": %zu, ",
                b->triangles, b->width, b->height, b->build_ms, b->build_ms_first, b->blas_ms,
                b->tlas_ms, b->bytes, b->scratch_bytes);
        fprintf(f,
                "\"instancing\": \"%s\", \"instances\": %u, \"meshes\": %u, "
                "\"unique_triangles\": %llu, \"blas_bytes\": %zu, \"tlas_bytes\": %zu, "
                "\"hit_numbering\": \"%s\", ",
                b->two_level ? "two-level" : "flat", b->instances, b->meshes,
                (unsigned long long)b->unique_triangles, b->blas_bytes, b->tlas_bytes,
                numbering_names[b->numbering]);
        json_times(f, "primary", b->primary_timed, &b->primary);
        json_times(f, "shadow", b->shadow_timed, &b->shadow);
        json_times(f, "diffuse", b->diffuse_timed, &b->diffuse);
        fprintf(f, "\"hits\": %u, \"blocked\": %u}%s\n", b->hits, b->blocked,
                i + 1 < count ? "," : "");
    }
    fprintf(f, "  ]\n}\n");
    if (fclose(f) != 0 || rename(tmp, path) != 0) {
        remove(tmp);
        return vkrt_error_set(err, "%s: cannot write", path);
    }
    return true;
}

/* --check-scenes: what the two-level form's hits would be, checked on the CPU against vkrt's
 * own numbering. For every kept instance k of the plan and every triangle p of its BLAS (what
 * the hit shader sees as gl_InstanceID and gl_PrimitiveID), the number closest.rchit makes of
 * them (the instance's custom index as the 24-bit field holds it, or instance_first[k], plus p)
 * must name the triangle of vkrt_model_world (what vkrt bench numbers and bench_rays.h reads)
 * that is triangle p of the BLAS moved by the instance's transform as the record holds it. */
static bool check_plan(const vkrt_model *model, uint64_t *checked, vkrt_error *err)
{
    rtpipe_plan p;
    vkrt_mesh world;
    bool copied = false;
    if (!rtpipe_plan_instanced(model, &p, err))
        return false;
    if (!vkrt_model_world(model, &world, &copied, err)) {
        rtpipe_plan_free(&p);
        return false;
    }
    bool ok = true;
    *checked = 0;
    for (uint32_t k = 0; ok && k < p.instance_count; ++k) {
        const VkAccelerationStructureInstanceKHR *r = &p.instances[k];
        uint32_t b = (uint32_t)r->accelerationStructureReference;
        uint32_t first = p.numbering == RTPIPE_HIT_CUSTOM_INDEX ? r->instanceCustomIndex
                                                                : p.instance_first[k];
        for (uint32_t t = 0; ok && t < p.triangles[b]; ++t) {
            uint64_t hit = (uint64_t)first + t;
            if (hit >= world.triangle_count) {
                ok = vkrt_error_set(err, "instance %u triangle %u: hit %llu is past the %u "
                                         "triangles", k, t, (unsigned long long)hit,
                                    world.triangle_count);
                break;
            }
            const float *o = p.positions[b] + 9 * (size_t)t, *w = world.positions + 9 * hit;
            for (int v = 0; ok && v < 3; ++v)
                for (int row = 0; row < 3; ++row) {
                    const float *m = r->transform.matrix[row];
                    double x = (double)m[0] * o[3 * v] + (double)m[1] * o[3 * v + 1] +
                               (double)m[2] * o[3 * v + 2] + m[3];
                    double scale = fabs(m[0] * o[3 * v]) + fabs(m[1] * o[3 * v + 1]) +
                                   fabs(m[2] * o[3 * v + 2]) + fabs(m[3]);
                    if (fabs(x - w[3 * v + row]) > 1e-5 * scale + 1e-30)
                        ok = vkrt_error_set(err, "instance %u triangle %u (hit %llu), vertex %d: "
                                                 "%g, but vkrt's triangle has %g", k, t,
                                            (unsigned long long)hit, v, x, w[3 * v + row]);
                }
            ++*checked;
        }
    }
    if (copied)
        vkrt_mesh_free(&world);
    rtpipe_plan_free(&p);
    return ok;
}

static int check_scenes(const options *o)
{
    for (uint32_t s = 0; s < o->scene_count; ++s) {
        vkrt_scene scene;
        vkrt_error err = {{0}};
        uint64_t checked = 0;
        if (!vkrt_scene_load_geometry(o->scenes[s], &scene, &err)) {
            fprintf(stderr, "rtpipe-bench: %s\n", err.msg);
            return exit_failure;
        }
        rtpipe_plan p;
        bool ok = rtpipe_plan_instanced(&scene.model, &p, &err);
        if (ok)
            printf("%s: two-level: %u instances of %u meshes, hits numbered by %s\n",
                   o->scenes[s], p.instance_count, p.blas_count, numbering_names[p.numbering]);
        rtpipe_plan_free(&p);
        ok = ok && check_plan(&scene.model, &checked, &err);
        vkrt_scene_free(&scene);
        if (!ok) {
            fprintf(stderr, "rtpipe-bench: %s: %s\n", o->scenes[s], err.msg);
            return exit_failure;
        }
        printf("%s: %llu instanced triangles numbered as vkrt bench numbers them\n", o->scenes[s],
               (unsigned long long)checked);
    }
    return 0;
}

/* --check-shaders: what can be tested without a ray tracing device. */
static int check_shaders(const char *dir)
{
    rtpipe_shaders shaders;
    vkrt_error err = {{0}};
    if (!rtpipe_shaders_compile(&shaders, &err)) {
        fprintf(stderr, "rtpipe-bench: %s\n", err.msg);
        return exit_failure;
    }
    int status = 0;
    for (int i = 0; i < RTPIPE_STAGES; ++i) {
        printf("%-14s %6zu SPIR-V words\n", rtpipe_shader_path(i), shaders.words[i]);
        if (!dir)
            continue;
        char path[4200];
        snprintf(path, sizeof path, "%s/%s.spv", dir, rtpipe_shader_path(i));
        FILE *f = fopen(path, "wb");
        if (!f || fwrite(shaders.spirv[i], sizeof(uint32_t), shaders.words[i], f) !=
                      shaders.words[i]) {
            fprintf(stderr, "rtpipe-bench: %s: cannot write\n", path);
            status = exit_failure;
        }
        if (f && fclose(f) != 0)
            status = exit_failure;
    }
    rtpipe_shaders_free(&shaders);
    return status;
}

int main(int argc, char **argv)
{
    options opts;
    vkrt_error err = {{0}};
    if (!parse_options(argc, argv, &opts, &err)) {
        bool help = strcmp(err.msg, "help") == 0;
        if (!help)
            fprintf(stderr, "rtpipe-bench: %s\n", err.msg);
        fputs(usage, help ? stdout : stderr);
        return help ? 0 : exit_usage;
    }
    if (opts.check_shaders)
        return check_shaders(opts.check_shaders_dir);
    if (opts.check_scenes)
        return check_scenes(&opts);

    /* The shaders first: a compile error needs no GPU to show. */
    rtpipe_shaders shaders;
    if (!rtpipe_shaders_compile(&shaders, &err)) {
        fprintf(stderr, "rtpipe-bench: %s\n", err.msg);
        return exit_failure;
    }
    rtpipe_device dev;
    rtpipe_device_status status = rtpipe_device_create(&dev, opts.device, opts.validation, &err);
    if (status != RTPIPE_DEVICE_OK) {
        fprintf(stderr, "rtpipe-bench: %s\n", err.msg);
        rtpipe_shaders_free(&shaders);
        return status == RTPIPE_DEVICE_UNSUPPORTED ? exit_unsupported : exit_failure;
    }
    char driver[64];
    driver_text(&dev.ctx.properties, driver, sizeof driver);
    printf("device: %s (driver %s), VK_KHR_ray_tracing_pipeline: shader group handle %u bytes, "
           "max recursion %u, max dispatch %u rays\n",
           dev.ctx.properties.deviceName, driver, dev.pipeline.shaderGroupHandleSize,
           dev.pipeline.maxRayRecursionDepth, dev.pipeline.maxRayDispatchInvocationCount);
    print_header();
    fflush(stdout);
    bench_row *rows = calloc(opts.scene_count, sizeof *rows);
    uint32_t row_count = 0;
    bool ok = rows != NULL;
    if (!ok)
        vkrt_error_set(&err, "out of memory");
    for (uint32_t s = 0; ok && s < opts.scene_count; ++s) {
        vkrt_scene scene;
        /* Tracing reads no material or texture: the geometry alone, as vkrt bench loads it. */
        if (!vkrt_scene_load_geometry(opts.scenes[s], &scene, &err)) {
            ok = false;
            break;
        }
        bench_row *row = &rows[row_count];
        row->scene = opts.scenes[s];
        row->width = opts.width ? opts.width : scene.config.width;
        row->height = opts.height ? opts.height : scene.config.height;
        ok = bench_scene(&dev, &shaders, &scene, opts.instancing, row, &err);
        if (!ok)
            vkrt_error_prefix(&err, "%s", opts.scenes[s]);
        if (ok) {
            print_row(row);
            fflush(stdout);
            ++row_count;
        }
        vkrt_scene_free(&scene);
    }
    if (ok && opts.json)
        ok = write_json(opts.json, &dev, rows, row_count, &err);
    free(rows);
    rtpipe_shaders_free(&shaders);
    if (ok) {
        ok = rtpipe_device_finish(&dev, &err);
    } else {
        vkrt_error finish_err;
        rtpipe_device_finish(&dev, &finish_err);
    }
    if (!ok) {
        fprintf(stderr, "rtpipe-bench: %s\n", err.msg);
        return exit_failure;
    }
    return 0;
}
