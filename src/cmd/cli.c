/* cli.c: command-line parsing (see cli.h). */
#include "cli.h"

#include "../device_pool.h"
#include "../../glsl/shared.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *vkrt_usage(void)
{
    return "usage: vkrt render SCENE.cfg [options]   render every frame (camera) of a scene\n"
           "       vkrt view SCENE.cfg [options]     fly through a scene in a window\n"
           "       vkrt bench SCENE.cfg... [options]  time primary, shadow and diffuse rays per\n"
           "                                         scene and acceleration structure\n"
           "       vkrt --list-devices               list Vulkan devices\n"
           "       vkrt --help | --version\n"
           "\n"
           "render options:\n"
           "  -o PATH           output file (.png or .exr); a pattern such as out/f%04d.png\n"
           "                    numbers the frames; overrides the scene's `output`\n"
           "  --width W         image width in pixels (overrides `resolution`)\n"
           "  --height H        image height in pixels\n"
           "  --spp N           samples per pixel (overrides `samples`)\n"
           "  --accel A         auto | brute | grid | bvh | kdtree (overrides `accel`)\n"
           "  --bvh-splits S    auto | on | off: spatial splits in the BVH, which put a\n"
           "                    triangle in several leaves (overrides `bvh-splits`)\n"
           "  --camera N|NAME   render only the scene's camera N (from 0, in the order the\n"
           "                    scene lists them) or the one named NAME, as a single frame\n"
           "  --fps F           frames per second at which a scene file's camera animation\n"
           "                    is sampled into frames (default 24)\n"
           "  --environment R G B  the radiance of rays that miss, each >= 0 (overrides the\n"
           "                    scene's `environment` and `environment-map`)\n"
           "  --environment-map FILE  an equirectangular map (.exr, .hdr, ...; relative to\n"
           "                    the working folder) as the environment (overrides the scene's)\n"
           "  --instancing M    auto | flat | two-level: each mesh once on the device under a\n"
           "                    two-level BVH (auto: where instances repeat meshes), or every\n"
           "                    instance's triangles in world space\n"
           "  --integrator I    auto | whitted | path (overrides `integrator`): Whitted's\n"
           "                    delta lights and perfect mirrors, or the path tracer\n"
           "  --clamp L         scale each contribution a path adds to a pixel down so that\n"
           "                    its largest channel is at most L: fewer fireflies, but biased\n"
           "                    (light is lost); off by default\n"
           "  --target-error E  sample each pixel until the estimated relative standard error\n"
           "                    of its luminance is at most E (e.g. 0.05), --spp the most\n"
           "                    (docs/scene-format.md, \"Sampling to a target error\"); path\n"
           "                    integrator; prints the error reached\n"
           "  --sample-count-image PATH  with --target-error: each pixel's samples, EXR (the\n"
           "                    counts) or PNG (grey: count / --spp), numbered like -o\n"
           "  --verbose         say which acceleration structure and integrator were chosen\n"
           "                    and why, the structure's build statistics, and every loader\n"
           "                    warning (folded by kind without it)\n"
           "  --profile         time every dispatch of each frame (GPU timestamps) and print a\n"
           "                    table per depth and kernel: the frame is rendered again after\n"
           "                    300 ms of GPU warm-up, 11 times back to back, medians shown;\n"
           "                    then the driver's statistics of each kernel, where it has them\n"
           "  --profile-repeat N  --profile with N timed frames instead of 11\n"
           "  --seed N          another set of random numbers (default 0): renders of one scene\n"
           "                    with different seeds have independent noise\n"
           "  --exposure STOPS  scale PNG output by 2^STOPS before the sRGB curve (EXR unchanged)\n"
           "  --denoise         Intel Open Image Denoise's RT filter on each frame; an EXR gets\n"
           "                    the denoised image and keeps the rendered one as layer \"noisy\".\n"
           "                    Needs libOpenImageDenoise.so.2: tools/setup-python puts it in\n"
           "                    .venv, or VKRT_OIDN_LIBRARY=PATH names it\n"
           "  --aov LIST        also write the AOVs named (albedo,normal,depth,position): layers\n"
           "                    albedo.RGB, normal.XYZ, depth.Z, position.XYZ of an EXR, or\n"
           "                    files beside a PNG (NAME.albedo.png, NAME.normal.png,\n"
           "                    NAME.depth.exr, NAME.position.exr; docs/scene-format.md, \"AOVs\")\n"
           "  --tonemap C       none | aces | agx (overrides `tonemap`): the tone curve of PNG\n"
           "                    output and the window, after --exposure: none clips at 1, aces is\n"
           "                    Hill's ACES fit, agx Blender's AgX (minimal fit); EXR unchanged\n"
           "  --device N        Vulkan device (see --list-devices); default: the first discrete\n"
           "                    GPU, else the first device\n"
           "  --validation      enable Vulkan validation layers (also VKRT_VALIDATION=1); any\n"
           "                    validation message makes the run fail\n"
           "  --no-cache        compile every kernel, parse the OBJ and build the structure,\n"
           "                    neither reading nor writing the cache of kernels, meshes and\n"
           "                    structures (~/.cache/vkrt; VKRT_CACHE_DIR=DIR moves it,\n"
           "                    VKRT_SCENE_CACHE_DIR=DIR the meshes and structures alone)\n"
           "  --frames A:B[:STEP]  render only frames A, A + STEP, ... up to B (numbered from 0,\n"
           "                    as the output pattern numbers them), e.g. for a render farm\n"
           "  --resume          skip frames whose output files are already complete (a\n"
           "                    flythrough interrupted by Ctrl-C, a crash or a lost device)\n"
           "  --devices all|N,M,...  render the frames on several devices at once, a worker\n"
           "                    process each, each taking the next frame when done (a device\n"
           "                    listed twice gets two workers); a worker that fails has its\n"
           "                    frame rendered by the others; a summary per device at the end\n"
           "  --quiet           no summary on stderr\n"
           "  --list-devices    list Vulkan devices and exit\n"
           "  --help, --version\n"
           "\n"
           "bench options: --width, --height, --accel, --bvh-splits, --instancing, --device,\n"
           "  --validation, --quiet, --verbose, --no-cache as for render (without --accel: brute,\n"
           "  grid, bvh and kdtree in turn)\n"
           "  --json PATH       write the results as JSON too\n"
           "  --stats           count nodes, triangles and SIMD use per ray instead of timing\n"
           "  --kernel-stats    print the driver's statistics of the trace kernels\n"
           "  --whole-scene     load materials and textures too (tracing reads neither)\n"
           "  tuning, each against the device's default (docs/performance.md, docs/architecture.md):\n"
           "  --workgroup N  --grid-density CELLS_PER_TRIANGLE  --bvh-width 2|4  --bvh-leaf N\n"
           "  --bvh-cost C  --kd-cost C  --loads storage|texel  --walk one-loop|nested\n"
           "\n"
           "view options: --width, --height, --spp, --accel, --bvh-splits, --instancing,\n"
           "  --integrator, --clamp, --exposure, --tonemap, --denoise, --target-error, --camera,\n"
           "  --fps, --environment, --environment-map, --device, --validation, --quiet, --no-cache\n"
           "  as for render (--denoise: each shown frame is denoised on the host); the window opens\n"
           "  at the scene's resolution, from its first camera (or --camera's), and a still\n"
           "  picture gathers samples until it has --spp of them (default: the scene's `samples`,\n"
           "  at least 16), or with --target-error until every pixel is within it (--spp the cap)\n"
           "  --record FILE     K appends the camera to FILE as a scene.cfg `camera` line\n"
           "  --script FILE     play key and mouse events from FILE (a testing aid; see\n"
           "                    docs/viewer.md)\n"
           "view controls:\n"
           "  W/S, A/D          move forward/back, left/right (along the view)\n"
           "  E/Q, Space/C      move up/down\n"
           "  mouse drag        look around\n"
           "  scroll, +/-       faster/slower; hold Shift to go 4x faster\n"
           "  R                 reset to the scene's camera\n"
           "  F                 frame the whole scene\n"
           "  P                 screenshot next to the scene: PNG of the window, EXR of the\n"
           "                    accumulated linear image\n"
           "  K                 print the camera as a scene.cfg `camera` line (and --record it)\n"
           "  Esc               quit\n";
}

