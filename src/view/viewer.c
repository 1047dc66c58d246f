/*
 * viewer.c: `vkrt view` (see viewer.h): the window, its input and the frame loop.
 *
 * One frame of the loop:
 *   events (the window's, or the script's for this frame) -> keys held move the camera ->
 *   swapchain and renderer follow the window's size -> the camera differs from the one the image
 *   was traced from: start the image again -> fewer passes than the target: trace a few more ->
 *   something new to show: the display pass and present.
 * A still camera whose image has all its passes traces nothing, and the loop sleeps in
 * glfwWaitEvents until something happens, so a converged or minimised window costs no CPU.
 */
#define _POSIX_C_SOURCE 200809L
#include "viewer.h"

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "../gpu/context.h"
#include "../gpu/vk_check.h"
#include "../output/image_write.h"
#include "../render/renderer.h"
#include "../scene/scene.h"
#include "../scene/text_file.h"
#include "camera.h"
#include "display.h"
#include "script.h"
#include "view_denoise.h"

/* A frame aims to trace for about this long, so a fast GPU adds many passes per frame and a slow
 * one stays responsive with one. */
#define VIEW_FRAME_SECONDS (1.0 / 30.0)
/* Longest step the camera takes in one frame, so a slow frame does not jump it across the scene. */
#define VIEW_MAX_STEP_SECONDS 0.1
/* The time a scripted frame lasts: the same flight on every machine. */
#define VIEW_SCRIPT_FRAME_SECONDS (1.0 / 30.0)
/* How long the window's size must stay put before the renderer is rebuilt at it (a rebuild
 * compiles the kernels again); until then the old image is shown scaled. */
#define VIEW_RESIZE_SETTLE_SECONDS 0.25
/* Shift multiplies the speed by this. */
#define VIEW_SHIFT_SPEED 4.0f
/* How often the title's numbers are renewed. */
#define VIEW_TITLE_SECONDS 0.5

typedef struct viewer {
    const vkrt_view_desc *opts;
    const vkrt_scene *scene;
    GLFWwindow *window;
    gpu_context ctx;
    vkrt_render_desc desc;
    vkrt_renderer *renderer; /* NULL until created */
    view_display display;
    bool have_display;
    view_denoise denoised; /* --denoise: the image the window shows instead of the renderer's */
    view_camera camera;

    /* The image: the camera its passes were traced from, how many it holds, and a number that
     * changes whenever it starts again (for the log). */
    vkrt_config_camera traced;
    uint32_t passes;
    uint32_t active_pixels; /* with --target-error: pixels still sampling after the last pass */
    uint32_t version;
    double seconds_per_pass;

    bool keys[GLFW_KEY_LAST + 1];
    bool dragging;
    double cursor_x, cursor_y;
    bool quit;
    bool failed;          /* something went wrong (a screenshot, say): exit with 1 */
    bool swapchain_stale; /* the window's size changed, or presentation said so */
    bool redraw;          /* show the image again, though nothing new was traced */
    double resized_at;    /* when the framebuffer's size last changed */

    view_script script;
    size_t script_next;   /* the next event to play */
    uint32_t script_wait; /* frames still to wait before it */
    bool script_wait_converged;

    uint64_t frame;
    uint32_t screenshot_number;
    FILE *record;

    /* The title's numbers, over the last VIEW_TITLE_SECONDS. */
    double title_at, title_fps, title_rays_per_second;
    uint32_t title_frames;
    double title_trace_seconds;
    uint64_t title_rays;
} viewer;

/* ---------------------------------------------------------------------------------------------
 * Keys and names
 * ------------------------------------------------------------------------------------------- */

