/* cli.c: command-line parsing (see cli.h). */
#include "cli.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

const char *vkrt_usage(void)
{
    return "usage: vkrt render SCENE.cfg [options]   render every frame (camera) of a scene\n"
           "       vkrt view SCENE.cfg [options]     fly through a scene in a window\n"
           "       vkrt bench SCENE.cfg... [--accel A] [--json OUT.json] [--width W --height H]\n"
           "                  [--grid-density CELLS_PER_TRIANGLE] [--workgroup N] [--stats]\n"
           "                  [--bvh-width 2|4] [--ray-fetch static|dynamic]\n"
           "                  [--whole-scene] [--sort-diffuse CELLS] [--kernel-stats]\n"
           "                  [--bvh-leaf N] [--bvh-cost C] [--loads storage|texel]\n"
           "                  [--walk one-loop|nested]\n"
           "                                         time primary and shadow rays per structure\n"
           "       vkrt --list-devices               list Vulkan devices\n"
           "       vkrt --help | --version\n"
           "\n"
           "render options:\n"
           "  -o PATH           output file (.png or .exr); a pattern such as out/f%04d.png\n"
           "                    numbers the frames; overrides the scene's `output`\n"
           "  --width W         image width in pixels (overrides `resolution`)\n"
           "  --height H        image height in pixels\n"
           "  --spp N           samples per pixel (overrides `samples`)\n"
           "  --accel A         auto | brute | grid | bvh (overrides `accel`)\n"
           "  --verbose         say which acceleration structure was chosen and why, and its\n"
           "                    build statistics\n"
           "  --profile         time every dispatch of each frame (GPU timestamps) and print a\n"
           "                    table per depth and kernel: the frame is rendered again after\n"
           "                    300 ms of GPU warm-up, 11 times back to back, medians shown\n"
           "  --profile-repeat N  --profile with N timed frames instead of 11\n"
           "  --exposure STOPS  scale PNG output by 2^STOPS before the sRGB curve (EXR unchanged)\n"
           "  --device N        Vulkan device (see --list-devices); default: the first discrete\n"
           "                    GPU, else the first device\n"
           "  --validation      enable Vulkan validation layers (also VKRT_VALIDATION=1); any\n"
           "                    validation message makes the run fail\n"
           "  --resume          skip frames whose output files are already complete (a\n"
           "                    flythrough interrupted by Ctrl-C, a crash or a lost device)\n"
           "  --quiet           no summary on stderr\n"
           "  --list-devices    list Vulkan devices and exit\n"
           "  --help, --version\n"
           "\n"
           "view options: --width, --height, --spp, --accel, --exposure, --device, --validation\n"
           "  as for render; the window opens at the scene's resolution, from its first camera,\n"
           "  and a still picture gathers samples until it has --spp of them (default: the\n"
           "  scene's `samples`, at least 16)\n"
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

bool vkrt_options_parse(int argc, char **argv, vkrt_options *opts, vkrt_error *err)
{
    memset(opts, 0, sizeof *opts);
    opts->device = -1;
    const char *env = getenv("VKRT_VALIDATION");
    opts->validation = env && strcmp(env, "0") != 0 && *env;
    for (int i = 1; i < argc; ++i) {
        const char *arg = argv[i];
        const char *value = i + 1 < argc ? argv[i + 1] : NULL;
        uint32_t device;
        if (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0) {
            opts->command = VKRT_COMMAND_HELP;
            return true;
        } else if (strcmp(arg, "--version") == 0) {
            opts->command = VKRT_COMMAND_VERSION;
            return true;
        } else if (strcmp(arg, "--list-devices") == 0) {
            opts->command = VKRT_COMMAND_LIST_DEVICES;
            return true;
        } else if (strcmp(arg, "-o") == 0) {
            if (!value)
                return vkrt_error_set(err, "-o needs a path");
            opts->output = value;
            ++i;
        } else if (strcmp(arg, "--width") == 0) {
            if (!parse_u32(arg, value, 1, 16384, &opts->width, err))
                return false;
            ++i;
        } else if (strcmp(arg, "--height") == 0) {
            if (!parse_u32(arg, value, 1, 16384, &opts->height, err))
                return false;
            ++i;
        } else if (strcmp(arg, "--spp") == 0) {
            if (!parse_u32(arg, value, 1, 65536, &opts->samples, err))
                return false;
            ++i;
        } else if (strcmp(arg, "--device") == 0) {
            if (!parse_u32(arg, value, 0, 1000, &device, err))
                return false;
            opts->device = (int)device;
            ++i;
        } else if (strcmp(arg, "--exposure") == 0) {
            if (!parse_float(arg, value, &opts->exposure, err))
                return false;
            ++i;
        } else if (strcmp(arg, "--accel") == 0) {
            if (!value || !vkrt_accel_parse(value, &opts->accel))
                return vkrt_error_set(err, "--accel: '%s' is not one of auto, brute, grid, bvh",
                                      value ? value : "");
            opts->accel_given = true;
            ++i;
        } else if (strcmp(arg, "--grid-density") == 0) {
            if (!parse_float(arg, value, &opts->grid_density, err))
                return false;
            if (opts->grid_density <= 0 || opts->grid_density > 1000)
                return vkrt_error_set(err, "--grid-density: '%s' is not in (0, 1000]", value);
            ++i;
        } else if (strcmp(arg, "--workgroup") == 0) {
            if (!parse_u32(arg, value, 1, 1024, &opts->workgroup_size, err))
                return false;
            ++i;
        } else if (strcmp(arg, "--bvh-leaf") == 0) {
            if (!parse_u32(arg, value, 1, 16, &opts->bvh_max_leaf, err))
                return false;
            ++i;
        } else if (strcmp(arg, "--bvh-cost") == 0) {
            if (!parse_float(arg, value, &opts->bvh_traversal_cost, err))
                return false;
            if (!(opts->bvh_traversal_cost > 0 && opts->bvh_traversal_cost <= 100))
                return vkrt_error_set(err, "--bvh-cost: '%s' is not in (0, 100]", value);
            ++i;
        } else if (strcmp(arg, "--sort-diffuse") == 0) {
            if (!parse_u32(arg, value, 0, 16, &opts->sort_diffuse, err))
                return false;
            if (opts->sort_diffuse == 1)
                return vkrt_error_set(err, "--sort-diffuse: 1 cell sorts nothing; 0 (none) or 2..16");
            ++i;
        } else if (strcmp(arg, "--bvh-width") == 0) {
            if (!parse_u32(arg, value, 2, 4, &opts->bvh_width, err))
                return false;
            if (opts->bvh_width == 3)
                return vkrt_error_set(err, "--bvh-width: 3 is not one of 2, 4");
            ++i;
        } else if (strcmp(arg, "--loads") == 0) {
            if (!parse_choice(arg, value, "storage", "texel", &opts->loads, err))
                return false;
            ++i;
        } else if (strcmp(arg, "--walk") == 0) {
            if (!parse_choice(arg, value, "one-loop", "nested", &opts->walk, err))
                return false;
            ++i;
        } else if (strcmp(arg, "--ray-fetch") == 0) {
            if (!parse_choice(arg, value, "static", "dynamic", &opts->ray_fetch, err))
                return false;
            ++i;
        } else if (strcmp(arg, "--stats") == 0) {
            opts->stats = true;
        } else if (strcmp(arg, "--kernel-stats") == 0) {
            opts->kernel_stats = true;
        } else if (strcmp(arg, "--whole-scene") == 0) {
            opts->whole_scene = true;
        } else if (strcmp(arg, "--script") == 0 || strcmp(arg, "--record") == 0) {
            if (!value)
                return vkrt_error_set(err, "%s needs a path", arg);
            if (arg[2] == 's')
                opts->script = value;
            else
                opts->record = value;
            ++i;
        } else if (strcmp(arg, "--json") == 0) {
            if (!value)
                return vkrt_error_set(err, "--json needs a path");
            opts->json = value;
            ++i;
        } else if (strcmp(arg, "--resume") == 0) {
            opts->resume = true;
        } else if (strcmp(arg, "--verbose") == 0) {
            opts->verbose = true;
        } else if (strcmp(arg, "--profile") == 0) {
            opts->profile = true;
        } else if (strcmp(arg, "--profile-repeat") == 0) {
            if (!parse_u32(arg, value, 1, 1000, &opts->profile_repeat, err))
                return false;
            opts->profile = true;
            ++i;
        } else if (strcmp(arg, "--quiet") == 0) {
            opts->quiet = true;
        } else if (strcmp(arg, "--validation") == 0) {
            opts->validation = true;
        } else if (arg[0] == '-' && arg[1]) {
            return vkrt_error_set(err, "unknown option '%s' (see vkrt --help)", arg);
        } else if (opts->command == VKRT_COMMAND_NONE) {
            if (strcmp(arg, "render") == 0)
                opts->command = VKRT_COMMAND_RENDER;
            else if (strcmp(arg, "bench") == 0)
                opts->command = VKRT_COMMAND_BENCH;
            else if (strcmp(arg, "view") == 0)
                opts->command = VKRT_COMMAND_VIEW;
            else
                return vkrt_error_set(err, "unknown command '%s' (see vkrt --help)", arg);
        } else if (!opts->scene_path) {
            opts->scene_path = arg;
            opts->scene_paths[opts->scene_count++] = arg;
        } else if (opts->command == VKRT_COMMAND_BENCH &&
                   opts->scene_count < sizeof opts->scene_paths / sizeof *opts->scene_paths) {
            opts->scene_paths[opts->scene_count++] = arg;
        } else {
            return vkrt_error_set(err, "unexpected argument '%s'", arg);
        }
    }
    if (opts->command == VKRT_COMMAND_NONE)
        return vkrt_error_set(err, "no command given (see vkrt --help)");
    const char *name = opts->command == VKRT_COMMAND_BENCH  ? "bench"
                       : opts->command == VKRT_COMMAND_VIEW ? "view"
                                                            : "render";
    if (!opts->scene_path)
        return vkrt_error_set(err, "%s needs a scene file: vkrt %s SCENE.cfg", name, name);
    return true;
}
