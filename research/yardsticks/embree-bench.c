/*
 * embree-bench.c: Embree 3 on the rays of `vkrt bench`, a CPU yardstick for vkrt on lavapipe
 * (research/README.md, `research/cpu-run embree`). Built only where Embree is installed (meson
 * option embree_bench).
 *
 *   embree-bench SCENE.cfg... [--width W --height H] [--threads N] [--json OUT.json]
 *
 * The scene's geometry is loaded by vkrt's own loader and the rays made by bench_rays.c, so the
 * primary rays are bit for bit those vkrt traces; the shadow and diffuse rays start from
 * Embree's own primary hits, which is where they may differ from vkrt's by the few hits the two
 * disagree on. One RTCScene per scene, built once with RTC_BUILD_QUALITY_HIGH (the geometry stays
 * in a flythrough, so the build that traces fastest is the fair yardstick); rays are traced one
 * at a time with rtcIntersect1 (closest hit) or rtcOccluded1 (shadow rays, any hit), on N
 * threads (default 2) that take interleaved blocks of rays. Timing as vkrt bench's: warm-up runs
 * worth warmup_ms, then timed_runs runs on the monotonic clock; the median is reported.
 */
#define _POSIX_C_SOURCE 200809L
#include <embree3/rtcore.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "../../glsl/shared.h"
#include "bench_rays.h"
#include "scene/scene.h"

enum { timed_runs = 11, min_warmup_runs = 2, max_warmup_runs = 4000, max_threads = 64 };

/* As vkrt bench: enough back-to-back runs first for caches and clocks to settle. */
static const double warmup_ms = 300.0;

/* Rays a thread takes at a time: consecutive pixels of a row for primary rays, so a block stays
 * coherent, and small enough that interleaving the blocks balances the image's costly parts
 * between threads. */
enum { block_rays = 256 };

typedef struct options {
    const char *scenes[64];
    unsigned scene_count;
    uint32_t width, height; /* 0: the scene's resolution */
    unsigned threads;
    const char *json;
} options;

typedef struct trace_times {
    double median_ms, min_ms, max_ms;
} trace_times;

typedef struct row {
    const char *scene;
    uint32_t triangles, width, height, rays, shadow_rays, diffuse_rays, hits, blocked;
    double build_ms;
    trace_times primary, shadow, diffuse;
} row;

/* One thread's share of a trace: blocks thread, thread + threads, ... of the rays. */
typedef struct trace_job {
    RTCScene scene;
    const Ray *rays;
    Hit *hits;
    uint32_t count;
    unsigned thread, threads;
    bool any_hit;
} trace_job;

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

/* Hits in vkrt's form: triangle is the OBJ-order index (Embree's primID: the triangles go in in
 * that order), or VKRT_NO_HIT; u, v the barycentrics of v1 and v2 as in vkrt. For shadow rays
 * only triangle matters: 0 blocked, VKRT_NO_HIT not. */
static void *trace_thread(void *arg)
{
    const trace_job *job = arg;
    struct RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (uint32_t start = job->thread * block_rays; start < job->count;
         start += job->threads * block_rays) {
        uint32_t end = start + block_rays < job->count ? start + block_rays : job->count;
        for (uint32_t i = start; i < end; ++i) {
            const Ray *r = &job->rays[i];
            struct RTCRayHit rh = {
                .ray = {.org_x = r->origin.x,
                        .org_y = r->origin.y,
                        .org_z = r->origin.z,
                        .tnear = r->origin.w,
                        .dir_x = r->direction.x,
                        .dir_y = r->direction.y,
                        .dir_z = r->direction.z,
                        .tfar = r->direction.w,
                        .mask = ~0u},
                .hit = {.geomID = RTC_INVALID_GEOMETRY_ID, .instID = {RTC_INVALID_GEOMETRY_ID}},
            };
            if (job->any_hit) {
                rtcOccluded1(job->scene, &context, &rh.ray);
                /* Embree marks an occluded ray by tfar = -inf. */
                job->hits[i] = (Hit){.t = 0, .triangle = rh.ray.tfar < 0 ? 0 : VKRT_NO_HIT};
            } else {
                rtcIntersect1(job->scene, &context, &rh);
                bool hit = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
                job->hits[i] = (Hit){.t = hit ? rh.ray.tfar : 0,
                                     .u = rh.hit.u,
                                     .v = rh.hit.v,
                                     .triangle = hit ? rh.hit.primID : VKRT_NO_HIT};
            }
        }
    }
    return NULL;
}

