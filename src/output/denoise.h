/*
 * denoise.h: Intel Open Image Denoise 2's RT filter on a finished frame (`--denoise`), for the
 * finish stage (finish.h) and the viewer.
 *
 * The library is loaded at run time, so vkrt builds and runs without it; only --denoise needs
 * it. libOpenImageDenoise.so.2 is looked for, in order:
 *   1. VKRT_OIDN_LIBRARY, when set: that file and nothing else;
 *   2. the project's .venv, where tools/setup-python installs PyPI's pyoidn wheel
 *      (.venv/lib/python3.X/site-packages/pyoidn/oidn/lib/): the .venv beside the folder that
 *      holds the vkrt binary (build/vkrt -> ./.venv), then the one in the source tree vkrt was
 *      built from;
 *   3. the dynamic linker's path (LD_LIBRARY_PATH, ldconfig's folders).
 * The library picks its device (OIDN_DEVICE_TYPE_DEFAULT): a GPU it supports (CUDA, HIP, SYCL),
 * else the CPU. Images cross to the device through OIDN buffers (a copy each way), so the same
 * code serves both.
 */
#ifndef VKRT_DENOISE_H
#define VKRT_DENOISE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "../error.h"

typedef struct vkrt_denoiser vkrt_denoiser;

typedef struct vkrt_denoiser_desc {
    bool interactive; /* the viewer: OIDN's balanced quality, faster than the final-frame one */
} vkrt_denoiser_desc;

/* Whether the library can be loaded (it is, and let go again; no device is made): for a
 * command to refuse --denoise before any work. False with err saying where it looked and how to
 * get it (tools/setup-python, VKRT_OIDN_LIBRARY). */
bool vkrt_denoise_library_check(vkrt_error *err);

/* Loads the library and makes its device. False with err set (the library missing, as for
 * vkrt_denoise_library_check, or its device failing); then nothing is left. */
bool vkrt_denoiser_create(vkrt_denoiser **out, const vkrt_denoiser_desc *desc, vkrt_error *err);

/* One line for --verbose: the library's version, its device ("CPU", "CUDA", ...) and the file
 * it was loaded from. Valid while d lives. */
const char *vkrt_denoiser_describe(const vkrt_denoiser *d);

/* A frame to denoise. albedo and normal are the first non-specular hit's (3 floats per pixel,
 * like rgb), or NULL; OIDN takes a normal only beside an albedo, so a normal without an albedo
 * is not used. */
typedef struct vkrt_denoise_input {
    uint32_t width, height;
    const float *rgb;    /* linear radiance (HDR), 3 floats per pixel, the top row first */
    const float *albedo; /* in [0, 1], or NULL */
    const float *normal; /* unit or zero vectors, any fixed space, or NULL */
    bool clean_aux;      /* albedo and normal are free of noise (OIDN's cleanAux): the filter
                            then trusts their edges fully; leave false for few-sample AOVs */
} vkrt_denoise_input;

/* Denoises in->rgb into out (width * height * 3 floats; may be in->rgb itself). Calls may come
 * from several threads: they run one at a time. The filter is kept while the size and the
 * inputs given stay the same, so a flythrough's frames reuse it. False with err set (the
 * library's message) on failure. */
bool vkrt_denoiser_run(vkrt_denoiser *d, const vkrt_denoise_input *in, float *out, vkrt_error *err);

/* Frees the filter, its buffers and the device. NULL does nothing. */
void vkrt_denoiser_destroy(vkrt_denoiser *d);

#endif