/* option's value as 1 (first) or 2 (second), the values of bench's two-way choices. */
static bool parse_choice(const char *option, const char *text, const char *first,
                         const char *second, int *out, vkrt_error *err)
{
    if (text && strcmp(text, first) == 0)
        *out = 1;
    else if (text && strcmp(text, second) == 0)
        *out = 2;
    else
        return vkrt_error_set(err, "%s: '%s' is not one of %s, %s", option, text ? text : "",
                              first, second);
    return true;
}

static bool parse_u32(const char *option, const char *text, uint32_t min, uint32_t max,
                      uint32_t *out, vkrt_error *err)
{
    if (!text)
        return vkrt_error_set(err, "%s needs a value", option);
    char *end;
    errno = 0;
    long long value = strtoll(text, &end, 10);
    if (errno || end == text || *end || value < (long long)min || value > (long long)max)
        return vkrt_error_set(err, "%s: '%s' is not a whole number from %u to %u", option, text,
                              min, max);
    *out = (uint32_t)value;
    return true;
}

static bool parse_float(const char *option, const char *text, float *out, vkrt_error *err)
{
    if (!text)
        return vkrt_error_set(err, "%s needs a value", option);
    char *end;
    errno = 0;
    float value = strtof(text, &end);
    if (errno || end == text || *end || !isfinite(value))
        return vkrt_error_set(err, "%s: '%s' is not a number", option, text);
    *out = value;
    return true;
}

