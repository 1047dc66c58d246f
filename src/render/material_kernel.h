/*
 * material_kernel.h: the shading code generated for one scene.
 *
 * The light, count and shade kernels include "generated/materials.glsl", which exists only in
 * memory: it is written here from the shaders the scene's materials use (and no others), each shader's
 * text inlined under a #line naming its file, its count_rays / shade / environment renamed per
 * shader, and a switch over the shader index calling the right one. A compile error inside a
 * user's shader comes back as "<material file>:<line>: material 'name': <shader>:<line>: ...".
 */
#ifndef VKRT_MATERIAL_KERNEL_H
#define VKRT_MATERIAL_KERNEL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "../error.h"
#include "../scene/materials.h"

typedef struct vkrt_material_kernel {
    char *text;               /* generated/materials.glsl */
    bool path;                /* made for the path integrator (generated/light_stage.glsl) */
    bool *shader_uses_lights; /* per shader: reads light samples, so needs shadow rays */
    uint32_t shader_count;
} vkrt_material_kernel;

/* Writes the module for materials. float_atomics: the device adds floats atomically
 * (VK_EXT_shader_atomic_float), else shade.comp falls back to compare-and-swap. path: for the
 * path integrator: the switches over each shader's emitted, bsdf_eval and bsdf_sample, which a
 * shader then must define (for Whitted they return their defaults and call no shader; under path
 * Whitted's count_rays and shade switches do), and generated/light_stage.glsl with next-event
 * estimation (for Whitted a nee_at returning 0, never called). The integrator itself is the kernels' INTEGRATOR
 * specialization constant; the module only leaves out what that constant makes dead, so the
 * driver does not compile it. */
bool vkrt_material_kernel_create(vkrt_material_kernel *k, const vkrt_scene_materials *materials,
                                 bool float_atomics, bool path, vkrt_error *err);

/* vkrt_material_kernel_create; with whitted_samples, a Whitted module also switches over the
 * bsdf_sample of each shader that names one (a token search; the others return false): --aov
 * asks it whether a Whitted path goes on through a delta bounce (glsl/shade.comp). */
bool vkrt_material_kernel_create_sampling(vkrt_material_kernel *k,
                                          const vkrt_scene_materials *materials,
                                          bool float_atomics, bool path, bool whitted_samples,
                                          vkrt_error *err);

/* Compiles kernel (e.g. "shade.comp") against the module, with preamble (NULL or the device's
 * #extension and #define lines, gpu_shader_sources.preamble); on a compile error in a user's
 * shader err names the material file line that uses it. */
bool vkrt_material_kernel_compile(const vkrt_material_kernel *k,
                                  const vkrt_scene_materials *materials, const char *kernel,
                                  const char *preamble, uint32_t **spirv, size_t *words,
                                  vkrt_error *err);

void vkrt_material_kernel_destroy(vkrt_material_kernel *k);

#endif