/* Script key names (script.h) to GLFW's key codes. */
static int key_code(const char *name)
{
    static const struct {
        const char *name;
        int key;
    } named[] = {
        {"space", GLFW_KEY_SPACE}, {"shift", GLFW_KEY_LEFT_SHIFT}, {"escape", GLFW_KEY_ESCAPE},
        {"esc", GLFW_KEY_ESCAPE},  {"plus", GLFW_KEY_KP_ADD},      {"minus", GLFW_KEY_MINUS},
        {"equal", GLFW_KEY_EQUAL}, {"enter", GLFW_KEY_ENTER},
    };
    if (name[0] && !name[1]) {
        if (name[0] >= 'a' && name[0] <= 'z')
            return GLFW_KEY_A + (name[0] - 'a');
        if (name[0] >= '0' && name[0] <= '9')
            return GLFW_KEY_0 + (name[0] - '0');
        if (name[0] == '+')
            return GLFW_KEY_KP_ADD;
        if (name[0] == '-')
            return GLFW_KEY_MINUS;
    }
    for (size_t i = 0; i < sizeof named / sizeof *named; ++i)
        if (strcmp(name, named[i].name) == 0)
            return named[i].key;
    return -1;
}

static bool held(const viewer *v, int key)
{
    return v->keys[key];
}

static float axis(const viewer *v, int positive, int positive2, int negative, int negative2)
{
    return (float)((held(v, positive) || (positive2 >= 0 && held(v, positive2))) -
                   (held(v, negative) || (negative2 >= 0 && held(v, negative2))));
}

static bool moving(const viewer *v)
{
    return axis(v, GLFW_KEY_W, -1, GLFW_KEY_S, -1) != 0 ||
           axis(v, GLFW_KEY_D, -1, GLFW_KEY_A, -1) != 0 ||
           axis(v, GLFW_KEY_E, GLFW_KEY_SPACE, GLFW_KEY_Q, GLFW_KEY_C) != 0;
}

/* ---------------------------------------------------------------------------------------------
 * Actions
 * ------------------------------------------------------------------------------------------- */

static float aspect(const viewer *v)
{
    return (float)v->desc.width / (float)v->desc.height;
}

/* The folder and name stem of the scene file, for screenshots: "scenes/x/scene.cfg" gives
 * "scenes/x/scene-view-", "models/duck.glb" "models/duck-view-". */
static char *screenshot_prefix(const char *scene_path)
{
    const char *slash = strrchr(scene_path, '/');
    const char *name = slash ? slash + 1 : scene_path;
    const char *dot = strrchr(name, '.');
    size_t stem = dot && dot != name ? (size_t)(dot - name) : strlen(name);
    size_t folder = (size_t)(name - scene_path);
    char *prefix = malloc(folder + stem + 8);
    if (prefix)
        sprintf(prefix, "%.*s%.*s-view-", (int)folder, scene_path, (int)stem, name);
    return prefix;
}

static bool exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

/* P: the window as PNG (what it shows) and the accumulated image as linear EXR, next to the scene
 * under the first number that names neither file yet. */
static void screenshot(viewer *v)
{
    vkrt_error err = {{0}};
    char *prefix = screenshot_prefix(v->opts->scene_path);
    size_t size = prefix ? strlen(prefix) + 16 : 0;
    char *png = malloc(size), *exr = malloc(size);
    VkExtent2D e = v->display.swapchain.extent;
    uint8_t *window = malloc((size_t)e.width * e.height * 3);
    float *linear = malloc((size_t)v->desc.width * v->desc.height * 3 * sizeof *linear);
    bool ok = prefix && png && exr && window && linear;
    if (!ok)
        vkrt_error_set(&err, "out of memory for a screenshot");
    for (; ok; ++v->screenshot_number) {
        snprintf(png, size, "%s%03u.png", prefix, v->screenshot_number);
        snprintf(exr, size, "%s%03u.exr", prefix, v->screenshot_number);
        if (!exists(png) && !exists(exr))
            break;
    }
    ok = ok && view_display_read(&v->display, window, &err) &&
         vkrt_renderer_read_image(v->renderer, v->passes, linear, &err) &&
         vkrt_image_write_png8(png, e.width, e.height, window, &err) &&
         vkrt_image_write_frame(exr, v->desc.width, v->desc.height, linear, &v->opts->finish,
                                &err);
    if (ok) {
        fprintf(stderr, "vkrt: screenshot %s (%ux%u, as shown) and %s (%u of %u samples)\n", png,
                e.width, e.height, exr, v->passes, v->desc.samples);
        ++v->screenshot_number;
    } else {
        fprintf(stderr, "vkrt: screenshot failed: %s\n", err.msg);
        v->failed = true;
    }
    free(linear);
    free(window);
    free(exr);
    free(png);
    free(prefix);
}