/* A float option that must be positive (and finite). */
static bool parse_positive(const char *option, const char *text, float *out, vkrt_error *err)
{
    if (!parse_float(option, text, out, err))
        return false;
    if (!(*out > 0))
        return vkrt_error_set(err, "%s: '%s' is not a positive number", option, text);
    return true;
}

/* --aov's list (names joined by commas) as VKRT_AOV_* bits. */
static bool parse_aovs(const char *text, uint32_t *out, vkrt_error *err)
{
    static const struct {
        const char *name;
        uint32_t bit;
    } names[] = {{"albedo", VKRT_AOV_ALBEDO},
                 {"normal", VKRT_AOV_NORMAL},
                 {"depth", VKRT_AOV_DEPTH},
                 {"position", VKRT_AOV_POSITION}};
    if (!text || !*text)
        return vkrt_error_set(err, "--aov needs a list of albedo, normal, depth, position");
    *out = 0;
    for (const char *p = text; *p;) {
        size_t n = strcspn(p, ",");
        uint32_t bit = 0;
        for (size_t k = 0; k < sizeof names / sizeof *names; ++k)
            if (n == strlen(names[k].name) && strncmp(p, names[k].name, n) == 0)
                bit = names[k].bit;
        if (!bit)
            return vkrt_error_set(err, "--aov: '%.*s' is not one of albedo, normal, depth, "
                                       "position", (int)n, p);
        *out |= bit;
        p += n + (p[n] == ',');
    }
    return true;
}

/* Which commands take each option; the parser refuses an option its command does not take. */
enum { RENDER = 1 << VKRT_COMMAND_RENDER, VIEW = 1 << VKRT_COMMAND_VIEW,
       BENCH = 1 << VKRT_COMMAND_BENCH, ALL = RENDER | VIEW | BENCH };

