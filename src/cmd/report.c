/*
 * report.c: what `vkrt render` prints on stderr (report.h).
 */
#define _POSIX_C_SOURCE 200809L
#include "report.h"

#include <sys/resource.h>

#include "../gpu/pipeline.h"
#include "../gpu/spirv_cache.h"

void report_accel_stats(FILE *out, const vkrt_accel_stats *s)
{
    /* A structure from the cache (render/accel_cache.h) was read, not built, in build_ms. */
    const char *built = s->from_cache ? "read from the structure cache in" : "built in";
    fprintf(out, "vkrt: accel %s: %s\n", vkrt_accel_name(s->kind), s->reason);
    if (s->two_level)
        fprintf(out,
                "vkrt: instancing: %u instances of %u meshes, %llu triangles instanced, %u "
                "unique on the device\n",
                s->instances, s->meshes, (unsigned long long)s->instanced_triangles, s->triangles);
    if (s->kind == VKRT_ACCEL_BVH)
        fprintf(out,
                "vkrt: BVH: %u nodes, %u leaves, %u references, %.2f per leaf, depth %u, SAH cost "
                "%.1f, %.2f MiB, %s %.1f ms\n",
                s->nodes, s->leaves, s->references, s->triangles_per_leaf, s->max_depth,
                s->sah_cost, s->bytes / 1048576.0, built, s->build_ms);
    else if (s->kind == VKRT_ACCEL_KDTREE)
        fprintf(out,
                "vkrt: kd-tree: %u nodes, %u leaves (%u empty), %.2f triangles per non-empty "
                "leaf, %u references, depth %u, SAH cost %.1f, %.2f MiB, %s %.1f ms\n",
                s->nodes, s->leaves, s->empty_leaves, s->triangles_per_leaf, s->references,
                s->max_depth, s->sah_cost, s->bytes / 1048576.0, built, s->build_ms);
    else if (s->kind == VKRT_ACCEL_GRID)
        fprintf(out,
                "vkrt: grid: %ux%ux%u = %u cells, %u occupied, %.2f triangles per occupied cell, "
                "fullest cell %u, %.2f MiB, %s %.1f ms\n",
                s->grid_dims[0], s->grid_dims[1], s->grid_dims[2], s->nodes, s->leaves,
                s->triangles_per_leaf, s->max_cell_refs, s->bytes / 1048576.0, built, s->build_ms);
    if (s->choose_ms > 0)
        fprintf(out, "vkrt: choosing took %.1f ms\n", s->choose_ms);
}

void report_kernel_cache(FILE *out)
{
    uint32_t loaded, compiled, stored;
    gpu_spirv_cache_counts(&loaded, &compiled, &stored);
    char dir[4096];
    uint32_t pipelines_loaded, pipelines_stored;
    gpu_pipeline_cache_counts(&pipelines_loaded, &pipelines_stored);
    if (gpu_spirv_cache_dir(dir, sizeof dir))
        fprintf(out,
                "vkrt: kernels: %u compiled, %u from the cache in %s, %u stored there; "
                "pipelines: %u from the driver's data there, %u stored%s\n",
                compiled, loaded, dir, stored, pipelines_loaded, pipelines_stored,
                compiled > stored ? " (the cache could not be written: is it a file, read-only "
                                    "or full?)"
                                  : "");
    else
        fprintf(out,
                "vkrt: kernels: %u compiled (no kernel cache: --no-cache, VKRT_CACHE_DIR is empty, "
                "or there is no HOME)\n",
                compiled);
}

