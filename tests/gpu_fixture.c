/* gpu_fixture.c: shared setup of the GPU tests (see gpu_fixture.h). */
#define _POSIX_C_SOURCE 200809L
#include "gpu_fixture.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "gpu/pipeline.h"
#include "gpu/shader.h"
#include "render/kernel_sources.h"
#include "scene/scene.h"

void fixture_context_create(gpu_context *ctx)
{
    vkrt_error err = {{0}};
    /* Validation is on unless VKRT_VALIDATION=0 says otherwise: for a GPU machine without the
     * layers installed, where these tests still check results. */
    const char *env = getenv("VKRT_VALIDATION");
    gpu_context_desc desc = {.device_index = -1, .validation = !env || strcmp(env, "0") != 0};
    if (!gpu_context_create(ctx, &desc, &err))
        fail_msg("gpu_context_create: %s", err.msg);
}

void fixture_context_destroy(gpu_context *ctx)
{
    gpu_context_destroy(ctx);
    if (ctx->validation_messages)
        fail_msg("%u validation message(s)", ctx->validation_messages);
}

typedef struct test_sources {
    const char *kernel;
} test_sources;

static char *lookup(void *user, const char *path)
{
    const test_sources *s = user;
    if (strcmp(path, "test.comp") == 0)
        return strdup(s->kernel);
    return vkrt_kernel_source_lookup(NULL, path);
}

void fixture_run_kernel(gpu_context *ctx, const char *kernel_source, gpu_buffer *buffers,
                        uint32_t count, const void *push, uint32_t push_size, uint32_t items)
{
    vkrt_error err = {{0}};
    test_sources user = {kernel_source};
    gpu_shader_sources sources = {.lookup = lookup, .user = &user, .display_prefix = "tests/"};
    uint32_t *spirv;
    size_t words;
    if (!gpu_shader_compile(&sources, "test.comp", &spirv, &words, &err))
        fail_msg("compile: %s", err.msg);
    gpu_storage_set set;
    gpu_pipeline pipe;
    if (!gpu_storage_set_create(ctx, &set, count, push_size, &err))
        fail_msg("set: %s", err.msg);
    if (!gpu_pipeline_create(ctx, &pipe, &set, spirv, words, 64, NULL, 0, "test", &err))
        fail_msg("pipeline: %s", err.msg);
    free(spirv);
    for (uint32_t i = 0; i < count; ++i)
        gpu_storage_set_bind(ctx, &set, i, &buffers[i]);
    VkCommandBuffer cmd;
    if (!gpu_commands_begin(ctx, &cmd, &err))
        fail_msg("%s", err.msg);
    gpu_dispatch(cmd, &pipe, &set, push, items);
    if (!gpu_commands_submit(ctx, &err))
        fail_msg("%s", err.msg);
    gpu_pipeline_destroy(ctx, &pipe);
    gpu_storage_set_destroy(ctx, &set);
}

void fixture_render(const vkrt_scene *scene, const vkrt_render_desc *desc, float *rgb,
                    vkrt_accel_stats *accel)
{
    gpu_context ctx;
    fixture_context_create(&ctx);
    vkrt_error err = {{0}};
    vkrt_renderer *r = NULL;
    if (!vkrt_renderer_create(&r, &ctx, scene, desc, &err))
        fail_msg("renderer: %s", err.msg);
    if (accel)
        *accel = *vkrt_renderer_accel_stats(r);
    if (!vkrt_renderer_render(r, &scene->cameras[0], 0, rgb, NULL, &err))
        fail_msg("render: %s", err.msg);
    vkrt_renderer_destroy(r);
    fixture_context_destroy(&ctx);
}