static const struct known_option {
    const char *name;
    unsigned commands;
} known_options[] = {
    {"--width", ALL},        {"--height", ALL},         {"--accel", ALL},
    {"--device", ALL},       {"--validation", ALL},     {"--quiet", ALL},
    {"--verbose", ALL},      {"--no-cache", ALL},       {"-o", RENDER},            {"--spp", RENDER | VIEW},
    {"--exposure", RENDER | VIEW},                      {"--profile", RENDER},
    {"--profile-repeat", RENDER},                       {"--seed", RENDER},
    {"--frames", RENDER},    {"--resume", RENDER},      {"--devices", RENDER},
    {"--script", VIEW},      {"--record", VIEW},        {"--json", BENCH},
    {"--stats", BENCH},      {"--kernel-stats", BENCH}, {"--whole-scene", BENCH},
    {"--workgroup", BENCH},  {"--grid-density", BENCH}, {"--bvh-width", BENCH},
    {"--bvh-leaf", BENCH},   {"--bvh-cost", BENCH},     {"--kd-cost", BENCH},
    {"--loads", BENCH},
    {"--walk", BENCH},       {"--integrator", RENDER | VIEW}, {"--clamp", RENDER | VIEW},
    {"--target-error", RENDER | VIEW},                  {"--sample-count-image", RENDER},
    {"--bvh-splits", ALL},   {"--instancing", ALL},     {"--camera", RENDER | VIEW},
    {"--fps", RENDER | VIEW},                           {"--environment", RENDER | VIEW},
    {"--environment-map", RENDER | VIEW},               {"--denoise", RENDER | VIEW},
    {"--aov", RENDER},
    {"--tonemap", RENDER | VIEW},
};

static const char *command_name(vkrt_command command)
{
    return command == VKRT_COMMAND_BENCH ? "bench" : command == VKRT_COMMAND_VIEW ? "view"
                                                                                  : "render";
}

/* Refuses arg unless it is an option that command takes. */
static bool check_option(vkrt_command command, const char *arg, vkrt_error *err)
{
    for (size_t i = 0; i < sizeof known_options / sizeof *known_options; ++i) {
        const struct known_option *o = &known_options[i];
        if (strcmp(arg, o->name) != 0)
            continue;
        if (o->commands & (1u << command))
            return true;
        char takers[32] = "";
        for (vkrt_command c = VKRT_COMMAND_RENDER; c <= VKRT_COMMAND_VIEW; ++c)
            if (o->commands & (1u << c))
                snprintf(takers + strlen(takers), sizeof takers - strlen(takers), "%s%s",
                         takers[0] ? " and " : "", command_name(c));
        return vkrt_error_set(err, "vkrt %s does not take %s (an option of vkrt %s)",
                              command_name(command), arg, takers);
    }
    return vkrt_error_set(err, "unknown option '%s' (see vkrt --help)", arg);
}

/* Parses an option every command takes into c; *used says whether arg was one, *consumed how
 * many arguments after it were its values. */
