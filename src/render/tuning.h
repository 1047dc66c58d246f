/*
 * tuning.h: every device-dependent default of the renderer, in one place. The renderer, the
 * acceleration structure's upload and `vkrt bench` ask this module, never the device type
 * themselves. Each default is written once, in tuning.c, beside the reason that chose it; the
 * measurements are in docs/performance.md.
 */
#ifndef VKRT_TUNING_H
#define VKRT_TUNING_H

#include <stdbool.h>
#include <stdint.h>

#include "../gpu/context.h"

/* How traversal reads triangles and BVH nodes: storage buffers, or uniform texel buffer views of
 * the same buffers (texelFetch). */
typedef enum vkrt_loads {
    VKRT_LOADS_DEFAULT,
    VKRT_LOADS_STORAGE,
    VKRT_LOADS_TEXEL,
} vkrt_loads;

/* How the BVH's walk loops: one loop that visits a node or a leaf per iteration, or inner nodes
 * and leaves in two loops of their own inside a third (glsl/lib/traverse_bvh.glsl). */
typedef enum vkrt_walk {
    VKRT_WALK_DEFAULT,
    VKRT_WALK_ONE_LOOP,
    VKRT_WALK_NESTED,
} vkrt_walk;

/* What a user (`vkrt bench`, tests) may set against the defaults; zero everywhere means "the
 * device's default" (sokol's convention). */
typedef struct vkrt_tuning_overrides {
    uint32_t workgroup_size;  /* invocations per workgroup of the wave kernels */
    float grid_density;       /* cells per triangle of a grid */
    uint32_t bvh_width;       /* children per node of the BVH's GPU layout, 2 or 4 */
    uint32_t bvh_max_leaf;    /* the BVH build's largest leaf (1..16) */
    float bvh_traversal_cost; /* the BVH build's SAH cost of a node against a triangle */
    float bvh_spatial_budget; /* the share of duplicate references spatial splits may add
                                 (0 .. BVH_MAX_SPATIAL_BUDGET; 0: accel_gpu.c's default) */
    float kd_traversal_cost;  /* the kd-tree build's K_T / K_I */
    vkrt_loads loads;
    vkrt_walk walk;
} vkrt_tuning_overrides;

/* The settings every kernel and structure reads, resolved for one device. */
typedef struct vkrt_tuning {
    bool cpu_device;          /* a CPU implementation: the choices below follow it */
    uint32_t workgroup_size;
    float grid_density;       /* 0: the grid's own default (grid.h) */
    uint32_t bvh_width;       /* 2 or 4 */
    uint32_t bvh_max_leaf;    /* 0: bvh.h's default */
    float bvh_traversal_cost; /* 0: bvh.h's default */
    float bvh_spatial_budget; /* 0: accel_gpu.c's default */
    float kd_traversal_cost;  /* K_T / K_I; 0: kdtree.h's default */
    bool texel_loads;         /* read through texel views where they hold the whole buffers */
    bool texel_loads_required;/* asked for: an error where they cannot hold them */
    bool nested_walk;
    bool grid_competes;       /* accel auto weighs the grid against the BVH */
    bool kdtree_competes;     /* accel auto takes the kd-tree up to accel_kdtree_limit */
    uint32_t loop_budget;     /* loop iterations an invocation may run in all (0: no limit) */
    uint32_t brute_force_block; /* triangles per brute-force dispatch */
    float min_importance;     /* a cast ray weaker than this (largest channel) is dropped */
    uint32_t wave_rays;       /* camera rays a sample pass aims at: several samples per pixel go
                                 in one pass when the image has fewer pixels than this */
    double warmup_ms;         /* device time run before anything is timed (vkrt_warmup_runs) */
    bool material_order;      /* group each bounce's hits by shader (glsl/order.comp) where a
                                 scene has several; a test hook overrides it (test_hooks.h) */
} vkrt_tuning;

/* Whether ctx's device is a CPU implementation. */
bool vkrt_device_is_cpu(const gpu_context *ctx);

/* The settings for a device (cpu_device; loop_limited: a device that ends an invocation's loops
 * after a budget of iterations) with the overrides o (NULL: none) applied. Checks nothing: values out of range are refused
 * where they are used (the BVH's layout, the pipeline's limits). */
vkrt_tuning vkrt_tuning_choose(bool cpu_device, bool loop_limited, const vkrt_tuning_overrides *o);

/* vkrt_tuning_choose for ctx's device. */
vkrt_tuning vkrt_tuning_for(const gpu_context *ctx, const vkrt_tuning_overrides *o);

/* Warm-up before anything is timed: runs of a probe_ms-long piece of work that make up
 * warmup_ms of device time (vkrt_tuning.warmup_ms), at least min_runs and at most
 * VKRT_WARMUP_MAX_RUNS. A GPU idle before a timing runs at low clocks, and the same frame takes
 * several times as long right after the host wrote a file as right after another; VKRT_WARMUP_MS
 * at full load brings it to its clocks. A CPU device runs at the CPU's clocks: min_runs only. */
#define VKRT_WARMUP_MS 300.0
#define VKRT_WARMUP_MAX_RUNS 4000u
uint32_t vkrt_warmup_runs(double warmup_ms, double probe_ms, uint32_t min_runs);

#endif
