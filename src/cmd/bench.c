/*
 * bench.c: `vkrt bench` (see bench.h).
 *
 * Rays: primary rays through the pixel centres of the scene's first camera; shadow rays from
 * each primary hit towards the first point or spot light (or against the first directional
 * light; without any, towards a point above the scene's bounds); diffuse bounce rays from each
 * primary hit in a cosine-distributed direction about the normal facing the camera (closest hit,
 * the incoherent rays of a path tracer's first bounce). Each trace is timed by
 * bench_timing.c: back to back in one submission after a 300 ms warm-up, with GPU timestamps
 * between runs; the median of the timed runs is reported, with the fastest and slowest in the
 * JSON: runs with host work between them let a GPU's clocks fall in the gaps, and then time
 * the clock changes rather than the trace.
 * Brute force traces an evenly spread subset of the rays when all of them would take too long:
 * its rate is the same per ray. The rays are made by bench_rays.c.
 */
#define _POSIX_C_SOURCE 200809L
#include "bench.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../glsl/shared.h"
#include "../bench_rays.h"
#include "../bench_timing.h"
#include "../gpu/context.h"
#include "../render/accel_cache.h"
#include "../render/renderer.h"
#include "../render/trace_api.h"
#include "../scene/scene.h"
#include "render_desc.h"

/* Ray-triangle tests brute force may spend per measurement: about a second on a CPU device, so
 * that brute force stays in a bench run of a large scene without taking it over. */
static const double brute_force_tests = 2e8;

typedef struct bench_row {
    const char *scene;
    vkrt_accel_stats accel;
    uint32_t triangles, width, height;
    uint32_t primary_rays, primary_timed, shadow_rays, shadow_timed, diffuse_timed;
    bench_times primary, shadow, diffuse;
    double primary_ms, shadow_ms, diffuse_ms; /* medians */
    uint32_t hits, blocked, diffuse_hits;
    double grid_density;
    uint32_t workgroup_size;
    bool texel_loads;                            /* traversal read through texel buffers */
    bool nested_walk;                            /* the BVH's walk in nested loops */
    bool kernel_stats;                           /* --kernel-stats: the two below are filled */
    char trace_kernel[1024], occlusion_kernel[1024]; /* the driver's statistics, JSON pairs */
    bool stats;                                  /* counted, not timed (--stats) */
    vkrt_traversal_stats primary_stats, shadow_stats, diffuse_stats;
} bench_row;

/* What one timed run does, for bench_time_trace: vkrt_renderer_trace. */
typedef struct renderer_trace {
    vkrt_renderer *r;
    const Ray *rays;
    uint32_t count;
    bool any_hit;
    Hit *hits;
} renderer_trace;

static bool run_renderer_trace(void *user, uint32_t repeats, double *ms, vkrt_error *err)
{
    renderer_trace *t = user;
    return vkrt_renderer_trace(t->r, t->rays, t->count, t->any_hit, t->hits, repeats, ms, err);
}

/* Times the trace, or with --stats (a renderer made with traversal_stats) counts its work. */
static bool measure(vkrt_renderer *r, bool stats, double warmup_ms, const Ray *rays,
                    uint32_t count, bool any_hit, Hit *hits, bench_times *times,
                    vkrt_traversal_stats *counted, vkrt_error *err)
{
    if (stats)
        return vkrt_renderer_trace_stats(r, rays, count, any_hit, hits, counted, err);
    renderer_trace t = {r, rays, count, any_hit, hits};
    return bench_time_trace(run_renderer_trace, &t, warmup_ms, times, err);
}