/* K: the camera as a scene.cfg line on stdout, and appended to --record's file. */
static void print_camera(viewer *v)
{
    char line[512];
    vkrt_error err = {{0}};
    if (!view_camera_format(&v->camera, line, sizeof line, &err)) {
        fprintf(stderr, "vkrt: %s\n", err.msg);
        v->failed = true;
        return;
    }
    printf("%s\n", line);
    fflush(stdout);
    if (v->record && (fprintf(v->record, "%s\n", line) < 0 || fflush(v->record) != 0)) {
        fprintf(stderr, "vkrt: %s: cannot append the camera\n", v->opts->record);
        v->failed = true;
    }
}

static void on_key(viewer *v, int key, bool down)
{
    if (key < 0 || key > GLFW_KEY_LAST)
        return;
    v->keys[key] = down;
    if (!down)
        return;
    switch (key) {
    case GLFW_KEY_ESCAPE:
        v->quit = true;
        break;
    case GLFW_KEY_R: {
        float speed = v->camera.speed;
        view_camera_init(&v->camera, &v->scene->cameras[0], speed);
        break;
    }
    case GLFW_KEY_F:
        view_camera_frame(&v->camera, v->scene->model.bounds_min, v->scene->model.bounds_max,
                          aspect(v));
        break;
    case GLFW_KEY_P:
        screenshot(v);
        break;
    case GLFW_KEY_K:
        print_camera(v);
        break;
    case GLFW_KEY_EQUAL:
    case GLFW_KEY_KP_ADD:
        view_camera_scale_speed(&v->camera, 1);
        break;
    case GLFW_KEY_MINUS:
    case GLFW_KEY_KP_SUBTRACT:
        view_camera_scale_speed(&v->camera, -1);
        break;
    default:
        break;
    }
}

static void on_cursor(viewer *v, double x, double y)
{
    if (v->dragging)
        view_camera_look(&v->camera, (float)(x - v->cursor_x), (float)(y - v->cursor_y));
    v->cursor_x = x;
    v->cursor_y = y;
}

/* ---------------------------------------------------------------------------------------------
 * GLFW callbacks: each hands its event to the functions above, which scripts call too.
 * ------------------------------------------------------------------------------------------- */

static viewer *of(GLFWwindow *window)
{
    return glfwGetWindowUserPointer(window);
}

static void key_callback(GLFWwindow *window, int key, int scancode, int action, int mods)
{
    (void)scancode;
    (void)mods;
    if (action != GLFW_REPEAT)
        on_key(of(window), key, action == GLFW_PRESS);
}

static void button_callback(GLFWwindow *window, int button, int action, int mods)
{
    (void)mods;
    viewer *v = of(window);
    if (button != GLFW_MOUSE_BUTTON_LEFT)
        return;
    v->dragging = action == GLFW_PRESS;
    glfwGetCursorPos(window, &v->cursor_x, &v->cursor_y);
}

static void cursor_callback(GLFWwindow *window, double x, double y)
{
    on_cursor(of(window), x, y);
}

static void scroll_callback(GLFWwindow *window, double dx, double dy)
{
    (void)dx;
    view_camera_scale_speed(&of(window)->camera, (float)dy);
}

static void framebuffer_callback(GLFWwindow *window, int width, int height)
{
    (void)width;
    (void)height;
    viewer *v = of(window);
    v->swapchain_stale = true;
    v->resized_at = glfwGetTime();
}

static void refresh_callback(GLFWwindow *window)
{
    of(window)->redraw = true;
}

static void close_callback(GLFWwindow *window)
{
    of(window)->quit = true;
}

static void error_callback(int code, const char *description)
{
    fprintf(stderr, "vkrt: GLFW error %#x: %s\n", (unsigned)code, description);
}

/* ---------------------------------------------------------------------------------------------
 * The script
 * ------------------------------------------------------------------------------------------- */

/* A still view is done at --spp, or with --target-error once no pixel is above it (the estimate
 * of glsl/lib/adaptive.glsl decides, as in vkrt render). */
