/*
 * denoise.c: Open Image Denoise loaded at run time, and its RT filter on a frame (denoise.h).
 */
#define _GNU_SOURCE /* RTLD_NODELETE */
#include "denoise.h"

#include <dlfcn.h>
#include <glob.h>
#include <limits.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "oidn.h"

#ifndef VKRT_SOURCE_ROOT
#define VKRT_SOURCE_ROOT ""
#endif

static const char oidn_soname[] = "libOpenImageDenoise.so.2";
/* Where pip puts the pyoidn wheel's library inside a virtual environment. */
static const char venv_library[] =
    "/.venv/lib/python3*/site-packages/pyoidn/oidn/lib/libOpenImageDenoise.so.2";
/* What a message says to get the library. */
static const char how_to_get[] =
    "run tools/setup-python (it installs PyPI's pyoidn, which ships the library, into .venv), "
    "or set VKRT_OIDN_LIBRARY to the path of a libOpenImageDenoise.so.2";

/* The oldest library the API of oidn.h is: 2.0 renamed the Set/Get functions we call. */
enum { OIDN_LEAST_VERSION = 20000 };

typedef struct oidn_library {
    void *handle;
    char path[PATH_MAX];
    oidn_api api;
} oidn_library;

/* ---------------------------------------------------------------------------------------------
 * Finding and loading the library
 * ------------------------------------------------------------------------------------------- */

static const struct {
    const char *name;
    size_t offset;
} api_symbols[] = {
#define SYMBOL(f)                                                                                  \
    {                                                                                              \
#f, offsetof(oidn_api, f)                                                                  \
    }
    SYMBOL(oidnNewDevice),      SYMBOL(oidnCommitDevice),   SYMBOL(oidnGetDeviceInt),
    SYMBOL(oidnGetDeviceError), SYMBOL(oidnReleaseDevice),  SYMBOL(oidnNewBuffer),
    SYMBOL(oidnWriteBuffer),    SYMBOL(oidnReadBuffer),     SYMBOL(oidnReleaseBuffer),
    SYMBOL(oidnNewFilter),      SYMBOL(oidnSetFilterImage), SYMBOL(oidnSetFilterBool),
    SYMBOL(oidnSetFilterInt),   SYMBOL(oidnCommitFilter),   SYMBOL(oidnExecuteFilter),
    SYMBOL(oidnReleaseFilter),
#undef SYMBOL
};

/* dlopen of path (a file, or a bare soname for the linker's search), every function of oidn.h
 * resolved. The library stays mapped after dlclose (RTLD_NODELETE): its thread pool may outlive
 * a device, and unloading code under running threads is what that avoids. */
static bool library_open(oidn_library *lib, const char *path, char *why, size_t why_size)
{
    void *handle = dlopen(path, RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE);
    if (!handle) {
        const char *e = dlerror();
        snprintf(why, why_size, "%s", e ? e : "cannot be loaded");
        return false;
    }
    for (size_t i = 0; i < sizeof api_symbols / sizeof *api_symbols; ++i) {
        void *symbol = dlsym(handle, api_symbols[i].name);
        if (!symbol) {
            snprintf(why, why_size, "it has no %s: not Open Image Denoise 2", api_symbols[i].name);
            dlclose(handle);
            return false;
        }
        /* POSIX lets a dlsym result stand for a function pointer of the same size. */
        memcpy((char *)&lib->api + api_symbols[i].offset, &symbol, sizeof symbol);
    }
    lib->handle = handle;
    snprintf(lib->path, sizeof lib->path, "%s", path);
    return true;
}

/* The folder above the one that holds the running binary (build/vkrt -> the checkout), or "". */
static void binary_parent(char *out, size_t size)
{
    char exe[PATH_MAX];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    out[0] = '\0';
    if (n <= 0)
        return;
    exe[n] = '\0';
    for (int up = 0; up < 2; ++up) {
        char *slash = strrchr(exe, '/');
        if (!slash)
            return;
        *slash = '\0';
    }
    snprintf(out, size, "%s", exe[0] ? exe : "/");
}

/* The pyoidn library under root's .venv, loaded; false (why appended to tried) where there is
 * none or it does not load. */
static bool library_open_venv(oidn_library *lib, const char *root, char *tried, size_t tried_size)
{
    if (!root[0])
        return false;
    char pattern[PATH_MAX];
    if (snprintf(pattern, sizeof pattern, "%s%s", root, venv_library) >= (int)sizeof pattern)
        return false;
    glob_t found;
    bool ok = false;
    size_t used = strlen(tried);
    if (glob(pattern, 0, NULL, &found) == 0) {
        char why[512];
        for (size_t i = 0; i < found.gl_pathc && !ok; ++i) {
            ok = library_open(lib, found.gl_pathv[i], why, sizeof why);
            if (!ok)
                snprintf(tried + used, tried_size - used, "%s%s: %s", used ? "; " : "",
                         found.gl_pathv[i], why);
        }
        globfree(&found);
    } else {
        snprintf(tried + used, tried_size - used, "%s%s/.venv", used ? "; " : "", root);
    }
    return ok;
}