static bool bench_one(gpu_context *ctx, const vkrt_scene *scene, const vkrt_render_desc *desc,
                      bench_row *row, vkrt_error *err)
{
    vkrt_renderer *r;
    if (!vkrt_renderer_create(&r, ctx, scene, desc, err))
        return false;
    uint32_t pixels = desc->width * desc->height;
    Ray *primary = malloc(pixels * sizeof *primary), *shadow = malloc(pixels * sizeof *shadow);
    Hit *hits = malloc(pixels * sizeof *hits);
    bool ok = primary && shadow && hits;
    if (!ok)
        vkrt_error_set(err, "out of memory for %u rays", pixels);
    row->accel = *vkrt_renderer_accel_stats(r);
    row->texel_loads = vkrt_renderer_texel_loads(r);
    row->nested_walk = vkrt_renderer_tuning(r)->nested_walk;
    row->workgroup_size = vkrt_renderer_tuning(r)->workgroup_size;
    double warmup_ms = vkrt_renderer_tuning(r)->warmup_ms;
    row->triangles = scene->model.triangle_count;
    if (ok && row->kernel_stats)
        ok = vkrt_renderer_trace_kernel_statistics(r, row->trace_kernel, sizeof row->trace_kernel,
                                                   row->occlusion_kernel,
                                                   sizeof row->occlusion_kernel, err);
    row->width = desc->width;
    row->height = desc->height;
    uint32_t timed = pixels;
    if (row->accel.kind == VKRT_ACCEL_BRUTE) {
        double affordable = brute_force_tests / fmax(1.0, scene->model.triangle_count);
        if (affordable < timed)
            timed = affordable < 1024 ? 1024 : (uint32_t)affordable;
        if (timed > pixels)
            timed = pixels;
    }
    if (ok) {
        bench_primary_rays(&scene->cameras[0], desc->width, desc->height, primary);
        /* A subset for brute force: every stride-th ray, so it sees the whole image. */
        uint32_t stride = pixels / timed;
        for (uint32_t i = 0; stride > 1 && i < timed; ++i)
            primary[i] = primary[i * stride];
        ok = measure(r, row->stats, warmup_ms, primary, timed, false, hits, &row->primary,
                     &row->primary_stats, err);
        row->primary_ms = row->primary.median_ms;
    }
    if (ok) {
        row->primary_rays = pixels;
        row->primary_timed = timed;
        uint32_t n = bench_shadow_rays(scene, primary, hits, timed, shadow);
        for (uint32_t i = 0; i < timed; ++i)
            row->hits += hits[i].triangle != VKRT_NO_HIT;
        row->shadow_rays = n;
        row->shadow_timed = n;
        Hit *primary_hits = malloc(timed * sizeof *primary_hits);
        ok = primary_hits != NULL;
        if (ok)
            memcpy(primary_hits, hits, timed * sizeof *hits);
        ok = ok && (n == 0 || measure(r, row->stats, warmup_ms, shadow, n, true, hits, &row->shadow,
                                      &row->shadow_stats, err));
        row->shadow_ms = row->shadow.median_ms;
        for (uint32_t i = 0; ok && i < n; ++i)
            row->blocked += hits[i].triangle != VKRT_NO_HIT;
        /* The shadow buffer is free again: it holds the diffuse rays now. */
        n = ok ? bench_diffuse_rays(scene, primary, primary_hits, timed, shadow) : 0;
        row->diffuse_timed = n;
        ok = ok && (n == 0 || measure(r, row->stats, warmup_ms, shadow, n, false, hits, &row->diffuse,
                                      &row->diffuse_stats, err));
        row->diffuse_ms = row->diffuse.median_ms;
        for (uint32_t i = 0; ok && i < n; ++i)
            row->diffuse_hits += hits[i].triangle != VKRT_NO_HIT;
        free(primary_hits);
    }
    free(primary);
    free(shadow);
    free(hits);
    vkrt_renderer_destroy(r);
    return ok;
}

static double mrays(uint32_t rays, double ms)
{
    return ms > 0 ? rays / (ms * 1e3) : 0;
}

static void print_stats(FILE *out, const vkrt_traversal_stats *s)
{
    fprintf(out, " %6.1f %6.1f %5.0f%%", s->steps_per_ray, s->tests_per_ray,
            100 * s->simd_utilisation);
}

static void print_row(FILE *out, const bench_row *b)
{
    if (b->stats) {
        fprintf(out, "%-28s %-6s %9u", b->scene, vkrt_accel_name(b->accel.kind), b->triangles);
        print_stats(out, &b->primary_stats);
        print_stats(out, &b->shadow_stats);
        print_stats(out, &b->diffuse_stats);
        fprintf(out, " %8u %8u\n", b->hits, b->blocked);
        return;
    }
    fprintf(out, "%-28s %-6s %9u %9.1f %8.2f %10.4g %10.4g %10.4g %8u %8u\n", b->scene,
            vkrt_accel_name(b->accel.kind), b->triangles, b->accel.build_ms,
            b->accel.bytes / 1048576.0, mrays(b->primary_timed, b->primary_ms),
            mrays(b->shadow_timed, b->shadow_ms), mrays(b->diffuse_timed, b->diffuse_ms), b->hits,
            b->blocked);
    if (b->kernel_stats)
        fprintf(out, "  trace.comp: %s\n  occlusion.comp: %s\n", b->trace_kernel,
                b->occlusion_kernel);
}