void report_scene_cache(FILE *out, const vkrt_scene_cache_report *c)
{
    if (c->outcome == VKRT_SCENE_CACHE_OFF)
        return;
    fprintf(out, "vkrt: scene cache: ");
    if (c->rejected[0])
        fprintf(out, "the entry found was not used (%s); ", c->rejected);
    if (c->outcome == VKRT_SCENE_CACHE_HIT)
        fprintf(out, "model read in %.0f ms", c->read_ms);
    else if (c->outcome == VKRT_SCENE_CACHE_STORED)
        fprintf(out, "scene file parsed, model stored in %.0f ms", c->store_ms);
    else if (c->outcome == VKRT_SCENE_CACHE_STORING)
        fprintf(out, "scene file parsed, model being stored on a thread");
    else
        fprintf(out, "scene file parsed, not stored: %s", c->why);
    fprintf(out, "; the scene file's key hashed in %.0f ms\n", c->hash_ms);
}

void report_progress(FILE *out, uint32_t done, uint32_t total, uint32_t rendered, double seconds,
                     const char *path, bool terminal)
{
    double rate = seconds > 0 ? rendered / seconds : 0;
    char left[64] = "";
    if (rate > 0 && done < total)
        snprintf(left, sizeof left, ", about %.0f s left", (total - done) / rate);
    fprintf(out, "%svkrt: %u of %u frames done (%s), %.2f frames/s%s%s", terminal ? "\r" : "", done,
            total, path, rate, left, terminal ? "\033[K" : "\n");
    fflush(out);
}

void report_memory(FILE *out, const vkrt_renderer *renderer, const gpu_context *ctx,
                   const vkrt_scene *scene)
{
    vkrt_renderer_memory m = vkrt_renderer_memory_use(renderer);
    const double MiB = 1048576.0;
    /* Under a two-level BVH the device holds each mesh once: say how many triangles that is. */
    const vkrt_accel_stats *accel = vkrt_renderer_accel_stats(renderer);
    char counts[128] = "";
    if (accel->two_level)
        snprintf(counts, sizeof counts, " (%u unique of %llu instanced)", accel->triangles,
                 (unsigned long long)accel->instanced_triangles);
    fprintf(out,
            "vkrt: device memory: triangles %.1f MiB%s, nodes %.1f MiB, textures %.1f MiB, rays "
            "%.1f MiB, image %.1f MiB, other %.1f MiB: %.1f MiB of the device's %.1f MiB\n",
            m.triangles / MiB, counts, m.nodes / MiB, m.textures / MiB, m.rays / MiB,
            m.image / MiB, m.other / MiB, m.total / MiB, ctx->memory_limit / MiB);
    char split[256];
    vkrt_renderer_split_text(renderer, split, sizeof split);
    fprintf(out, "vkrt: arrays split past %llu bytes (%s): %s\n",
            (unsigned long long)ctx->split_bytes, gpu_buffer_limit_name(ctx, ctx->split_bytes),
            *split ? split : "none");
    struct rusage usage;
    double peak = getrusage(RUSAGE_SELF, &usage) == 0 ? usage.ru_maxrss / 1024.0 : 0.0;
    fprintf(out,
            "vkrt: host memory: mesh %.1f MiB (positions, normals, texture coordinates, "
            "materials), peak resident %.1f MiB\n",
            vkrt_model_host_bytes(&scene->model) / MiB, peak);
}

void report_startup(FILE *out, const startup_clock *t, const vkrt_scene *scene,
                    const vkrt_accel_stats *accel, const vkrt_renderer_startup *steps)
{
    fprintf(out,
            "vkrt: start-up: scene %.0f ms (scene file %.0f ms, materials and textures %.0f "
            "ms), Vulkan %.0f ms, renderer %.0f ms (structure %.0f ms, of which %s %.0f; "
            "triangles' upload %.0f, materials %.0f, lights %.0f, buffers %.0f, %s %.0f), first "
            "frame %.0f ms, its image written %.0f ms; %.0f ms since main\n",
            t->scene - t->main, scene->model_ms, scene->materials_ms, t->vulkan - t->scene,
            t->renderer - t->vulkan,
            steps->structure_ms, accel->from_cache ? "reading it from the cache" : "building",
            accel->build_ms + accel->choose_ms, steps->geometry_ms, steps->materials_ms,
            steps->lights_ms, steps->buffers_ms,
            steps->kernels_recompiled ? "kernels compiled after them"
                                      : "waiting for the kernels compiled alongside",
            steps->kernels_ms, t->frame - t->renderer, t->image - t->frame, t->image - t->main);
}

