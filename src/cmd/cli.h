/*
 * cli.h: the command line of `vkrt render`, `view` and `bench`. Each command has its own options
 * struct; options all three share (the device, the image, messages) are one struct they embed. A
 * flag given to a command that does not take it is an error that names the command. What the
 * options ask of the renderer is resolved in one place, render_desc.h.
 */
#ifndef VKRT_CLI_H
#define VKRT_CLI_H

#include <stdbool.h>
#include <stdint.h>

#include "../error.h"
#include "../render/renderer.h"
#include "../scene/config.h"
#include "../scene/loader.h"

typedef enum vkrt_command {
    VKRT_COMMAND_NONE = 0,
    VKRT_COMMAND_RENDER,
    VKRT_COMMAND_BENCH,
    VKRT_COMMAND_VIEW,
    VKRT_COMMAND_HELP,
    VKRT_COMMAND_VERSION,
    VKRT_COMMAND_LIST_DEVICES,
} vkrt_command;

/* Options every command takes. */
typedef struct vkrt_common_options {
    uint32_t width, height;   /* --width, --height; 0 when not given (the scene's resolution) */
    vkrt_accel_kind accel;    /* --accel, when accel_given (else the scene's choice holds) */
    bool accel_given;
    vkrt_integrator integrator; /* --integrator (render, view); auto (0) when not given */
    vkrt_bvh_splits bvh_splits; /* --bvh-splits, when bvh_splits_given */
    bool bvh_splits_given;
    vkrt_instancing instancing; /* --instancing; auto (0) when not given */
    float clamp;              /* --clamp (render, view): the largest channel one path may add
                                 to a pixel, > 0; 0 when not given (no clamp) */
    float target_error;       /* --target-error (render, view): sample each pixel until its
                                 estimated relative error is at most this (--spp the cap); 0
                                 when not given (uniform sampling) */
    int device;               /* --device; -1 picks the default */
    bool validation;          /* --validation, or VKRT_VALIDATION=1 in the environment */
    bool quiet;
    bool verbose;
    bool no_cache;            /* --no-cache: compile every kernel (gpu/spirv_cache.h) */
} vkrt_common_options;

/* What render and view ask of the scene over what its files say (applied to the loaded scene by
 * scene_options.h, but fps, which the loader takes). */
typedef struct vkrt_scene_options {
    const char *camera;          /* --camera N|NAME: only that camera of the scene, as one frame;
                                    NULL when not given (every camera, one frame each) */
    float fps;                   /* --fps: frames per second at which a file's camera animation
                                    is sampled into frames, positive and finite (the loader's
                                    vkrt_load_options.fps); VKRT_LOAD_DEFAULT_FPS when not given */
    bool environment_given;      /* --environment R G B: rays that miss see this radiance */
    float environment[3];        /* each finite and >= 0 */
    const char *environment_map; /* --environment-map FILE, the path as given (relative to the
                                    working folder); NULL when not given */
    bool tonemap_given;          /* --tonemap none|aces|agx: the tone curve of 8-bit output */
    vkrt_tonemap tonemap;
} vkrt_scene_options;

typedef struct vkrt_render_options {
    vkrt_common_options common;
    vkrt_scene_options scene_options;
    const char *scene_path;
    const char *output;       /* -o: overrides the scene's output; NULL when not given */
    uint32_t samples;         /* --spp; 0 when not given */
    float exposure;           /* --exposure, stops, PNG only */
    bool denoise;             /* --denoise: Open Image Denoise on every frame (output/denoise.h) */
    bool profile;             /* --profile: time every dispatch */
    uint32_t profile_repeat;  /* --profile-repeat: timed frames of a profile; 0 when not given */
    uint32_t seed;            /* --seed: the random numbers' seed; 0 when not given */
    bool resume;              /* --resume: skip frames whose files are already complete */
    bool frames_given;        /* --frames A:B[:STEP]: only frames A, A + STEP, ... up to B */
    uint32_t frame_first, frame_last, frame_step;
    const char *devices;      /* --devices all|N,M,...: a worker process per device listed
                                 (device_pool.h); NULL when not given */
    const char *sample_count_image; /* --sample-count-image: each pixel's samples (with
                                       --target-error), a pattern like -o's; NULL: none */
    uint32_t aovs;            /* --aov: the AOVs written with each frame (VKRT_AOV_* of
                                 glsl/shared.h); 0 when not given */
} vkrt_render_options;

typedef struct vkrt_view_options {
    vkrt_common_options common;
    vkrt_scene_options scene_options;
    const char *scene_path;
    uint32_t samples;         /* --spp; 0 when not given */
    float exposure;           /* --exposure, stops */
    bool denoise;             /* --denoise: the window shows the image denoised */
    const char *script;       /* --script: events to play (a testing aid); NULL when not given */
    const char *record;       /* --record: where K appends camera lines; NULL when not given */
} vkrt_view_options;

typedef struct vkrt_bench_options {
    vkrt_common_options common;
    const char *scene_paths[64]; /* every scene.cfg given */
    uint32_t scene_count;
    const char *json;         /* --json: where to write the results */
    vkrt_tuning_overrides tuning; /* --workgroup, --grid-density, --bvh-width, --bvh-leaf,
                                     --bvh-cost, --kd-cost, --loads, --walk */
    bool kernel_stats;        /* --kernel-stats: the driver's statistics of the trace kernels */
    bool stats;               /* --stats: count traversal work instead of timing */
    bool whole_scene;         /* --whole-scene: load materials and textures too */
} vkrt_bench_options;

typedef struct vkrt_command_line {
    vkrt_command command;     /* which of the structs below holds the options */
    vkrt_render_options render;
    vkrt_view_options view;
    vkrt_bench_options bench;
} vkrt_command_line;

/* Parses argv: the command first (or --help, --version, --list-devices), then its scene(s) and
 * options in any order. On failure returns false with a one-line message in err. */
bool vkrt_command_line_parse(int argc, char **argv, vkrt_command_line *cl, vkrt_error *err);

/* The --help text. */
const char *vkrt_usage(void);

#endif