static bool converged(const viewer *v)
{
    bool within = v->desc.target_error > 0 && v->passes > 0 && v->active_pixels == 0;
    return v->passes >= v->desc.samples || within;
}

static bool script_running(const viewer *v)
{
    return v->script.count > 0 && v->script_next <= v->script.count &&
           (v->script_next < v->script.count || v->script_wait || v->script_wait_converged);
}

/* Waits, briefly, for the window system to give the window the size a script asked for. */
static void settle_size(viewer *v, int width, int height)
{
    double until = glfwGetTime() + 2.0;
    int w = 0, h = 0;
    do {
        glfwWaitEventsTimeout(0.01);
        glfwGetFramebufferSize(v->window, &w, &h);
    } while ((w != width || h != height) && glfwGetTime() < until);
    v->resized_at = -1e9; /* no settling for a script: rebuild the renderer at once */
}

/* Plays the events due at the start of this frame. */
static void play_script(viewer *v)
{
    if (v->script_wait > 0) {
        --v->script_wait;
        return;
    }
    if (v->script_wait_converged) {
        if (!converged(v))
            return;
        v->script_wait_converged = false;
    }
    while (v->script_next < v->script.count && !v->quit) {
        const view_event *e = &v->script.events[v->script_next++];
        switch (e->kind) {
        case VIEW_EVENT_KEY_DOWN:
        case VIEW_EVENT_KEY_UP:
            on_key(v, e->key, e->kind == VIEW_EVENT_KEY_DOWN);
            break;
        case VIEW_EVENT_BUTTON_DOWN:
        case VIEW_EVENT_BUTTON_UP:
            v->dragging = e->kind == VIEW_EVENT_BUTTON_DOWN;
            break;
        case VIEW_EVENT_MOVE:
            on_cursor(v, v->cursor_x + e->x, v->cursor_y + e->y);
            break;
        case VIEW_EVENT_SCROLL:
            view_camera_scale_speed(&v->camera, e->y);
            break;
        case VIEW_EVENT_RESIZE:
            glfwSetWindowSize(v->window, (int)e->x, (int)e->y);
            settle_size(v, (int)e->x, (int)e->y);
            break;
        case VIEW_EVENT_WAIT:
            /* This frame is the first of the wait. */
            if (e->frames > 0) {
                v->script_wait = e->frames - 1;
                return;
            }
            break;
        case VIEW_EVENT_WAIT_CONVERGED:
            /* Checked from the next frame on: events just played (a key, a resize) may change
             * the camera or the image only in this frame's update. */
            v->script_wait_converged = true;
            return;
        }
    }
}

/* ---------------------------------------------------------------------------------------------
 * Setup
 * ------------------------------------------------------------------------------------------- */

static bool create_surface(void *user, VkInstance instance, VkSurfaceKHR *surface, vkrt_error *err)
{
    viewer *v = user;
    VkResult result = glfwCreateWindowSurface(instance, v->window, NULL, surface);
    if (result != VK_SUCCESS)
        return vkrt_error_set(err, "glfwCreateWindowSurface failed: %s", gpu_result_name(result));
    return true;
}

static bool open_window(viewer *v, vkrt_error *err)
{
    if (!glfwInit()) {
        const char *why = NULL;
        glfwGetError(&why);
        return vkrt_error_set(err,
                              "cannot open a window (%s); vkrt view needs a display, "
                              "vkrt render does not",
                              why ? why : "glfwInit failed");
    }
    /* From here on GLFW's errors are printed as they happen (setup's are reported above). */
    glfwSetErrorCallback(error_callback);
    if (!glfwVulkanSupported())
        return vkrt_error_set(err, "GLFW found no Vulkan loader for windows");
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    char title[256];
    snprintf(title, sizeof title, "vkrt view: %s", v->opts->scene_path);
    v->window = glfwCreateWindow((int)v->desc.width, (int)v->desc.height, title, NULL, NULL);
    if (!v->window) {
        const char *why = NULL;
        glfwGetError(&why);
        return vkrt_error_set(err, "cannot open a %ux%u window: %s", v->desc.width, v->desc.height,
                              why ? why : "glfwCreateWindow failed");
    }
    glfwSetWindowUserPointer(v->window, v);
    glfwSetKeyCallback(v->window, key_callback);
    glfwSetMouseButtonCallback(v->window, button_callback);
    glfwSetCursorPosCallback(v->window, cursor_callback);
    glfwSetScrollCallback(v->window, scroll_callback);
    glfwSetFramebufferSizeCallback(v->window, framebuffer_callback);
    glfwSetWindowRefreshCallback(v->window, refresh_callback);
    glfwSetWindowCloseCallback(v->window, close_callback);
    glfwGetCursorPos(v->window, &v->cursor_x, &v->cursor_y);
    return true;
}

