/*
 * tuning.c: the device-dependent defaults (see tuning.h), each with the measurement behind it.
 */
#include "tuning.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../test_hooks.h"

/* 64 invocations fill two NVIDIA warps or one AMD wave64 and suit lavapipe's 8-wide SIMD. */
enum { default_workgroup_size = 64 };

/* Children per node of the BVH's GPU layout. On GPUs the pairs of two float boxes outran the
 * quantized 4-wide nodes on every scene measured; on CPU devices (lavapipe, whose texel fetches
 * cost more than the nodes' decoding) the 4-wide nodes were the faster with the nested walk on
 * every scene's primary rays. */
enum { gpu_bvh_width = 2, cpu_bvh_width = 4 };

/* On a GPU a triangle test (the watertight one) costs more against a node step than the SAH's
 * usual ratio says: smaller leaves (at most 2 triangles, a node costing half a triangle test)
 * traced Sponza's diffuse rays 1.13x as fast on an H200 and no scene's rays more than about 3%
 * slower. CPU devices keep bvh.h's defaults: one run on lavapipe showed no difference beyond
 * noise, and that tree is the smaller. */
enum { gpu_bvh_max_leaf = 2 };
static const float gpu_bvh_traversal_cost = 0.5f;

/* Mesa's llvmpipe ends an invocation's loops after 65535 iterations in all: brute force goes in
 * blocks of triangles below that, and a brute-force light kernel that would need more is refused
 * (renderer_frame.c). Other devices have no such limit; the block only splits dispatches. */
enum { llvmpipe_loop_budget = 65535, brute_force_block = 32768 };

/* Camera rays per sample pass. A pass is some 5 dispatches per depth whatever its size, and a
 * small image's passes left the H200 idle between them: a 256x256 Cornell box path-traced at 64
 * spp, one pass per sample, took 60 ms, the same samples as one 512x512 frame 17 ms
 * (research/results/path-h200/). 2^21 rays is a 1080p image's pass, which fills the GPU;
 * lavapipe, whose dispatches cost little next to its tracing, takes a smaller one (its ray
 * buffers stay within its 128 MiB storage buffers). */
enum { gpu_wave_rays = 1 << 21, cpu_wave_rays = 1 << 16 };

/* A cast ray whose importance (largest channel) falls under this is not traced: it could change
 * its pixel by less than a thousandth of the light that reaches it. */
static const float default_min_importance = 1e-3f;

bool vkrt_device_is_cpu(const gpu_context *ctx)
{
    return ctx->properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
}

vkrt_tuning vkrt_tuning_choose(bool cpu_device, bool llvmpipe, const vkrt_tuning_overrides *o)
{
    static const vkrt_tuning_overrides none = {0};
    if (!o)
        o = &none;
    vkrt_tuning t = {
        .cpu_device = cpu_device,
        .workgroup_size = o->workgroup_size ? o->workgroup_size : default_workgroup_size,
        .grid_density = o->grid_density,
        .bvh_width = o->bvh_width ? o->bvh_width : cpu_device ? cpu_bvh_width : gpu_bvh_width,
        .bvh_max_leaf = o->bvh_max_leaf ? o->bvh_max_leaf : cpu_device ? 0 : gpu_bvh_max_leaf,
        .bvh_traversal_cost = o->bvh_traversal_cost > 0 ? o->bvh_traversal_cost
                              : cpu_device              ? 0
                                                        : gpu_bvh_traversal_cost,
        .bvh_spatial_budget = o->bvh_spatial_budget,
        .kd_traversal_cost = o->kd_traversal_cost,
        /* Mesa's llvmpipe loads a storage buffer one lane and one word at a time, each behind a
         * bounds check and a branch, and a texel buffer with vector gathers: texel loads made
         * lavapipe's traversal 3.4-6x faster. On GPUs storage loads were as fast or faster. */
        .texel_loads = o->loads == VKRT_LOADS_TEXEL || (o->loads == VKRT_LOADS_DEFAULT && cpu_device),
        .texel_loads_required = o->loads == VKRT_LOADS_TEXEL,
        /* llvmpipe runs both sides of every branch any lane takes, so the walk with inner nodes
         * and leaves in loops of their own was faster there; one loop was faster on GPUs. */
        .nested_walk = o->walk == VKRT_WALK_NESTED || (o->walk == VKRT_WALK_DEFAULT && cpu_device),
        .loop_budget = llvmpipe ? llvmpipe_loop_budget : 0,
        .brute_force_block = brute_force_block,
        .min_importance = default_min_importance,
        .wave_rays = cpu_device ? cpu_wave_rays : gpu_wave_rays,
        .warmup_ms = cpu_device ? 0.0 : VKRT_WARMUP_MS,
    };
    /* The grid traced about as fast as the BVH only on a CPU device reading storage buffers; with
     * texel loads the kd-tree is weighed instead (src/accel/choose.c), and on GPUs the BVH was
     * 1.2 to 2.1 times faster than the grid on every scene measured. */
    t.grid_competes = cpu_device && !t.texel_loads;
    /* The kd-tree outran the BVH on a CPU device reading texel buffers (src/accel/choose.c). */
    t.kdtree_competes = cpu_device && t.texel_loads;
    /* Subgroups of hits of several shaders run each shader's code in turn: on the H200 the
     * path tracer's light and shade kernels of Sponza with a glossy floor took 1.6 and 2.2 times
     * as long at the first bounce as with every material glossy or every one diffuse
     * (research/journal.md, "Hits grouped by shader"). The environment variable is for
     * measurements and tests, which compare the two. */
    t.material_order = !cpu_device;
    int forced_order = vkrt_test_hooks_get()->material_order;
    if (forced_order >= 0)
        t.material_order = forced_order == 1;
    return t;
}

vkrt_tuning vkrt_tuning_for(const gpu_context *ctx, const vkrt_tuning_overrides *o)
{
    return vkrt_tuning_choose(vkrt_device_is_cpu(ctx),
                              strncmp(ctx->properties.deviceName, "llvmpipe", 8) == 0, o);
}

uint32_t vkrt_warmup_runs(double warmup_ms, double probe_ms, uint32_t min_runs)
{
    double runs = probe_ms > 0 ? ceil(warmup_ms / probe_ms) : min_runs;
    if (runs < min_runs)
        runs = min_runs;
    return runs > VKRT_WARMUP_MAX_RUNS ? VKRT_WARMUP_MAX_RUNS : (uint32_t)runs;
}
