/*
 * cli.h: command-line parsing for `vkrt render`, `view` and `bench`.
 */
#ifndef VKRT_CLI_H
#define VKRT_CLI_H

#include <stdbool.h>
#include <stdint.h>

#include "error.h"
#include "scene/config.h"

typedef enum vkrt_command {
    VKRT_COMMAND_NONE = 0,
    VKRT_COMMAND_RENDER,
    VKRT_COMMAND_BENCH,
    VKRT_COMMAND_VIEW,
    VKRT_COMMAND_HELP,
    VKRT_COMMAND_VERSION,
    VKRT_COMMAND_LIST_DEVICES,
} vkrt_command;

typedef struct vkrt_options {
    vkrt_command command;
    const char *scene_path;   /* render: the scene.cfg; bench: the first of scene_paths */
    const char *scene_paths[64]; /* bench: every scene.cfg given */
    uint32_t scene_count;
    const char *json;         /* bench --json: where to write the results */
    float grid_density;       /* bench --grid-density: cells per triangle; 0: the default */
    uint32_t bvh_width;       /* bench --bvh-width: 2 or 4; 0: the default */
    uint32_t bvh_max_leaf;    /* bench --bvh-leaf: the build's largest leaf, 1..16; 0: the default */
    float bvh_traversal_cost; /* bench --bvh-cost: the build's node cost; 0: the default */
    int loads;                /* bench --loads: 1 storage, 2 texel (vkrt_loads); 0: default */
    int walk;                 /* bench --walk: 1 one-loop, 2 nested (vkrt_walk); 0: default */
    int ray_fetch;            /* bench --ray-fetch: 1 static, 2 dynamic (vkrt_ray_fetch); 0: default */
    uint32_t workgroup_size;  /* bench --workgroup: invocations per workgroup; 0: the default */
    uint32_t sort_diffuse;    /* bench --sort-diffuse: direction cells per side (2..16) of the GPU's
                                 ray sort before diffuse rays are traced; 0: tile order */
    bool kernel_stats;        /* bench --kernel-stats: the driver's statistics of the trace kernels */
    bool stats;               /* bench --stats: count traversal work instead of timing */
    bool whole_scene;         /* bench --whole-scene: load materials and textures too */
    const char *output;       /* -o: overrides the scene's output; NULL when not given */
    const char *script;       /* view --script: events to play (a testing aid); NULL when not given */
    const char *record;       /* view --record: where K appends camera lines; NULL when not given */
    uint32_t width, height;   /* 0 when not given */
    uint32_t samples;         /* --spp; 0 when not given */
    int device;               /* --device; -1 picks the default */
    float exposure;           /* --exposure, stops, PNG only */
    vkrt_accel_kind accel;    /* --accel; VKRT_ACCEL_AUTO when not given (the scene's choice holds) */
    bool accel_given;
    bool quiet;
    bool verbose;
    bool profile;             /* render --profile: time every dispatch */
    uint32_t profile_repeat;  /* --profile-repeat: timed frames of a profile; 0 when not given */
    bool resume;              /* render --resume: skip frames whose files are already complete */
    bool validation;          /* --validation, or VKRT_VALIDATION=1 in the environment */
} vkrt_options;

/* Parses argv. On failure returns false with a one-line message in err. */
bool vkrt_options_parse(int argc, char **argv, vkrt_options *opts, vkrt_error *err);

/* The --help text. */
const char *vkrt_usage(void);

#endif