static bool parse_common(const char *arg, const char *value, vkrt_common_options *c, bool *used,
                         int *consumed, vkrt_error *err)
{
    *used = true;
    *consumed = 0;
    uint32_t device;
    if (strcmp(arg, "--width") == 0 || strcmp(arg, "--height") == 0) {
        *consumed = 1;
        return parse_u32(arg, value, 1, 16384, arg[2] == 'w' ? &c->width : &c->height, err);
    } else if (strcmp(arg, "--device") == 0) {
        *consumed = 1;
        if (!parse_u32(arg, value, 0, 1000, &device, err))
            return false;
        c->device = (int)device;
    } else if (strcmp(arg, "--accel") == 0) {
        *consumed = 1;
        char names[VKRT_NAMES_BYTES];
        if (!value || !vkrt_accel_parse(value, &c->accel))
            return vkrt_error_set(err, "--accel: '%s' is not one of %s", value ? value : "",
                                  vkrt_accel_names(names));
        c->accel_given = true;
    } else if (strcmp(arg, "--bvh-splits") == 0) {
        *consumed = 1;
        char names[VKRT_NAMES_BYTES];
        if (!value || !vkrt_bvh_splits_parse(value, &c->bvh_splits))
            return vkrt_error_set(err, "--bvh-splits: '%s' is not one of %s", value ? value : "",
                                  vkrt_bvh_splits_names(names));
        c->bvh_splits_given = true;
    } else if (strcmp(arg, "--instancing") == 0) {
        *consumed = 1;
        static const char *const names[] = {"auto", "flat", "two-level"};
        size_t k = 0;
        while (value && k < sizeof names / sizeof *names && strcmp(value, names[k]) != 0)
            ++k;
        if (!value || k == sizeof names / sizeof *names)
            return vkrt_error_set(err, "--instancing: '%s' is not one of auto, flat, two-level",
                                  value ? value : "");
        c->instancing = (vkrt_instancing)k;
    } else if (strcmp(arg, "--integrator") == 0) {
        *consumed = 1;
        char names[VKRT_NAMES_BYTES];
        if (!value || !vkrt_integrator_parse(value, &c->integrator))
            return vkrt_error_set(err, "--integrator: '%s' is not one of %s", value ? value : "",
                                  vkrt_integrator_names(names));
    } else if (strcmp(arg, "--clamp") == 0) {
        *consumed = 1;
        return parse_positive(arg, value, &c->clamp, err);
    } else if (strcmp(arg, "--target-error") == 0) {
        *consumed = 1;
        return parse_positive(arg, value, &c->target_error, err);
    } else if (strcmp(arg, "--validation") == 0) {
        c->validation = true;
    } else if (strcmp(arg, "--quiet") == 0) {
        c->quiet = true;
    } else if (strcmp(arg, "--no-cache") == 0) {
        c->no_cache = true;
    } else if (strcmp(arg, "--verbose") == 0) {
        c->verbose = true;
    } else {
        *used = false;
    }
    return true;
}

/* Parses a scene option (render and view) into o; *used says whether arg was one, *consumed how
 * many of the `count` arguments after it (values) were its values. */
static bool parse_scene_option(const char *arg, char *const *values, int count,
                               vkrt_scene_options *o, bool *used, int *consumed, vkrt_error *err)
{
    *used = true;
    *consumed = 1;
    const char *value = count > 0 ? values[0] : NULL;
    if (strcmp(arg, "--camera") == 0) {
        /* A name never starts with '-' here: `--camera -o x.png` forgot the camera. */
        if (!value || !*value || value[0] == '-')
            return vkrt_error_set(err, "--camera needs a camera's number (from 0) or name%s%s%s",
                                  value ? ", not '" : "", value ? value : "", value ? "'" : "");
        o->camera = value;
    } else if (strcmp(arg, "--fps") == 0) {
        return parse_positive(arg, value, &o->fps, err);
    } else if (strcmp(arg, "--environment") == 0) {
        for (int i = 0; i < 3; ++i) {
            if (i >= count)
                return vkrt_error_set(err, "--environment needs 3 numbers (R G B), got %d", i);
            if (!parse_float(arg, values[i], &o->environment[i], err))
                return false;
            if (!(o->environment[i] >= 0))
                return vkrt_error_set(err, "--environment: '%s' is negative (radiance is >= 0)",
                                      values[i]);
        }
        *consumed = 3;
        o->environment_given = true;
    } else if (strcmp(arg, "--environment-map") == 0) {
        if (!value || !*value)
            return vkrt_error_set(err, "--environment-map needs a path");
        o->environment_map = value;
    } else if (strcmp(arg, "--tonemap") == 0) {
        if (!vkrt_tonemap_parse(value, &o->tonemap))
            return vkrt_error_set(err, "--tonemap: '%s' is not one of none, aces, agx",
                                  value ? value : "");
        o->tonemap_given = true;
    } else {
        *used = false;
        *consumed = 0;
    }
    return true;
}

