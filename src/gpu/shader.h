/*
 * shader.h: GLSL to SPIR-V at run time, through glslang's C API.
 *
 * Sources come from a lookup function (the kernels embedded in the binary, or a user's files), so
 * this module knows nothing of where they live. `#include "file"` is resolved here, relative to
 * the including file, and each included text is framed with #line directives naming its file, so
 * a compile error reads "glsl/lib/intersect.glsl:42: ..." (the display name), not "0:1042".
 */
#ifndef VKRT_GPU_SHADER_H
#define VKRT_GPU_SHADER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "../error.h"

/* Returns a malloc'd, NUL-terminated copy of the source at path, or NULL if there is none.
 * path uses '/' separators and has no "." or ".." parts. */
typedef char *(*gpu_source_lookup_fn)(void *user, const char *path);

typedef struct gpu_shader_sources {
    gpu_source_lookup_fn lookup;
    void *user;
    const char *display_prefix; /* put before paths in messages, e.g. "glsl/"; may be NULL */
    const char *preamble;       /* lines put after the #version header (#extension and #define
                                   lines of what the device allows); may be NULL */
} gpu_shader_sources;

/* Compiles the compute shader at path (with its includes) to SPIR-V for Vulkan 1.1. The kernel
 * source has no #version line: one is added, with VKRT_GLSL defined, then sources->preamble. On
 * success *spirv is a malloc'd array of *word_count words; on failure err holds the first errors
 * with their file:line. */
bool gpu_shader_compile(const gpu_shader_sources *sources, const char *path, uint32_t **spirv,
                        size_t *word_count, vkrt_error *err);

/* Shader stages gpu_shader_compile_stage knows: compute, and those of a ray tracing pipeline. */
typedef enum gpu_shader_stage {
    GPU_SHADER_COMPUTE = 0,
    GPU_SHADER_RAYGEN,
    GPU_SHADER_MISS,
    GPU_SHADER_CLOSEST_HIT,
} gpu_shader_stage;

/* gpu_shader_compile for any of those stages. Compute compiles exactly as gpu_shader_compile
 * does (SPIR-V 1.3); the ray tracing stages target SPIR-V 1.4, which GL_EXT_ray_tracing needs
 * (the device then needs VK_KHR_spirv_1_4 or Vulkan 1.2). */
bool gpu_shader_compile_stage(const gpu_shader_sources *sources, const char *path,
                              gpu_shader_stage stage, uint32_t **spirv, size_t *word_count,
                              vkrt_error *err);

/* Expands the includes of the source at path into one text (what gpu_shader_compile feeds to
 * glslang, without the #version header); *text is malloc'd. Exposed for tests. */
bool gpu_shader_expand(const gpu_shader_sources *sources, const char *path, char **text,
                       vkrt_error *err);

#endif