/* One trace of every ray on the options' threads; returns its wall time in ms, or a negative
 * number when a thread could not start. */
static double trace_once(RTCScene scene, const Ray *rays, uint32_t count, bool any_hit, Hit *hits,
                         unsigned threads)
{
    pthread_t ids[max_threads];
    trace_job jobs[max_threads];
    double start = now_ms();
    unsigned started = 0;
    for (; started < threads; ++started) {
        jobs[started] = (trace_job){scene, rays, hits, count, started, threads, any_hit};
        if (pthread_create(&ids[started], NULL, trace_thread, &jobs[started]) != 0)
            break;
    }
    for (unsigned t = 0; t < started; ++t)
        pthread_join(ids[t], NULL);
    double ms = now_ms() - start;
    return started == threads ? ms : -1;
}

static int compare_doubles(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static bool timed_trace(RTCScene scene, const Ray *rays, uint32_t count, bool any_hit, Hit *hits,
                        unsigned threads, trace_times *times, vkrt_error *err)
{
    double probe = trace_once(scene, rays, count, any_hit, hits, threads);
    if (probe < 0)
        return vkrt_error_set(err, "cannot start %u threads", threads);
    uint32_t warmup = probe > 0 ? (uint32_t)(warmup_ms / probe) + 1 : max_warmup_runs;
    warmup = warmup < min_warmup_runs   ? min_warmup_runs
             : warmup > max_warmup_runs ? max_warmup_runs
                                        : warmup;
    double ms[timed_runs];
    for (uint32_t i = 0; i < warmup + timed_runs; ++i) {
        double t = trace_once(scene, rays, count, any_hit, hits, threads);
        if (t < 0)
            return vkrt_error_set(err, "cannot start %u threads", threads);
        if (i >= warmup)
            ms[i - warmup] = t;
    }
    qsort(ms, timed_runs, sizeof *ms, compare_doubles);
    *times = (trace_times){ms[timed_runs / 2], ms[0], ms[timed_runs - 1]};
    return true;
}

/* Embree's messages, kept for the next failed call to report. */
static void embree_error(void *user, enum RTCError code, const char *message)
{
    vkrt_error *err = user;
    vkrt_error_set(err, "embree error %d: %s", (int)code, message ? message : "");
}

/* Builds the scene's triangles into an Embree scene; returns NULL with err set on failure
 * (Embree's own message where its error function gave one). */
static RTCScene build_scene(RTCDevice device, const vkrt_mesh *mesh, double *build_ms,
                            vkrt_error *err)
{
    double start = now_ms();
    RTCScene scene = rtcNewScene(device);
    RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    if (!scene || !geom) {
        if (scene)
            rtcReleaseScene(scene);
        return err->msg[0] ? NULL : (vkrt_error_set(err, "embree: cannot create a scene"), NULL);
    }
    /* Embree's own buffers, which it pads for its vector loads; vkrt's mesh is unindexed (9
     * floats per triangle), so triangle i is vertices 3i, 3i + 1, 3i + 2. */
    uint32_t n = mesh->triangle_count;
    float *v = rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                       3 * sizeof(float), 3 * (size_t)n);
    uint32_t *idx = rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                            3 * sizeof(uint32_t), n);
    if (v && idx) {
        memcpy(v, mesh->positions, 9 * sizeof(float) * (size_t)n);
        for (uint32_t i = 0; i < 3 * n; ++i)
            idx[i] = i;
        rtcSetGeometryBuildQuality(geom, RTC_BUILD_QUALITY_HIGH);
        rtcCommitGeometry(geom);
        rtcAttachGeometry(scene, geom);
        rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
        rtcCommitScene(scene);
    }
    rtcReleaseGeometry(geom);
    if (!v || !idx || rtcGetDeviceError(device) != RTC_ERROR_NONE) {
        rtcReleaseScene(scene);
        return err->msg[0] ? NULL : (vkrt_error_set(err, "embree: cannot build the scene"), NULL);
    }
    *build_ms = now_ms() - start;
    return scene;
}