/* --frames A:B[:STEP]: A and B included, STEP 1 when not given. */
static bool parse_frame_range(const char *value, vkrt_render_options *o, vkrt_error *err)
{
    static const char *const form = "A:B or A:B:STEP, frame numbers from 0 with A <= B, STEP >= 1";
    unsigned long n[3] = {0, 0, 1};
    const char *p = value ? value : "";
    int count = 0;
    while (count < 3) {
        char *end;
        if (*p < '0' || *p > '9')
            break;
        n[count++] = strtoul(p, &end, 10);
        p = end;
        if (*p != ':')
            break;
        ++p;
    }
    if (count < 2 || *p != '\0' || n[0] > n[1] || n[1] > UINT32_MAX || n[2] < 1 ||
        n[2] > UINT32_MAX)
        return vkrt_error_set(err, "--frames: '%s' is not a frame range (%s)", value ? value : "",
                              form);
    o->frames_given = true;
    o->frame_first = (uint32_t)n[0];
    o->frame_last = (uint32_t)n[1];
    o->frame_step = (uint32_t)n[2];
    return true;
}

static bool parse_render(const char *arg, const char *value, vkrt_render_options *o,
                         int *consumed, vkrt_error *err)
{
    *consumed = 1;
    if (strcmp(arg, "-o") == 0) {
        if (!value)
            return vkrt_error_set(err, "-o needs a path");
        o->output = value;
    } else if (strcmp(arg, "--spp") == 0) {
        return parse_u32(arg, value, 1, 65536, &o->samples, err);
    } else if (strcmp(arg, "--exposure") == 0) {
        return parse_float(arg, value, &o->exposure, err);
    } else if (strcmp(arg, "--profile-repeat") == 0) {
        o->profile = true;
        return parse_u32(arg, value, 1, 1000, &o->profile_repeat, err);
    } else if (strcmp(arg, "--seed") == 0) {
        return parse_u32(arg, value, 0, UINT32_MAX, &o->seed, err);
    } else if (strcmp(arg, "--frames") == 0) {
        return parse_frame_range(value, o, err);
    } else if (strcmp(arg, "--devices") == 0) {
        if (!value)
            return vkrt_error_set(err,
                                  "--devices needs a value: all, or device numbers such as 0,2");
        o->devices = value;
        return vkrt_devices_spec_check(value, err);
    } else if (strcmp(arg, "--sample-count-image") == 0) {
        if (!value)
            return vkrt_error_set(err, "--sample-count-image needs a path");
        o->sample_count_image = value;
    } else if (strcmp(arg, "--aov") == 0) {
        return parse_aovs(value, &o->aovs, err);
    } else {
        *consumed = 0;
        if (strcmp(arg, "--profile") == 0)
            o->profile = true;
        else if (strcmp(arg, "--resume") == 0)
            o->resume = true;
        else if (strcmp(arg, "--denoise") == 0)
            o->denoise = true;
    }
    return true;
}

static bool parse_view(const char *arg, const char *value, vkrt_view_options *o, int *consumed,
                       vkrt_error *err)
{
    *consumed = 1;
    if (strcmp(arg, "--spp") == 0)
        return parse_u32(arg, value, 1, 65536, &o->samples, err);
    if (strcmp(arg, "--exposure") == 0)
        return parse_float(arg, value, &o->exposure, err);
    if (strcmp(arg, "--denoise") == 0) {
        *consumed = 0;
        o->denoise = true;
        return true;
    }
    if (!value)
        return vkrt_error_set(err, "%s needs a path", arg);
    if (strcmp(arg, "--script") == 0)
        o->script = value;
    else
        o->record = value;
    return true;
}

