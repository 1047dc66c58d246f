/*
 * kernel_sources.h: the GLSL kernels built into the binary (generated from glsl/ at build time
 * by tools/embed_glsl.py), and the lookup the shader compiler uses to read them.
 */
#ifndef VKRT_KERNEL_SOURCES_H
#define VKRT_KERNEL_SOURCES_H

typedef struct vkrt_kernel_source {
    const char *path; /* relative to glsl/, e.g. "lib/rng.glsl" */
    const char *text;
} vkrt_kernel_source;

/* Terminated by an entry with path == NULL. */
extern const vkrt_kernel_source vkrt_kernel_sources[];

/* gpu_source_lookup_fn over the embedded kernels: a malloc'd copy of path's text, or NULL.
 * When the environment variable VKRT_TEST_GLSL_DIR is set, files are read from that folder instead,
 * so kernels can be edited without rebuilding. user is unused. */
char *vkrt_kernel_source_lookup(void *user, const char *path);

#endif
