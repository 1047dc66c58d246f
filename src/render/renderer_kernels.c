/*
 * renderer_kernels.c: the wave kernels compiled for one scene and device. Every kernel gets the
 * same specialization constants (glsl/shared.h's VKRT_SPEC_*): what the scene has (normals,
 * texture coordinates), which structure traversal walks and how (the tuning's choices), so each
 * choice is dead code elimination in the driver rather than a branch at run time. The integrator
 * is one of them (VKRT_SPEC_INTEGRATOR): every kernel is the same file for both. light.comp,
 * count.comp and shade.comp include the material module generated from the materials the scene
 * uses.
 *
 * Compiling is glslang (GLSL to SPIR-V) and then the driver (vkCreateComputePipelines, which
 * compiles to machine code): seconds on a cold cache, most of a small scene's start. So each
 * kernel compiles on a thread of its own, started before the structure is built, for the plan
 * predicted from what is known then (renderer_kernels_start); the
 * renderer joins them after its uploads, when the plan is known for certain
 * (renderer_kernels_finish). A prediction that turns out wrong (a structure or an array split
 * that only the build could tell) costs the kernels compiled once more, as they were before.
 */
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "../gpu/shader.h"
#include "kernel_sources.h"
#include "renderer_private.h"

/* What every wave kernel may use beyond core GLSL on this device: subgroup operations (count.comp
 * reserves ray slots with one atomic per subgroup with them, one per ray without; the trace
 * kernels' statistics need them, and are not built without). */
#define SUBGROUPS                                                                                  \
    "#extension GL_KHR_shader_subgroup_arithmetic : require\n"                                     \
    "#extension GL_KHR_shader_subgroup_ballot : require\n"                                         \
    "#extension GL_KHR_shader_subgroup_vote : require\n"                                           \
    "#define VKRT_SUBGROUPS 1\n"
/* A scene with an array split over several buffers reads it through device addresses
 * (lib/bindings.glsl); every other scene's kernels go without, as they were. */
#define SPLIT_ARRAYS                                                                               \
    "#extension GL_EXT_buffer_reference : require\n"                                               \
    "#extension GL_EXT_buffer_reference_uvec2 : require\n"                                         \
    "#define VKRT_SPLIT_ARRAYS 1\n"

static const char *kernel_preamble(const gpu_context *ctx, bool split)
{
    if (split)
        return ctx->subgroup_arithmetic ? SUBGROUPS SPLIT_ARRAYS : SPLIT_ARRAYS;
    return ctx->subgroup_arithmetic ? SUBGROUPS : "";
}

/* The renderer's kernels, in the order they are compiled and their errors reported. */
enum kernel_slot {
    SLOT_RAYGEN,
    SLOT_TRACE,
    SLOT_LIGHT,
    SLOT_PREPARE,
    SLOT_COUNT,
    SLOT_SHADE,
    SLOT_ORDER,
    SLOT_ADAPT,
    SLOT_ADAPT_DISPATCH,
    SLOT_TOTAL
};

static gpu_pipeline *slot_pipeline(vkrt_renderer *r, uint32_t slot)
{
    gpu_pipeline *pipelines[SLOT_TOTAL] = {
        [SLOT_RAYGEN] = &r->raygen,   [SLOT_TRACE] = &r->trace, [SLOT_LIGHT] = &r->light,
        [SLOT_PREPARE] = &r->prepare, [SLOT_COUNT] = &r->count, [SLOT_SHADE] = &r->shade,
        [SLOT_ORDER] = &r->order,     [SLOT_ADAPT] = &r->adapt,
        [SLOT_ADAPT_DISPATCH] = &r->adapt_dispatch,
    };
    return pipelines[slot];
}

/* One kernel's compile: its source, what it is compiled for, and what came of it. */
typedef struct kernel_job {
    const renderer_kernels *owner;
    const char *path;         /* glsl/ name; NULL: the plan has no such kernel */
    bool material;            /* includes the generated material module */
    bool single;              /* one invocation per workgroup (prepare, adapt_dispatch) */
    pthread_t thread;
    bool started;             /* on a thread of its own, to be joined */
    bool ok;
    gpu_pipeline pipeline;
    vkrt_error err;
} kernel_job;

struct renderer_kernels {
    gpu_context *ctx;
    const gpu_storage_set *set;
    const vkrt_material_kernel *kernel;
    const vkrt_scene_materials *mats;
    renderer_kernel_plan plan;
    kernel_job jobs[SLOT_TOTAL];
};

/* GLSL to SPIR-V of a kernel that does not include the material module. */
static bool compile_plain(const char *path, const char *preamble, uint32_t **spirv, size_t *words,
                          vkrt_error *err)
{
    gpu_shader_sources sources = {
        .lookup = vkrt_kernel_source_lookup,
        .display_prefix = "glsl/",
        .preamble = preamble,
    };
    return gpu_shader_compile(&sources, path, spirv, words, err);
}