static bool bench_scene(RTCDevice device, const char *path, const options *opts, row *out,
                        vkrt_error *err)
{
    vkrt_scene s;
    if (!vkrt_scene_load_geometry(path, &s, err))
        return false;
    *out = (row){.scene = path,
                 .triangles = s.model.meshes[0].triangle_count,
                 .width = opts->width ? opts->width : s.config.width,
                 .height = opts->height ? opts->height : s.config.height};
    uint32_t pixels = out->width * out->height;
    Ray *primary = malloc(pixels * sizeof *primary), *other = malloc(pixels * sizeof *other);
    Hit *hits = malloc(pixels * sizeof *hits), *other_hits = malloc(pixels * sizeof *other_hits);
    RTCScene scene = NULL;
    bool ok = primary && other && hits && other_hits;
    if (!ok)
        vkrt_error_set(err, "out of memory for %u rays", pixels);
    if (ok && !(scene = build_scene(device, &s.model.meshes[0], &out->build_ms, err)))
        ok = false;
    if (ok) {
        out->rays = pixels;
        bench_primary_rays(&s.cameras[0], out->width, out->height, primary);
        ok = timed_trace(scene, primary, pixels, false, hits, opts->threads, &out->primary, err);
    }
    for (uint32_t i = 0; ok && i < pixels; ++i)
        out->hits += hits[i].triangle != VKRT_NO_HIT;
    if (ok) {
        out->shadow_rays = bench_shadow_rays(&s, primary, hits, pixels, other);
        ok = timed_trace(scene, other, out->shadow_rays, true, other_hits, opts->threads,
                         &out->shadow, err);
    }
    for (uint32_t i = 0; ok && i < out->shadow_rays; ++i)
        out->blocked += other_hits[i].triangle != VKRT_NO_HIT;
    if (ok) {
        out->diffuse_rays = bench_diffuse_rays(&s, primary, hits, pixels, other);
        ok = timed_trace(scene, other, out->diffuse_rays, false, other_hits, opts->threads,
                         &out->diffuse, err);
    }
    if (scene)
        rtcReleaseScene(scene);
    free(primary);
    free(other);
    free(hits);
    free(other_hits);
    vkrt_scene_free(&s);
    return ok;
}

static double mrays(uint32_t rays, double ms)
{
    return ms > 0 ? rays / (ms * 1e3) : 0;
}

static void print_row(const row *r)
{
    printf("%-30s %9u %9.1f %10.4g %10.4g %10.4g %8u %8u\n", r->scene, r->triangles, r->build_ms,
           mrays(r->rays, r->primary.median_ms), mrays(r->shadow_rays, r->shadow.median_ms),
           mrays(r->diffuse_rays, r->diffuse.median_ms), r->hits, r->blocked);
}

static void json_times(FILE *f, const char *name, uint32_t rays, const trace_times *t)
{
    fprintf(f,
            "\"%s_rays_timed\": %u, \"%s_ms\": %.4f, \"%s_ms_min\": %.4f, \"%s_ms_max\": %.4f, "
            "\"%s_mrays_per_s\": %.3f, ",
            name, rays, name, t->median_ms, name, t->min_ms, name, t->max_ms, name,
            mrays(rays, t->median_ms));
}

/* The same keys as vkrt bench's JSON where they mean the same, written under a temporary name
 * and renamed. */
