/*
 * rtpipe_shaders.h: the ray tracing pipeline's shaders (raygen.rgen, miss.rmiss, shadow.rmiss,
 * closest.rchit beside this file), embedded in the binary at build time and compiled to SPIR-V
 * 1.4 by glslang at startup, as vkrt compiles its kernels. Needs no device.
 */
#ifndef RTPIPE_SHADERS_H
#define RTPIPE_SHADERS_H

#include <stddef.h>
#include <stdint.h>

#include "error.h"
#include "gpu/shader.h"

/* The pipeline's stages, in the order of its shader groups and SBT records. */
enum { RTPIPE_RAYGEN, RTPIPE_MISS, RTPIPE_SHADOW_MISS, RTPIPE_CLOSEST_HIT, RTPIPE_STAGES };

typedef struct rtpipe_shaders {
    uint32_t *spirv[RTPIPE_STAGES];
    size_t words[RTPIPE_STAGES];
} rtpipe_shaders;

/* The source file and glslang stage of each of the RTPIPE_STAGES. */
const char *rtpipe_shader_path(int stage);
gpu_shader_stage rtpipe_shader_stage(int stage);

/* Compiles every stage. On failure err names the file and line, and nothing is left allocated. */
bool rtpipe_shaders_compile(rtpipe_shaders *s, vkrt_error *err);

/* Frees the SPIR-V. Safe on a zeroed struct. */
void rtpipe_shaders_free(rtpipe_shaders *s);

#endif