static void print_header(FILE *out, bool stats)
{
    if (stats) {
        fprintf(out, "%-28s %-6s %9s %-20s %-20s %-20s %8s %8s\n", "scene", "accel", "triangles",
                "  primary", "  shadow", "  diffuse", "hits", "blocked");
        fprintf(out, "%-28s %-6s %9s", "", "", "");
        for (int k = 0; k < 3; ++k)
            fprintf(out, " %6s %6s %6s", "nodes", "tris", "simd");
        fprintf(out, "\n");
        return;
    }
    fprintf(out, "%-28s %-6s %9s %9s %8s %10s %10s %10s %8s %8s\n", "scene", "accel", "triangles",
            "build_ms", "MiB", "primary", "shadow", "diffuse", "hits", "blocked");
    fprintf(out, "%-28s %-6s %9s %9s %8s %10s %10s %10s %8s %8s\n", "", "", "", "", "", "Mrays/s",
            "Mrays/s", "Mrays/s", "", "");
}

static void json_stats(FILE *f, const char *kind, const vkrt_traversal_stats *s)
{
    fprintf(f, "\"%s_nodes_per_ray\": %.3f, \"%s_triangles_per_ray\": %.3f, "
               "\"%s_simd_utilisation\": %.4f, ",
            kind, s->steps_per_ray, kind, s->tests_per_ray, kind, s->simd_utilisation);
}

static bool write_json(const char *path, const gpu_context *ctx, const bench_row *rows,
                       uint32_t count, vkrt_error *err)
{
    char tmp[4200];
    snprintf(tmp, sizeof tmp, "%s.tmp", path);
    FILE *f = fopen(tmp, "w");
    if (!f)
        return vkrt_error_set(err, "%s: cannot write", path);
    const VkPhysicalDeviceProperties *p = &ctx->properties;
    fprintf(f, "{\n  \"device\": \"%s\",\n  \"driver_version\": %u,\n  \"api_version\": \"%u.%u.%u\",\n",
            p->deviceName, p->driverVersion, VK_API_VERSION_MAJOR(p->apiVersion),
            VK_API_VERSION_MINOR(p->apiVersion), VK_API_VERSION_PATCH(p->apiVersion));
    fprintf(f, "  \"warmup_ms\": %.0f,\n  \"timed_runs\": %d,\n  \"statistic\": \"median\",\n"
               "  \"results\": [\n", vkrt_tuning_for(ctx, NULL).warmup_ms, BENCH_TIMED_RUNS);
    for (uint32_t i = 0; i < count; ++i) {
        const bench_row *b = &rows[i];
        fprintf(f,
                "    {\"workgroup_size\": %u, \"bvh_max_leaf\": %u, "
                "\"bvh_traversal_cost\": %g, \"kd_traversal_cost\": %g, \"sah_cost\": %.3f, "
                "\"references\": %u, \"stats\": %s, "
                "\"loads\": \"%s\", \"walk\": \"%s\", ",
                b->workgroup_size, b->accel.bvh_max_leaf, (double)b->accel.bvh_traversal_cost,
                (double)b->accel.kd_traversal_cost, b->accel.sah_cost, b->accel.references,
                b->stats ? "true" : "false",
                b->texel_loads ? "texel" : "storage", b->nested_walk ? "nested" : "one-loop");
        if (b->kernel_stats)
            fprintf(f, "\"trace_kernel\": {%s}, \"occlusion_kernel\": {%s}, ", b->trace_kernel,
                    b->occlusion_kernel);
        if (b->stats) {
            json_stats(f, "primary", &b->primary_stats);
            json_stats(f, "shadow", &b->shadow_stats);
            json_stats(f, "diffuse", &b->diffuse_stats);
        }
        fprintf(f,
                "\"scene\": \"%s\", \"accel\": \"%s\", \"reason\": \"%s\", \"triangles\": %u, "
                "\"width\": %u, \"height\": %u, \"build_ms\": %.3f, \"bytes\": %zu, "
                "\"nodes_or_cells\": %u, \"bvh_width\": %u, \"triangles_per_leaf\": %.3f, "
                "\"primary_rays_timed\": %u, \"primary_ms\": %.4f, \"primary_ms_min\": %.4f, "
                "\"primary_ms_max\": %.4f, \"primary_mrays_per_s\": %.3f, "
                "\"shadow_rays_timed\": %u, \"shadow_ms\": %.4f, \"shadow_ms_min\": %.4f, "
                "\"shadow_ms_max\": %.4f, \"shadow_mrays_per_s\": %.3f, "
                "\"diffuse_rays_timed\": %u, \"diffuse_ms\": %.4f, \"diffuse_ms_min\": %.4f, "
                "\"diffuse_ms_max\": %.4f, \"diffuse_mrays_per_s\": %.3f, "
                "\"diffuse_hits\": %u, \"hits\": %u, \"blocked\": %u, \"grid_density\": %g}%s\n",
                b->scene, vkrt_accel_name(b->accel.kind), b->accel.reason, b->triangles, b->width,
                b->height, b->accel.build_ms, b->accel.bytes, b->accel.nodes, b->accel.bvh_width,
                b->accel.triangles_per_leaf, b->primary_timed, b->primary_ms, b->primary.min_ms,
                b->primary.max_ms, mrays(b->primary_timed, b->primary_ms), b->shadow_timed,
                b->shadow_ms, b->shadow.min_ms, b->shadow.max_ms,
                mrays(b->shadow_timed, b->shadow_ms), b->diffuse_timed, b->diffuse_ms,
                b->diffuse.min_ms, b->diffuse.max_ms, mrays(b->diffuse_timed, b->diffuse_ms),
                b->diffuse_hits, b->hits, b->blocked, b->grid_density,
                i + 1 < count ? "," : "");
    }
    fprintf(f, "  ]\n}\n");
    if (fclose(f) != 0 || rename(tmp, path) != 0) {
        remove(tmp);
        return vkrt_error_set(err, "%s: cannot write", path);
    }
    return true;
}