static bool write_json(const char *path, const options *opts, const row *rows, unsigned count,
                       vkrt_error *err)
{
    char tmp[4200];
    snprintf(tmp, sizeof tmp, "%s.tmp", path);
    FILE *f = fopen(tmp, "w");
    if (!f)
        return vkrt_error_set(err, "%s: cannot write", path);
    fprintf(f,
            "{\n  \"tracer\": \"embree\",\n  \"embree_version\": \"%s\",\n  \"threads\": %u,\n"
            "  \"build_quality\": \"high\",\n  \"warmup_ms\": %.0f,\n  \"timed_runs\": %d,\n"
            "  \"statistic\": \"median\",\n  \"results\": [\n",
            RTC_VERSION_STRING, opts->threads, warmup_ms, timed_runs);
    for (unsigned i = 0; i < count; ++i) {
        const row *r = &rows[i];
        fprintf(f,
                "    {\"scene\": \"%s\", \"triangles\": %u, \"width\": %u, \"height\": %u, "
                "\"build_ms\": %.3f, ",
                r->scene, r->triangles, r->width, r->height, r->build_ms);
        json_times(f, "primary", r->rays, &r->primary);
        json_times(f, "shadow", r->shadow_rays, &r->shadow);
        json_times(f, "diffuse", r->diffuse_rays, &r->diffuse);
        fprintf(f, "\"hits\": %u, \"blocked\": %u}%s\n", r->hits, r->blocked,
                i + 1 < count ? "," : "");
    }
    fprintf(f, "  ]\n}\n");
    if (fclose(f) != 0 || rename(tmp, path) != 0) {
        remove(tmp);
        return vkrt_error_set(err, "%s: cannot write", path);
    }
    return true;
}

static bool parse_count(const char *text, uint32_t max, uint32_t *out)
{
    char *end;
    unsigned long v = strtoul(text, &end, 10);
    if (*text < '0' || *text > '9' || *end || v == 0 || v > max)
        return false;
    *out = (uint32_t)v;
    return true;
}

static const char usage[] =
    "usage: embree-bench SCENE.cfg... [--width W --height H] [--threads N] [--json OUT.json]\n";

static bool parse_options(int argc, char **argv, options *opts)
{
    *opts = (options){.threads = 2};
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        bool has_value = i + 1 < argc;
        uint32_t threads;
        if (!strcmp(a, "--width") && has_value) {
            if (!parse_count(argv[++i], 16384, &opts->width))
                return false;
        } else if (!strcmp(a, "--height") && has_value) {
            if (!parse_count(argv[++i], 16384, &opts->height))
                return false;
        } else if (!strcmp(a, "--threads") && has_value) {
            if (!parse_count(argv[++i], max_threads, &threads))
                return false;
            opts->threads = threads;
        } else if (!strcmp(a, "--json") && has_value) {
            opts->json = argv[++i];
        } else if (a[0] == '-' || opts->scene_count == 64) {
            return false;
        } else {
            opts->scenes[opts->scene_count++] = a;
        }
    }
    return opts->scene_count > 0 && (opts->width == 0) == (opts->height == 0);
}

int main(int argc, char **argv)
{
    options opts;
    if (!parse_options(argc, argv, &opts)) {
        fputs(usage, stderr);
        return 2;
    }
    vkrt_error err = {{0}};
    /* The build's threads too, so that Embree uses no more cores than the tracing does. */
    char config[32];
    snprintf(config, sizeof config, "threads=%u", opts.threads);
    RTCDevice device = rtcNewDevice(config);
    if (!device) {
        fprintf(stderr, "embree-bench: cannot create an Embree device (error %d)\n",
                (int)rtcGetDeviceError(NULL));
        return 1;
    }
    rtcSetDeviceErrorFunction(device, embree_error, &err);
    row *rows = calloc(opts.scene_count, sizeof *rows);
    bool ok = rows != NULL;
    if (!ok)
        vkrt_error_set(&err, "out of memory");
    printf("embree %s, %u threads, rtcIntersect1/rtcOccluded1, build quality high\n",
           RTC_VERSION_STRING, opts.threads);
    printf("%-30s %9s %9s %10s %10s %10s %8s %8s\n", "scene", "triangles", "build_ms", "primary",
           "shadow", "diffuse", "hits", "blocked");
    printf("%-30s %9s %9s %10s %10s %10s %8s %8s\n", "", "", "", "Mrays/s", "Mrays/s", "Mrays/s",
           "", "");
    for (unsigned i = 0; ok && i < opts.scene_count; ++i) {
        ok = bench_scene(device, opts.scenes[i], &opts, &rows[i], &err);
        if (ok) {
            print_row(&rows[i]);
            fflush(stdout);
        }
    }
    if (ok && opts.json)
        ok = write_json(opts.json, &opts, rows, opts.scene_count, &err);
    free(rows);
    rtcReleaseDevice(device);
    if (!ok) {
        fprintf(stderr, "embree-bench: %s\n", err.msg);
        return 1;
    }
    return 0;
}