/* The search of denoise.h, in its order. */
static bool library_find(oidn_library *lib, vkrt_error *err)
{
    *lib = (oidn_library){0};
    char why[512];
    const char *forced = getenv("VKRT_OIDN_LIBRARY");
    if (forced && forced[0]) {
        if (library_open(lib, forced, why, sizeof why))
            return true;
        return vkrt_error_set(err,
                              "--denoise: VKRT_OIDN_LIBRARY=%s: cannot load it: %s; unset it to "
                              "look in .venv and on the linker path, or %s",
                              forced, why, how_to_get);
    }
    char tried[768] = "", root[PATH_MAX];
    binary_parent(root, sizeof root);
    if (library_open_venv(lib, root, tried, sizeof tried))
        return true;
    if (strcmp(root, VKRT_SOURCE_ROOT) != 0 &&
        library_open_venv(lib, VKRT_SOURCE_ROOT, tried, sizeof tried))
        return true;
    if (library_open(lib, oidn_soname, why, sizeof why))
        return true;
    return vkrt_error_set(err,
                          "--denoise needs Intel Open Image Denoise 2 (%s), which is neither in "
                          "the project's .venv (%s) nor on the linker path: %s",
                          oidn_soname, tried[0] ? tried : "none found", how_to_get);
}

bool vkrt_denoise_library_check(vkrt_error *err)
{
    oidn_library lib;
    if (!library_find(&lib, err))
        return false;
    dlclose(lib.handle);
    return true;
}

/* ---------------------------------------------------------------------------------------------
 * The denoiser
 * ------------------------------------------------------------------------------------------- */

/* What the filter was committed for: a frame with another shape needs a new one. */
typedef struct filter_shape {
    uint32_t width, height;
    bool albedo, normal, clean_aux;
} filter_shape;

struct vkrt_denoiser {
    oidn_library lib;
    bool interactive;
    OIDNDevice device;
    char description[PATH_MAX + 128];
    pthread_mutex_t lock; /* one run at a time: the filter and its buffers are shared */
    OIDNFilter filter;    /* NULL until the first run */
    filter_shape shape;
    OIDNBuffer color, albedo, normal, output;
};

/* The device's pending error as "what: message"; false when there is one. */
static bool device_ok(vkrt_denoiser *d, const char *what, vkrt_error *err)
{
    const char *message = NULL;
    OIDNError code = d->lib.api.oidnGetDeviceError(d->device, &message);
    if (code == OIDN_ERROR_NONE)
        return true;
    return vkrt_error_set(err, "denoising: %s: %s (Open Image Denoise error %d)", what,
                          message && message[0] ? message : "failed", (int)code);
}

static const char *device_type_name(int type)
{
    switch (type) {
    case OIDN_DEVICE_TYPE_CPU:
        return "CPU";
    case OIDN_DEVICE_TYPE_SYCL:
        return "SYCL";
    case OIDN_DEVICE_TYPE_CUDA:
        return "CUDA";
    case OIDN_DEVICE_TYPE_HIP:
        return "HIP";
    case OIDN_DEVICE_TYPE_METAL:
        return "Metal";
    default:
        return "unknown";
    }
}

bool vkrt_denoiser_create(vkrt_denoiser **out, const vkrt_denoiser_desc *desc, vkrt_error *err)
{
    *out = NULL;
    vkrt_denoiser *d = calloc(1, sizeof *d);
    if (!d)
        return vkrt_error_set(err, "out of memory for the denoiser");
    if (!library_find(&d->lib, err)) {
        free(d);
        return false;
    }
    d->interactive = desc && desc->interactive;
    const oidn_api *api = &d->lib.api;
    d->device = api->oidnNewDevice(OIDN_DEVICE_TYPE_DEFAULT);
    if (!d->device) {
        const char *message = NULL;
        api->oidnGetDeviceError(NULL, &message);
        vkrt_error_set(err, "denoising: %s: no device: %s", d->lib.path,
                       message && message[0] ? message : "the library made none");
        dlclose(d->lib.handle);
        free(d);
        return false;
    }
    api->oidnCommitDevice(d->device);
    int version = api->oidnGetDeviceInt(d->device, "version");
    bool ok = device_ok(d, "starting its device", err);
    if (ok && version < OIDN_LEAST_VERSION)
        ok = vkrt_error_set(err, "denoising: %s is Open Image Denoise %d.%d, older than 2.0",
                            d->lib.path, version / 10000, version / 100 % 100);
    if (!ok || pthread_mutex_init(&d->lock, NULL) != 0) {
        if (ok)
            vkrt_error_set(err, "denoising: cannot make a lock");
        api->oidnReleaseDevice(d->device);
        dlclose(d->lib.handle);
        free(d);
        return false;
    }
    snprintf(d->description, sizeof d->description,
             "Open Image Denoise %d.%d.%d, %s device, %s quality (%s)", version / 10000,
             version / 100 % 100, version % 100,
             device_type_name(api->oidnGetDeviceInt(d->device, "type")),
             d->interactive ? "balanced" : "high", d->lib.path);
    *out = d;
    return true;
}