static bool create_gpu(viewer *v, vkrt_error *err)
{
    uint32_t count = 0;
    const char **extensions = glfwGetRequiredInstanceExtensions(&count);
    if (!extensions)
        return vkrt_error_set(err, "GLFW names no Vulkan instance extensions for windows");
    gpu_context_desc desc = {
        .device_index = v->opts->device,
        .validation = v->opts->validation,
        .instance_extensions = extensions,
        .instance_extension_count = count,
        .create_surface = create_surface,
        .surface_user = v,
    };
    int w, h;
    glfwGetFramebufferSize(v->window, &w, &h);
    if (!gpu_context_create(&v->ctx, &desc, err) ||
        !vkrt_renderer_create(&v->renderer, &v->ctx, v->scene, &v->desc, err))
        return false;
    if (w <= 0 || h <= 0) {
        w = (int)v->desc.width;
        h = (int)v->desc.height;
    }
    if (!view_display_create(&v->display, &v->ctx, (uint32_t)w, (uint32_t)h, err))
        return false;
    v->have_display = true;
    return true;
}

/* ---------------------------------------------------------------------------------------------
 * The frame
 * ------------------------------------------------------------------------------------------- */

/* Rebuilds the renderer at the window's size once the size has held still; the image starts
 * again. */
static bool follow_window_size(viewer *v, double now, vkrt_error *err)
{
    VkExtent2D e = v->display.swapchain.extent;
    if ((e.width == v->desc.width && e.height == v->desc.height) ||
        now - v->resized_at < VIEW_RESIZE_SETTLE_SECONDS)
        return true;
    /* The display's frames in flight read the old image. */
    if (vkQueueWaitIdle(v->ctx.queue) != VK_SUCCESS)
        return vkrt_error_set(err, "waiting for the GPU before a resize failed");
    vkrt_renderer_destroy(v->renderer);
    v->renderer = NULL;
    v->desc.width = e.width;
    v->desc.height = e.height;
    if (!vkrt_renderer_create(&v->renderer, &v->ctx, v->scene, &v->desc, err))
        return vkrt_error_prefix(err, "resizing the image to %ux%u", e.width, e.height);
    v->passes = 0;
    memset(&v->traced, 0, sizeof v->traced); /* forces a new image */
    return true;
}

/* How many passes this frame traces: as many as fit VIEW_FRAME_SECONDS at the measured speed,
 * at least one, at most what the target lacks. */
static uint32_t passes_this_frame(const viewer *v)
{
    uint32_t missing = v->desc.samples - v->passes;
    double fit = v->seconds_per_pass > 0 ? VIEW_FRAME_SECONDS / v->seconds_per_pass : 1;
    uint32_t n = fit < 1 ? 1 : fit > missing ? missing : (uint32_t)fit;
    return n ? n : 1;
}

static void update_title(viewer *v, double now, bool force)
{
    double span = now - v->title_at;
    if (span < VIEW_TITLE_SECONDS && !force)
        return;
    if (span > 0 && v->title_frames) {
        v->title_fps = v->title_frames / span;
        v->title_rays_per_second =
            v->title_trace_seconds > 0 ? v->title_rays / v->title_trace_seconds : 0;
    }
    char title[512];
    snprintf(title, sizeof title, "vkrt view: %s | %.1f fps | %.3g Mrays/s | %u/%u spp%s",
             v->opts->scene_path, v->title_fps, v->title_rays_per_second * 1e-6, v->passes,
             v->desc.samples, converged(v) ? ", converged" : "");
    glfwSetWindowTitle(v->window, title);
    v->title_at = now;
    v->title_frames = 0;
    v->title_trace_seconds = 0;
    v->title_rays = 0;
}