int vkrt_cmd_bench(const vkrt_command_line *cl)
{
    const vkrt_bench_options *opts = &cl->bench;
    vkrt_error err = {{0}};
    /* Its build_ms compares builds and thread counts: every structure is built, none read from
     * the structure cache. */
    vkrt_accel_cache_disable();
    gpu_context ctx;
    gpu_context_desc ctx_desc = {.device_index = opts->common.device, .validation = opts->common.validation,
                                 .pipeline_statistics = opts->kernel_stats};
    if (!gpu_context_create(&ctx, &ctx_desc, &err)) {
        fprintf(stderr, "vkrt: %s\n", err.msg);
        return 1;
    }
    static const vkrt_accel_kind all[] = {VKRT_ACCEL_BRUTE, VKRT_ACCEL_GRID, VKRT_ACCEL_BVH,
                                          VKRT_ACCEL_KDTREE};
    const vkrt_accel_kind *kinds = opts->common.accel_given ? &opts->common.accel : all;
    uint32_t kind_count = opts->common.accel_given ? 1 : (uint32_t)(sizeof all / sizeof *all);
    bench_row *rows = calloc((size_t)opts->scene_count * kind_count, sizeof *rows);
    uint32_t row_count = 0;
    bool ok = rows != NULL;
    printf("device: %s\n", ctx.properties.deviceName);
    print_header(stdout, opts->stats);
    for (uint32_t s = 0; ok && s < opts->scene_count; ++s) {
        vkrt_scene scene;
        /* Tracing reads no material or texture: load the geometry alone, unless asked to load
         * the whole scene (to see whether what a render uploads besides changes tracing). */
        if (!(opts->whole_scene ? vkrt_scene_load(opts->scene_paths[s], &scene, &err)
                                : vkrt_scene_load_geometry(opts->scene_paths[s], &scene, &err))) {
            ok = false;
            break;
        }
        vkrt_render_desc desc = vkrt_render_desc_for(&scene.config, cl);
        for (uint32_t k = 0; ok && k < kind_count; ++k) {
            bench_row *row = &rows[row_count];
            row->scene = opts->scene_paths[s];
            row->grid_density = opts->tuning.grid_density;
            row->kernel_stats = opts->kernel_stats;
            row->stats = opts->stats;
            desc.accel = kinds[k];
            ok = bench_one(&ctx, &scene, &desc, row, &err);
            if (ok) {
                print_row(stdout, row);
                if (opts->common.verbose && row->accel.kind == VKRT_ACCEL_BVH)
                    printf("  %s; SAH cost %.2f, %u references\n", row->accel.reason,
                           (double)row->accel.sah_cost, row->accel.references);
                fflush(stdout);
                ++row_count;
            }
        }
        vkrt_scene_free(&scene);
    }
    if (ok && opts->json)
        ok = write_json(opts->json, &ctx, rows, row_count, &err);
    free(rows);
    if (!gpu_context_close(&ctx, ok, &err)) {
        fprintf(stderr, "vkrt: %s\n", err.msg);
        return 1;
    }
    return 0;
}