const char *vkrt_denoiser_describe(const vkrt_denoiser *d)
{
    return d->description;
}

static bool same_shape(const filter_shape *a, const filter_shape *b)
{
    return a->width == b->width && a->height == b->height && a->albedo == b->albedo &&
           a->normal == b->normal && a->clean_aux == b->clean_aux;
}

static void release_filter(vkrt_denoiser *d)
{
    const oidn_api *api = &d->lib.api;
    if (d->filter)
        api->oidnReleaseFilter(d->filter);
    OIDNBuffer *buffers[] = {&d->color, &d->albedo, &d->normal, &d->output};
    for (size_t i = 0; i < sizeof buffers / sizeof *buffers; ++i) {
        if (*buffers[i])
            api->oidnReleaseBuffer(*buffers[i]);
        *buffers[i] = NULL;
    }
    d->filter = NULL;
    d->shape = (filter_shape){0};
}

/* The RT filter for frames of this shape, its buffers bound, committed. */
static bool make_filter(vkrt_denoiser *d, const filter_shape *shape, vkrt_error *err)
{
    const oidn_api *api = &d->lib.api;
    size_t bytes = (size_t)shape->width * shape->height * 3 * sizeof(float);
    d->color = api->oidnNewBuffer(d->device, bytes);
    d->output = api->oidnNewBuffer(d->device, bytes);
    d->albedo = shape->albedo ? api->oidnNewBuffer(d->device, bytes) : NULL;
    d->normal = shape->normal ? api->oidnNewBuffer(d->device, bytes) : NULL;
    d->filter = api->oidnNewFilter(d->device, "RT");
    bool ok = device_ok(d, "making the RT filter and its buffers", err);
    if (ok && (!d->filter || !d->color || !d->output || (shape->albedo && !d->albedo) ||
               (shape->normal && !d->normal)))
        ok = vkrt_error_set(err, "denoising: the library made no RT filter or buffers");
    if (!ok) {
        release_filter(d);
        return false;
    }
    struct {
        const char *name;
        OIDNBuffer buffer;
    } images[] = {
        {"color", d->color}, {"albedo", d->albedo}, {"normal", d->normal}, {"output", d->output}};
    for (size_t i = 0; i < sizeof images / sizeof *images; ++i)
        if (images[i].buffer)
            api->oidnSetFilterImage(d->filter, images[i].name, images[i].buffer, OIDN_FORMAT_FLOAT3,
                                    shape->width, shape->height, 0, 0, 0);
    api->oidnSetFilterBool(d->filter, "hdr", true);
    if (shape->albedo)
        api->oidnSetFilterBool(d->filter, "cleanAux", shape->clean_aux);
    api->oidnSetFilterInt(d->filter, "quality",
                          d->interactive ? OIDN_QUALITY_BALANCED : OIDN_QUALITY_HIGH);
    api->oidnCommitFilter(d->filter);
    if (!device_ok(d, "setting up the RT filter", err)) {
        release_filter(d);
        return false;
    }
    d->shape = *shape;
    return true;
}

bool vkrt_denoiser_run(vkrt_denoiser *d, const vkrt_denoise_input *in, float *out, vkrt_error *err)
{
    if (!in->rgb || in->width == 0 || in->height == 0)
        return vkrt_error_set(err, "denoising: an empty image (%ux%u)", in->width, in->height);
    if ((uint64_t)in->width * in->height > SIZE_MAX / (3 * sizeof(float)))
        return vkrt_error_set(err, "denoising: image %ux%u is too large", in->width, in->height);
    filter_shape shape = {.width = in->width,
                          .height = in->height,
                          .albedo = in->albedo != NULL,
                          .normal = in->albedo && in->normal,
                          .clean_aux = in->albedo && in->clean_aux};
    const oidn_api *api = &d->lib.api;
    size_t bytes = (size_t)in->width * in->height * 3 * sizeof(float);
    pthread_mutex_lock(&d->lock);
    bool ok = true;
    if (!d->filter || !same_shape(&shape, &d->shape)) {
        release_filter(d);
        ok = make_filter(d, &shape, err);
    }
    if (ok) {
        api->oidnWriteBuffer(d->color, 0, bytes, in->rgb);
        if (shape.albedo)
            api->oidnWriteBuffer(d->albedo, 0, bytes, in->albedo);
        if (shape.normal)
            api->oidnWriteBuffer(d->normal, 0, bytes, in->normal);
        api->oidnExecuteFilter(d->filter);
        api->oidnReadBuffer(d->output, 0, bytes, out);
        ok = device_ok(d, "running the RT filter", err);
    }
    pthread_mutex_unlock(&d->lock);
    return ok;
}

void vkrt_denoiser_destroy(vkrt_denoiser *d)
{
    if (!d)
        return;
    release_filter(d);
    d->lib.api.oidnReleaseDevice(d->device);
    pthread_mutex_destroy(&d->lock);
    dlclose(d->lib.handle);
    free(d);
}
