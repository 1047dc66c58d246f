/*
 * rtpipe_shaders.c: compiling the embedded ray tracing shaders (see rtpipe_shaders.h).
 *
 * The shaders include "shared.h", vkrt's own (glsl/shared.h), so that Ray and Hit are the very
 * structs vkrt's kernels read and write: a name not among this tool's sources is looked up among
 * vkrt's embedded kernels.
 */
#define _POSIX_C_SOURCE 200809L
#include "rtpipe_shaders.h"

#include <stdlib.h>
#include <string.h>

#include "render/kernel_sources.h"

/* Generated at build time from this folder's shaders (tools/embed_glsl.py --table). */
extern const vkrt_kernel_source rtpipe_shader_sources[];

static const char *const paths[RTPIPE_STAGES] = {
    [RTPIPE_RAYGEN] = "raygen.rgen",
    [RTPIPE_MISS] = "miss.rmiss",
    [RTPIPE_SHADOW_MISS] = "shadow.rmiss",
    [RTPIPE_CLOSEST_HIT] = "closest.rchit",
};

static const gpu_shader_stage stages[RTPIPE_STAGES] = {
    [RTPIPE_RAYGEN] = GPU_SHADER_RAYGEN,
    [RTPIPE_MISS] = GPU_SHADER_MISS,
    [RTPIPE_SHADOW_MISS] = GPU_SHADER_MISS,
    [RTPIPE_CLOSEST_HIT] = GPU_SHADER_CLOSEST_HIT,
};

const char *rtpipe_shader_path(int stage)
{
    return paths[stage];
}

gpu_shader_stage rtpipe_shader_stage(int stage)
{
    return stages[stage];
}

static char *lookup(void *user, const char *path)
{
    (void)user;
    for (const vkrt_kernel_source *k = rtpipe_shader_sources; k->path; ++k)
        if (strcmp(k->path, path) == 0)
            return strdup(k->text);
    return vkrt_kernel_source_lookup(NULL, path);
}

bool rtpipe_shaders_compile(rtpipe_shaders *s, vkrt_error *err)
{
    memset(s, 0, sizeof *s);
    gpu_shader_sources sources = {.lookup = lookup, .display_prefix = "research/yardsticks/rtpipe_bench/"};
    for (int i = 0; i < RTPIPE_STAGES; ++i)
        if (!gpu_shader_compile_stage(&sources, paths[i], stages[i], &s->spirv[i], &s->words[i],
                                      err)) {
            rtpipe_shaders_free(s);
            return false;
        }
    return true;
}

void rtpipe_shaders_free(rtpipe_shaders *s)
{
    for (int i = 0; i < RTPIPE_STAGES; ++i)
        free(s->spirv[i]);
    memset(s, 0, sizeof *s);
}
