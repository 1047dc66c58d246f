/*
 * tuning.c: the device-dependent defaults (see tuning.h), each with the reason behind it;
 * docs/performance.md has the measurements.
 */
#include "tuning.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../test_hooks.h"

/* 64 invocations fill two 32-wide subgroups or one 64-wide one, and a multiple of a CPU device's
 * SIMD width. */
enum { default_workgroup_size = 64 };

/* Children per node of the BVH's GPU layout. On GPUs the pairs of two float boxes outran the
 * quantized 4-wide nodes on every scene measured; on CPU devices, whose texel fetches cost more
 * than the nodes' decoding, the 4-wide nodes were the faster with the nested walk. */
enum { gpu_bvh_width = 2, cpu_bvh_width = 4 };

/* On a GPU a triangle test (the watertight one) costs more against a node step than the SAH's
 * usual ratio says, so smaller leaves (at most 2 triangles, a node costing half a triangle test)
 * trace faster. CPU devices keep bvh.h's defaults: no difference there, and that tree is the
 * smaller. */
enum { gpu_bvh_max_leaf = 2 };
static const float gpu_bvh_traversal_cost = 0.5f;

/* Devices with a loop budget end an invocation's loops after 65535 iterations in all: brute force
 * goes in blocks of triangles below that, and a brute-force light kernel that would need more is
 * refused (renderer_frame.c). Other devices have no such limit; the block only splits
 * dispatches. */
enum { loop_budget = 65535, brute_force_block = 32768 };

/* Camera rays per sample pass. A pass is some 5 dispatches per depth whatever its size, so a small
 * image's passes of one sample each leave a GPU idle between them; several samples per pass fill
 * it. 2^21 rays is a 1080p image's pass, which fills a GPU; a CPU device, whose dispatches cost
 * little next to its tracing, takes a smaller one (its ray buffers stay within small storage
 * buffer ranges). */
enum { gpu_wave_rays = 1 << 21, cpu_wave_rays = 1 << 16 };

/* A cast ray whose importance (largest channel) falls under this is not traced: it could change
 * its pixel by less than a thousandth of the light that reaches it. */
static const float default_min_importance = 1e-3f;

bool vkrt_device_is_cpu(const gpu_context *ctx)
{
    return ctx->properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
}

vkrt_tuning vkrt_tuning_choose(bool cpu_device, bool loop_limited, const vkrt_tuning_overrides *o)
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
        /* A CPU device may load a storage buffer one lane and one word at a time, each behind a
         * bounds check and a branch, and a texel buffer with vector gathers: texel loads make
         * its traversal several times faster. On GPUs storage loads are as fast or faster. */
        .texel_loads = o->loads == VKRT_LOADS_TEXEL || (o->loads == VKRT_LOADS_DEFAULT && cpu_device),
        .texel_loads_required = o->loads == VKRT_LOADS_TEXEL,
        /* A CPU device runs both sides of every branch any lane takes, so the walk with inner
         * nodes and leaves in loops of their own is faster there; one loop is faster on GPUs. */
        .nested_walk = o->walk == VKRT_WALK_NESTED || (o->walk == VKRT_WALK_DEFAULT && cpu_device),
        .loop_budget = loop_limited ? loop_budget : 0,
        .brute_force_block = brute_force_block,
        .min_importance = default_min_importance,
        .wave_rays = cpu_device ? cpu_wave_rays : gpu_wave_rays,
        .warmup_ms = cpu_device ? 0.0 : VKRT_WARMUP_MS,
    };
    /* The grid traced about as fast as the BVH only on a CPU device reading storage buffers; with
     * texel loads the kd-tree is weighed instead (src/accel/choose.c), and on GPUs the BVH was
     * faster than the grid on every scene measured. */
    t.grid_competes = cpu_device && !t.texel_loads;
    /* The kd-tree outran the BVH on a CPU device reading texel buffers (src/accel/choose.c). */
    t.kdtree_competes = cpu_device && t.texel_loads;
    /* Subgroups of hits of several shaders run each shader's code in turn, so grouping the hits
     * by shader pays on GPUs. A test hook forces either (test_hooks.h), for measurements and
     * tests, which compare the two. */
    t.material_order = !cpu_device;
    int forced_order = vkrt_test_hooks_get()->material_order;
    if (forced_order >= 0)
        t.material_order = forced_order == 1;
    return t;
}

vkrt_tuning vkrt_tuning_for(const gpu_context *ctx, const vkrt_tuning_overrides *o)
{
    /* No Vulkan query reports a loop budget: Mesa's CPU driver, the one device known to have
     * one, is told by its name. */
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
