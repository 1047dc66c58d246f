/*
 * gpu_fixture.h: what the GPU tests share: a validated Vulkan context and a way to run a small
 * test kernel (given as source text, able to include the real kernels' lib/ files) over storage
 * buffers.
 */
#ifndef VKRT_TEST_GPU_FIXTURE_H
#define VKRT_TEST_GPU_FIXTURE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "gpu/buffer.h"
#include "gpu/context.h"
#include "render/renderer.h"

/* Creates a context on the default device with validation layers on (fails the test if the layer
 * is missing). */
void fixture_context_create(gpu_context *ctx);

/* Fails the test if validation reported anything, then destroys the context. */
void fixture_context_destroy(gpu_context *ctx);

/* Compiles kernel_source (no #version line; `#include "lib/x.glsl"` reads the embedded kernels),
 * binds buffers[0..count-1] to bindings 0..count-1, pushes push_size bytes of push and dispatches
 * `items` invocations in workgroups of 64 (local_size_x_id = 0). Fails the test on any error. */
void fixture_run_kernel(gpu_context *ctx, const char *kernel_source, gpu_buffer *buffers,
                        uint32_t count, const void *push, uint32_t push_size, uint32_t items);

/* Renders the scene's first camera through the real renderer on a context of its own, with desc,
 * into rgb (desc's width * height * 3 floats); copies the structure's statistics into *accel
 * when accel is not NULL. Fails the test on any error. */
void fixture_render(const vkrt_scene *scene, const vkrt_render_desc *desc, float *rgb,
                    vkrt_accel_stats *accel);

#endif