static bool frame(viewer *v, double dt, bool log, vkrt_error *err)
{
    ++v->frame;
    /* Keys held move the camera; Shift speeds it up. */
    float boost =
        held(v, GLFW_KEY_LEFT_SHIFT) || held(v, GLFW_KEY_RIGHT_SHIFT) ? VIEW_SHIFT_SPEED : 1.0f;
    view_camera_move(&v->camera, axis(v, GLFW_KEY_W, -1, GLFW_KEY_S, -1),
                     axis(v, GLFW_KEY_D, -1, GLFW_KEY_A, -1),
                     axis(v, GLFW_KEY_E, GLFW_KEY_SPACE, GLFW_KEY_Q, GLFW_KEY_C),
                     (float)dt * boost);

    int w, h;
    glfwGetFramebufferSize(v->window, &w, &h);
    if (v->swapchain_stale && w > 0 && h > 0) {
        if (!view_display_resize(&v->display, (uint32_t)w, (uint32_t)h, err))
            return false;
        v->swapchain_stale = false;
        v->redraw = true;
    }
    double now = glfwGetTime();
    if (!follow_window_size(v, now, err))
        return false;

    vkrt_config_camera camera;
    view_camera_to_config(&v->camera, &camera);
    if (memcmp(&camera, &v->traced, sizeof camera) != 0) {
        v->traced = camera;
        v->passes = 0;
        ++v->version;
    }
    uint32_t traced = 0;
    if (!converged(v)) {
        traced = passes_this_frame(v);
        vkrt_frame_stats stats;
        if (!vkrt_renderer_add_samples(v->renderer, &v->traced, 0, v->passes, traced, &stats, err))
            return false;
        v->passes += traced;
        v->active_pixels = stats.active_pixels;
        v->seconds_per_pass = stats.seconds / traced;
        v->title_trace_seconds += stats.seconds;
        v->title_rays += stats.primary_rays + stats.shadow_rays + stats.secondary_rays;
    }
    if (log)
        fprintf(stderr, "vkrt: view: frame %llu view %u passes %u/%u traced %u\n",
                (unsigned long long)v->frame, v->version, v->passes, v->desc.samples, traced);
    vkrt_denoiser *denoiser = v->opts->finish.denoiser;
    if (traced && denoiser) {
        if (!view_denoise_update(&v->denoised, &v->ctx, v->renderer, denoiser, v->desc.width,
                                 v->desc.height, v->passes, err))
            return false;
        if (log)
            fprintf(stderr,
                    "vkrt: view: denoised frame %llu: read %.1f ms, denoise %.1f ms, "
                    "upload %.1f ms\n",
                    (unsigned long long)v->frame, v->denoised.read_ms, v->denoised.denoise_ms,
                    v->denoised.upload_ms);
    }
    if (traced || v->redraw) {
        bool out_of_date;
        /* Denoised, the image is one pass of finished radiance. */
        bool present_ok =
            denoiser && v->denoised.image.buffer
                ? view_display_present(&v->display, &v->denoised.image, v->desc.width,
                                       v->desc.height, 1, &v->opts->finish, &out_of_date, err)
                : view_display_present(&v->display, vkrt_renderer_image(v->renderer), v->desc.width,
                                       v->desc.height,
                                       vkrt_renderer_per_pixel_counts(v->renderer) ? 0 : v->passes,
                                       &v->opts->finish, &out_of_date, err);
        if (!present_ok)
            return false;
        v->redraw = out_of_date;
        v->swapchain_stale |= out_of_date;
        ++v->title_frames;
    }
    update_title(v, now, traced && converged(v));
    return true;
}