static bool parse_bench(const char *arg, const char *value, vkrt_bench_options *o, int *consumed,
                        vkrt_error *err)
{
    vkrt_tuning_overrides *t = &o->tuning;
    *consumed = 1;
    int choice;
    if (strcmp(arg, "--json") == 0) {
        if (!value)
            return vkrt_error_set(err, "--json needs a path");
        o->json = value;
    } else if (strcmp(arg, "--workgroup") == 0) {
        return parse_u32(arg, value, 1, 1024, &t->workgroup_size, err);
    } else if (strcmp(arg, "--grid-density") == 0) {
        if (!parse_float(arg, value, &t->grid_density, err))
            return false;
        if (t->grid_density <= 0 || t->grid_density > 1000)
            return vkrt_error_set(err, "--grid-density: '%s' is not in (0, 1000]", value);
    } else if (strcmp(arg, "--bvh-leaf") == 0) {
        return parse_u32(arg, value, 1, 16, &t->bvh_max_leaf, err);
    } else if (strcmp(arg, "--bvh-cost") == 0) {
        if (!parse_float(arg, value, &t->bvh_traversal_cost, err))
            return false;
        if (!(t->bvh_traversal_cost > 0 && t->bvh_traversal_cost <= 100))
            return vkrt_error_set(err, "--bvh-cost: '%s' is not in (0, 100]", value);
    } else if (strcmp(arg, "--kd-cost") == 0) {
        if (!parse_float(arg, value, &t->kd_traversal_cost, err))
            return false;
        if (!(t->kd_traversal_cost > 0 && t->kd_traversal_cost <= 100))
            return vkrt_error_set(err, "--kd-cost: '%s' is not in (0, 100]", value);
    } else if (strcmp(arg, "--bvh-width") == 0) {
        if (!parse_u32(arg, value, 2, 4, &t->bvh_width, err))
            return false;
        if (t->bvh_width == 3)
            return vkrt_error_set(err, "--bvh-width: 3 is not one of 2, 4");
    } else if (strcmp(arg, "--loads") == 0) {
        if (!parse_choice(arg, value, "storage", "texel", &choice, err))
            return false;
        t->loads = choice == 1 ? VKRT_LOADS_STORAGE : VKRT_LOADS_TEXEL;
    } else if (strcmp(arg, "--walk") == 0) {
        if (!parse_choice(arg, value, "one-loop", "nested", &choice, err))
            return false;
        t->walk = choice == 1 ? VKRT_WALK_ONE_LOOP : VKRT_WALK_NESTED;
    } else {
        *consumed = 0;
        if (strcmp(arg, "--stats") == 0)
            o->stats = true;
        else if (strcmp(arg, "--kernel-stats") == 0)
            o->kernel_stats = true;
        else if (strcmp(arg, "--whole-scene") == 0)
            o->whole_scene = true;
    }
    return true;
}

static vkrt_command parse_command_word(const char *word)
{
    static const struct {
        const char *word;
        vkrt_command command;
    } words[] = {
        {"render", VKRT_COMMAND_RENDER},      {"view", VKRT_COMMAND_VIEW},
        {"bench", VKRT_COMMAND_BENCH},        {"--help", VKRT_COMMAND_HELP},
        {"-h", VKRT_COMMAND_HELP},            {"--version", VKRT_COMMAND_VERSION},
        {"--list-devices", VKRT_COMMAND_LIST_DEVICES},
    };
    for (size_t i = 0; i < sizeof words / sizeof *words; ++i)
        if (strcmp(word, words[i].word) == 0)
            return words[i].command;
    return VKRT_COMMAND_NONE;
}