void report_pool_summary(const vkrt_render_options *opts, const vkrt_scene *scene,
                         uint32_t frame_count, const vkrt_pool_result *r)
{
    for (uint32_t w = 0; w < r->worker_count; ++w) {
        const vkrt_pool_worker *k = &r->workers[w];
        if (k->failed)
            fprintf(stderr, "vkrt: device %d (%s) failed after %u frame%s: %s%s\n", k->device,
                    k->device_name[0] ? k->device_name : "not started", k->frames,
                    k->frames == 1 ? "" : "s", k->failure,
                    !k->lost_frame        ? ""
                    : k->lost_frames == 1 ? "; the frame it held went back to the others"
                                          : "; the frames it held went back to the others");
    }
    if (opts->common.quiet)
        return;
    double gpu_seconds = 0;
    uint64_t rays = 0;
    for (uint32_t w = 0; w < r->worker_count; ++w) {
        const vkrt_pool_worker *k = &r->workers[w];
        gpu_seconds += k->gpu_seconds;
        rays += k->rays;
        fprintf(stderr, "vkrt: device %d (%s): %u frame%s, %.1f ms/frame\n", k->device,
                k->device_name[0] ? k->device_name : "not started", k->frames,
                k->frames == 1 ? "" : "s", k->frames ? 1e3 * k->seconds / k->frames : 0.0);
    }
    /* The rate once a device was ready: what a longer flythrough approaches. */
    double rendering = r->seconds - r->start_seconds;
    fprintf(stderr,
            "vkrt: %u worker%s | %u triangles | %u of %u frame%s in %.2f s, the first device "
            "ready after %.2f s | %.2f frames/s after that | %.3g Mrays/s per device\n",
            r->worker_count, r->worker_count == 1 ? "" : "s", scene->model.triangle_count,
            r->rendered, frame_count, frame_count == 1 ? "" : "s", r->seconds, r->start_seconds,
            rendering > 0 ? r->rendered / rendering : 0.0,
            gpu_seconds > 0 ? rays / gpu_seconds * 1e-6 : 0.0);
    if (!opts->common.verbose) /* else the first worker printed its choices at its start */
        fputs(r->about, stderr);
}

void report_render_summary(const vkrt_render_options *opts, vkrt_scene *scene,
                           const render_totals *totals, const startup_clock *clock)
{
    if (opts->common.quiet)
        return;
    uint32_t rendered = totals->rendered;
    fprintf(stderr,
            "vkrt: %s | %u triangles | accel %s | %u frame%s | %.1f ms/frame | %.3g Mrays/s\n",
            totals->device, scene->model.triangle_count, vkrt_accel_name(totals->accel.kind),
            rendered, rendered == 1 ? "" : "s", rendered ? 1e3 * totals->seconds / rendered : 0.0,
            totals->seconds > 0 ? totals->rays / totals->seconds * 1e-6 : 0.0);
    if (opts->common.verbose && clock->image)
        report_startup(stderr, clock, scene, &totals->accel, &totals->startup);
    if (opts->common.verbose && scene->model_cache.outcome == VKRT_SCENE_CACHE_STORING) {
        /* Said "being stored" before the first frame: now how it ended. */
        vkrt_scene_cache_finish(&scene->model_cache);
        report_scene_cache(stderr, &scene->model_cache);
    }
    if (!opts->common.verbose) {
        fprintf(stderr, "vkrt: accel %s: %s\n", vkrt_accel_name(totals->accel.kind),
                totals->accel.reason);
        fprintf(stderr, "vkrt: integrator %s: %s\n", vkrt_integrator_name(totals->integrator),
                totals->integrator_reason);
    }
}