static void compile_job(kernel_job *job)
{
    const renderer_kernels *k = job->owner;
    const renderer_kernel_plan *plan = &k->plan;
    const char *preamble = kernel_preamble(k->ctx, plan->split);
    uint32_t *spirv = NULL;
    size_t words = 0;
    bool ok = job->material ? vkrt_material_kernel_compile(k->kernel, k->mats, job->path, preamble,
                                                           &spirv, &words, &job->err)
                            : compile_plain(job->path, preamble, &spirv, &words, &job->err);
    ok = ok && gpu_pipeline_create(k->ctx, &job->pipeline, k->set, spirv, words,
                                   job->single ? 1 : plan->workgroup_size, plan->constants,
                                   RENDERER_KERNEL_CONSTANTS, job->path, &job->err);
    free(spirv);
    job->ok = ok;
}

static void *compile_thread(void *arg)
{
    compile_job(arg);
    return NULL;
}

bool renderer_kernels_start(vkrt_renderer *r, const renderer_kernel_plan *plan,
                            const vkrt_material_kernel *kernel, const vkrt_scene_materials *mats,
                            vkrt_error *err)
{
    renderer_kernels *k = calloc(1, sizeof *k);
    if (!k)
        return vkrt_error_set(err, "out of memory");
    *k = (renderer_kernels){r->ctx, &r->set, kernel, mats, *plan, {{0}}};
    /* occlusion.comp is not among them: only the trace API uses it (trace_api.c compiles it on
     * first use, renderer_kernels_compile_occlusion). */
    const struct {
        const char *path;
        bool material, single;
    } kernels[SLOT_TOTAL] = {
        [SLOT_RAYGEN] = {"raygen.comp", false, false},
        [SLOT_TRACE] = {"trace.comp", false, false},
        /* Whitted's shadow rays for the materials to read, or the path tracer's next-event
         * estimation, which evaluates the materials' BSDFs itself. */
        [SLOT_LIGHT] = {"light.comp", true, false},
        /* prepare.comp writes the next depth's indirect dispatch: one invocation. */
        [SLOT_PREPARE] = {"prepare.comp", false, true},
        [SLOT_COUNT] = {"count.comp", true, false},
        [SLOT_SHADE] = {"shade.comp", true, false},
        /* Hits grouped by shader only where the renderer groups them (tuning.c). */
        [SLOT_ORDER] = {plan->material_order ? "order.comp" : NULL, false, false},
        /* Adaptive sampling's kernels only where there is a target error. */
        [SLOT_ADAPT] = {plan->adaptive ? "adapt.comp" : NULL, false, false},
        [SLOT_ADAPT_DISPATCH] = {plan->adaptive ? "adapt_dispatch.comp" : NULL, false, true},
    };
    for (uint32_t s = 0; s < SLOT_TOTAL; ++s) {
        kernel_job *job = &k->jobs[s];
        *job = (kernel_job){.owner = k, .path = kernels[s].path,
                            .material = kernels[s].material, .single = kernels[s].single};
        /* A thread that cannot start costs speed only: its kernel compiles at the join. */
        job->started = job->path && pthread_create(&job->thread, NULL, compile_thread, job) == 0;
    }
    r->kernels = k;
    return true;
}

/* Waits for every kernel's compile (compiling on this thread those that got none); returns the
 * jobs, taken from r. */
static renderer_kernels *join(vkrt_renderer *r)
{
    renderer_kernels *k = r->kernels;
    r->kernels = NULL;
    for (uint32_t s = 0; k && s < SLOT_TOTAL; ++s) {
        kernel_job *job = &k->jobs[s];
        if (job->started)
            pthread_join(job->thread, NULL);
        else if (job->path)
            compile_job(job);
    }
    return k;
}

static void discard(vkrt_renderer *r, renderer_kernels *k)
{
    for (uint32_t s = 0; k && s < SLOT_TOTAL; ++s)
        gpu_pipeline_destroy(r->ctx, &k->jobs[s].pipeline);
    free(k);
}

void renderer_kernels_abandon(vkrt_renderer *r)
{
    discard(r, join(r));
}

static bool same_plan(const renderer_kernel_plan *a, const renderer_kernel_plan *b)
{
    return a->split == b->split && a->adaptive == b->adaptive &&
           a->material_order == b->material_order &&
           a->workgroup_size == b->workgroup_size &&
           memcmp(a->constants, b->constants, sizeof a->constants) == 0;
}

bool renderer_kernels_finish(vkrt_renderer *r, const renderer_kernel_plan *plan, bool *predicted,
                             vkrt_error *err)
{
    renderer_kernels *k = join(r);
    if (!k)
        return vkrt_error_set(err, "the kernels were not started");
    *predicted = same_plan(&k->plan, plan);
    if (!*predicted) {
        /* Compiled for another structure or array layout than the one built: again, for it. */
        const vkrt_material_kernel *kernel = k->kernel;
        const vkrt_scene_materials *mats = k->mats;
        discard(r, k);
        if (!renderer_kernels_start(r, plan, kernel, mats, err))
            return false;
        k = join(r);
    }
    /* The first error in the kernels' order, as when they compiled one after another. */
    for (uint32_t s = 0; s < SLOT_TOTAL; ++s)
        if (k->jobs[s].path && !k->jobs[s].ok) {
            *err = k->jobs[s].err;
            discard(r, k);
            return false;
        }
    for (uint32_t s = 0; s < SLOT_TOTAL; ++s) {
        *slot_pipeline(r, s) = k->jobs[s].pipeline;
        k->jobs[s].pipeline = (gpu_pipeline){0};
    }
    discard(r, k);
    return true;
}