bool vkrt_command_line_parse(int argc, char **argv, vkrt_command_line *cl, vkrt_error *err)
{
    memset(cl, 0, sizeof *cl);
    if (argc < 2)
        return vkrt_error_set(err, "no command given (see vkrt --help)");
    cl->command = parse_command_word(argv[1]);
    if (cl->command == VKRT_COMMAND_NONE)
        return vkrt_error_set(err, argv[1][0] == '-'
                                       ? "no command given before '%s' (see vkrt --help)"
                                       : "unknown command '%s' (see vkrt --help)",
                              argv[1]);
    if (cl->command >= VKRT_COMMAND_HELP)
        return true;
    vkrt_common_options *common = cl->command == VKRT_COMMAND_RENDER ? &cl->render.common
                                  : cl->command == VKRT_COMMAND_VIEW ? &cl->view.common
                                                                     : &cl->bench.common;
    common->device = -1;
    cl->render.scene_options.fps = VKRT_LOAD_DEFAULT_FPS;
    cl->view.scene_options.fps = VKRT_LOAD_DEFAULT_FPS;
    const char *env = getenv("VKRT_VALIDATION");
    common->validation = env && strcmp(env, "0") != 0 && *env;
    const char *scene = NULL;
    vkrt_bench_options *bench = &cl->bench;
    for (int i = 2; i < argc; ++i) {
        const char *arg = argv[i];
        const char *value = i + 1 < argc ? argv[i + 1] : NULL;
        if (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0) {
            cl->command = VKRT_COMMAND_HELP;
            return true;
        }
        if (arg[0] != '-' || !arg[1]) {
            if (!scene)
                scene = arg;
            else if (cl->command != VKRT_COMMAND_BENCH)
                return vkrt_error_set(err, "unexpected argument '%s'", arg);
            if (cl->command == VKRT_COMMAND_BENCH) {
                if (bench->scene_count == sizeof bench->scene_paths / sizeof *bench->scene_paths)
                    return vkrt_error_set(err, "bench takes at most %zu scenes",
                                          sizeof bench->scene_paths / sizeof *bench->scene_paths);
                bench->scene_paths[bench->scene_count++] = arg;
            }
            continue;
        }
        if (!check_option(cl->command, arg, err))
            return false;
        bool used;
        int consumed;
        bool ok = parse_common(arg, value, common, &used, &consumed, err);
        vkrt_scene_options *scene_options = cl->command == VKRT_COMMAND_RENDER
                                                ? &cl->render.scene_options
                                                : &cl->view.scene_options;
        if (ok && !used && cl->command != VKRT_COMMAND_BENCH)
            ok = parse_scene_option(arg, argv + i + 1, argc - i - 1, scene_options, &used,
                                    &consumed, err);
        if (ok && !used)
            ok = cl->command == VKRT_COMMAND_RENDER ? parse_render(arg, value, &cl->render,
                                                                   &consumed, err)
                 : cl->command == VKRT_COMMAND_VIEW ? parse_view(arg, value, &cl->view,
                                                                 &consumed, err)
                                                    : parse_bench(arg, value, bench, &consumed,
                                                                  err);
        if (!ok)
            return false;
        i += consumed;
    }
    const char *name = command_name(cl->command);
    if (!scene)
        return vkrt_error_set(err, "%s needs a scene file: vkrt %s SCENE.cfg", name, name);
    if (cl->render.devices && cl->render.common.device >= 0)
        return vkrt_error_set(err, "--device and --devices: give one (--devices %d for that device "
                              "alone)", cl->render.common.device);
    const vkrt_scene_options *so = cl->command == VKRT_COMMAND_VIEW ? &cl->view.scene_options
                                                                    : &cl->render.scene_options;
    if (so->environment_given && so->environment_map)
        return vkrt_error_set(err, "--environment and --environment-map: give one (a map is the "
                                   "whole environment)");
    if (cl->render.sample_count_image && !cl->render.common.target_error)
        return vkrt_error_set(err, "--sample-count-image needs --target-error (without it every "
                                   "pixel has --spp samples)");
    cl->render.scene_path = scene;
    cl->view.scene_path = scene;
    return true;
}