static bool run(viewer *v, vkrt_error *err)
{
    bool scripted = v->script.count > 0;
    double last = glfwGetTime();
    bool was_idle = false;
    v->redraw = true;
    while (!v->quit) {
        int w, h;
        glfwGetFramebufferSize(v->window, &w, &h);
        bool minimised = w == 0 || h == 0 || glfwGetWindowAttrib(v->window, GLFW_ICONIFIED);
        bool busy =
            !converged(v) || moving(v) || v->redraw || v->swapchain_stale || script_running(v);
        bool resize_pending = v->display.swapchain.extent.width != v->desc.width ||
                              v->display.swapchain.extent.height != v->desc.height;
        if (minimised) {
            glfwWaitEvents();
            was_idle = true;
            continue;
        }
        if (busy) {
            glfwPollEvents();
        } else if (resize_pending) {
            glfwWaitEventsTimeout(VIEW_RESIZE_SETTLE_SECONDS);
        } else {
            glfwWaitEvents();
            was_idle = true;
        }
        /* A script's frames last a fixed time; once it has ended, the clock's. */
        bool scripting = script_running(v);
        if (scripting)
            play_script(v);
        if (v->quit)
            break;
        double now = glfwGetTime();
        double dt = scripting  ? VIEW_SCRIPT_FRAME_SECONDS
                    : was_idle ? 0
                               : fmin(now - last, VIEW_MAX_STEP_SECONDS);
        last = now;
        was_idle = false;
        if (!frame(v, dt, scripted || v->opts->verbose, err))
            return false;
    }
    return true;
}

/* ---------------------------------------------------------------------------------------------
 * The command
 * ------------------------------------------------------------------------------------------- */

static void close_viewer(viewer *v)
{
    view_denoise_free(&v->denoised, &v->ctx);
    if (v->have_display)
        view_display_destroy(&v->display);
    vkrt_renderer_destroy(v->renderer);
}

int vkrt_view_run(const vkrt_view_desc *opts)
{
    viewer *v = calloc(1, sizeof *v);
    if (!v) {
        fprintf(stderr, "vkrt: out of memory\n");
        return 1;
    }
    v->opts = opts;
    v->scene = opts->scene;
    v->desc = opts->render;
    vkrt_error err = {{0}};
    bool ok = true;
    if (opts->script)
        ok = view_script_load(opts->script, key_code, &v->script, &err);
    if (ok && opts->record) {
        v->record = fopen(opts->record, "a");
        if (!v->record)
            ok = vkrt_error_set(&err, "%s: cannot open for appending camera lines", opts->record);
    }
    if (ok) {
        view_camera_init(
            &v->camera, &v->scene->cameras[0],
            view_camera_default_speed(v->scene->model.bounds_min, v->scene->model.bounds_max));
        ok = open_window(v, &err) && create_gpu(v, &err);
    }
    if (ok && !opts->quiet) {
        const char *why;
        vkrt_integrator integrator = vkrt_renderer_integrator(v->renderer, &why);
        fprintf(stderr,
                "vkrt: view: %s | %u triangles | accel %s | integrator %s | %ux%u | %u spp\n",
                v->ctx.properties.deviceName, v->scene->model.triangle_count,
                vkrt_accel_name(vkrt_renderer_accel_stats(v->renderer)->kind),
                vkrt_integrator_name(integrator), v->desc.width, v->desc.height, v->desc.samples);
        if (opts->verbose)
            fprintf(stderr, "vkrt: integrator %s: %s\n", vkrt_integrator_name(integrator), why);
    }
    ok = ok && run(v, &err);
    close_viewer(v);
    if (v->ctx.instance || v->ctx.validation_messages) {
        vkrt_error finish = {{0}};
        if (!gpu_context_finish(&v->ctx, &finish) && ok) {
            ok = false;
            err = finish;
        }
    }
    if (v->window)
        glfwDestroyWindow(v->window);
    glfwTerminate();
    if (!ok)
        fprintf(stderr, "vkrt: %s\n", err.msg);
    else if (!opts->quiet)
        fprintf(stderr, "vkrt: view: %llu frames\n", (unsigned long long)v->frame);
    int status = ok && !v->failed ? 0 : 1;
    if (v->record && fclose(v->record) != 0) {
        fprintf(stderr, "vkrt: %s: cannot close\n", opts->record);
        status = 1;
    }
    view_script_free(&v->script);
    free(v);
    return status;
}