bool renderer_kernels_compile_occlusion(vkrt_renderer *r, vkrt_error *err)
{
    if (r->occlusion.pipeline)
        return true;
    uint32_t *spirv = NULL;
    size_t words = 0;
    /* The trace kernel's plan: the same structure, walk and arrays. */
    bool ok = compile_plain("occlusion.comp", kernel_preamble(r->ctx, r->split), &spirv, &words,
                            err) &&
              gpu_pipeline_create_alike(r->ctx, &r->occlusion, &r->set, spirv, words, &r->trace,
                                        "occlusion.comp", err);
    free(spirv);
    return ok;
}

static uint32_t traverse_kind(vkrt_accel_kind kind, bool two_level)
{
    return two_level                   ? VKRT_TRAVERSE_BVH_INSTANCED
           : kind == VKRT_ACCEL_BVH    ? VKRT_TRAVERSE_BVH
           : kind == VKRT_ACCEL_GRID   ? VKRT_TRAVERSE_GRID
           : kind == VKRT_ACCEL_KDTREE ? VKRT_TRAVERSE_KDTREE
                                       : VKRT_TRAVERSE_BRUTE;
}

void renderer_kernel_plan_make(const vkrt_renderer *r, const renderer_data_layout *layout,
                               bool has_normals, bool has_texcoords, bool traversal_stats,
                               renderer_kernel_plan *plan)
{
    uint32_t workgroup_size = r->tuning.workgroup_size;
    /* A float specialization constant travels as its 32 bits. */
    uint32_t clamp_bits, target_bits;
    memcpy(&clamp_bits, &r->clamp, sizeof clamp_bits);
    memcpy(&target_bits, &r->target_error, sizeof target_bits);
    const uint32_t *shift = layout->split_shift;
    const gpu_spec_constant constants[RENDERER_KERNEL_CONSTANTS] = {
        {VKRT_SPEC_HAS_NORMALS, has_normals},
        {VKRT_SPEC_ACCEL_KIND, traverse_kind(layout->kind, layout->two_level)},
        {VKRT_SPEC_HAS_TEXCOORDS, has_texcoords},
        {VKRT_SPEC_WAVE_WORKGROUP, workgroup_size},
        {VKRT_SPEC_TRAVERSAL_STATS, traversal_stats},
        {VKRT_SPEC_BVH_WIDTH, layout->bvh_width},
        {VKRT_SPEC_TEXEL_LOADS, layout->texel_loads},
        {VKRT_SPEC_NESTED_WALK, r->tuning.nested_walk},
        {VKRT_SPEC_INTEGRATOR,
         r->integrator == VKRT_INTEGRATOR_PATH ? VKRT_INTEGRATE_PATH : VKRT_INTEGRATE_WHITTED},
        {VKRT_SPEC_LIGHT_SAMPLING, r->light_sampling},
        {VKRT_SPEC_HAS_CUTOUTS, r->has_cutouts},
        {VKRT_SPEC_EMITTER_LIGHT, layout->emitter_light},
        {VKRT_SPEC_CLAMP, clamp_bits},
        {VKRT_SPEC_SURFACE_MAPS, r->surface_maps},
        {VKRT_SPEC_TARGET_ERROR, target_bits},
        /* How each array is split (0: one buffer); read only where one is. */
        {VKRT_SPEC_SPLIT_TRIANGLES, shift[VKRT_SPLIT_TRIANGLES]},
        {VKRT_SPEC_SPLIT_NORMALS, shift[VKRT_SPLIT_NORMALS]},
        {VKRT_SPEC_SPLIT_TEXCOORDS, shift[VKRT_SPLIT_TEXCOORDS]},
        {VKRT_SPEC_SPLIT_TRIANGLE_MATERIAL, shift[VKRT_SPLIT_TRIANGLE_MATERIAL]},
        {VKRT_SPEC_SPLIT_NODES, shift[VKRT_SPLIT_NODES]},
        {VKRT_SPEC_SPLIT_REFS, shift[VKRT_SPLIT_REFS]},
        {VKRT_SPEC_SPLIT_TEXELS, shift[VKRT_SPLIT_TEXELS]},
        {VKRT_SPEC_MATERIAL_ORDER, r->material_order},
        {VKRT_SPEC_AOVS, r->aovs},
    };
    memset(plan, 0, sizeof *plan);
    bool split = false;
    for (uint32_t a = 0; a < VKRT_SPLIT_ARRAY_COUNT; ++a)
        split = split || shift[a] != 0;
    plan->split = split;
    plan->adaptive = r->target_error > 0;
    plan->material_order = r->material_order;
    plan->workgroup_size = workgroup_size;
    memcpy(plan->constants, constants, sizeof constants);
}
