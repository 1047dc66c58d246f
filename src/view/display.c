/*
 * display.c: the renderer's image into the window (see display.h).
 *
 * Synchronisation of one shown frame, all on the context's one queue:
 *   the renderer's passes end with a barrier that makes their image writes visible to later
 *   shader reads (gpu_dispatch), so the display pass may read the image;
 *   display pass -> (barrier) -> copy into the swapchain image, which waits on the acquire
 *   semaphore at the transfer stage, where its layout transition also waits;
 *   a last barrier keeps the renderer's next submission (which clears and adds to the image)
 *   from starting before the display pass has read it;
 *   the submission signals the image's `rendered` semaphore for presentation and the slot's fence,
 *   which the host waits on before it reuses the slot's command buffer and pixels.
 */
#include "display.h"

#include <stdlib.h>
#include <string.h>

#include "../../glsl/shared.h"
#include "../gpu/shader.h"
#include "../gpu/vk_check.h"
#include "../render/kernel_sources.h"

static const uint32_t display_workgroup_size = 64;

static bool create_pipeline(view_display *d, vkrt_error *err)
{
    gpu_shader_sources sources = {.lookup = vkrt_kernel_source_lookup, .display_prefix = "glsl/"};
    uint32_t *spirv;
    size_t words;
    if (!gpu_shader_compile(&sources, "display.comp", &spirv, &words, err))
        return false;
    /* Every frame's set has the same layout; the pipeline is made with the first's. */
    bool ok = gpu_pipeline_create(d->ctx, &d->pipeline, &d->frames[0].set, spirv, words,
                                  display_workgroup_size, NULL, 0, "display.comp", err);
    free(spirv);
    return ok;
}

static bool create_pixel_buffers(view_display *d, vkrt_error *err)
{
    VkExtent2D e = d->swapchain.extent;
    for (uint32_t i = 0; i < VIEW_FRAMES_IN_FLIGHT; ++i) {
        gpu_buffer_destroy(d->ctx, &d->frames[i].pixels);
        if (!gpu_buffer_create(d->ctx, &d->frames[i].pixels, (size_t)e.width * e.height * 4,
                               "window pixels", err))
            return false;
    }
    return true;
}

bool view_display_create(view_display *d, gpu_context *ctx, uint32_t width, uint32_t height,
                         vkrt_error *err)
{
    *d = (view_display){.ctx = ctx, .last = -1};
    VkCommandPoolCreateInfo pool_info = {
        .sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
        .flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT,
        .queueFamilyIndex = ctx->queue_family,
    };
    GPU_CHECK(vkCreateCommandPool(ctx->device, &pool_info, NULL, &d->pool));
    for (uint32_t i = 0; i < VIEW_FRAMES_IN_FLIGHT; ++i) {
        view_frame *f = &d->frames[i];
        VkCommandBufferAllocateInfo alloc = {
            .sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
            .commandPool = d->pool,
            .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
            .commandBufferCount = 1,
        };
        GPU_CHECK(vkAllocateCommandBuffers(ctx->device, &alloc, &f->cmd));
        /* Signalled, so that the first wait for the slot returns at once. */
        VkFenceCreateInfo fence_info = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO,
                                        .flags = VK_FENCE_CREATE_SIGNALED_BIT};
        GPU_CHECK(vkCreateFence(ctx->device, &fence_info, NULL, &f->done));
        VkSemaphoreCreateInfo semaphore_info = {.sType = VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
        GPU_CHECK(vkCreateSemaphore(ctx->device, &semaphore_info, NULL, &f->acquired));
        if (!gpu_storage_set_create(ctx, &f->set, 2, sizeof(DisplayParams), err))
            goto fail;
    }
    if (!create_pipeline(d, err) ||
        !view_swapchain_create(&d->swapchain, ctx, width, height, err) ||
        !create_pixel_buffers(d, err))
        goto fail;
    return true;
fail:
    view_display_destroy(d);
    return false;
}

/* Waits for a slot's last submission, with the context's watchdog. */
static bool wait_frame(view_display *d, view_frame *f, vkrt_error *err)
{
    VkResult waited = vkWaitForFences(d->ctx->device, 1, &f->done, VK_TRUE, d->ctx->timeout_ns);
    if (waited == VK_TIMEOUT || waited == VK_ERROR_DEVICE_LOST) {
        d->ctx->lost = true;
        return vkrt_error_set(err, "showing a frame: the GPU %s",
                              waited == VK_TIMEOUT ? "did not finish in time" : "was lost");
    }
    GPU_CHECK(waited);
    return true;
fail:
    return false;
}

static bool wait_all(view_display *d, vkrt_error *err)
{
    for (uint32_t i = 0; i < VIEW_FRAMES_IN_FLIGHT; ++i)
        if (d->frames[i].done && !wait_frame(d, &d->frames[i], err))
            return false;
    return true;
}

bool view_display_resize(view_display *d, uint32_t width, uint32_t height, vkrt_error *err)
{
    /* Presentation may still hold the old images' semaphores: the whole queue goes idle. */
    if (!wait_all(d, err))
        return false;
    GPU_CHECK(vkQueueWaitIdle(d->ctx->queue));
    d->last = -1;
    return view_swapchain_create(&d->swapchain, d->ctx, width, height, err) &&
           create_pixel_buffers(d, err);
fail:
    return false;
}

/* Moves a swapchain image's colour from layout `from` to `to` with the given access and stages. */
static void image_layout_barrier(VkCommandBuffer cmd, VkImage image, VkImageLayout from,
                                 VkImageLayout to, VkAccessFlags src_access, VkAccessFlags dst_access,
                                 VkPipelineStageFlags src_stage, VkPipelineStageFlags dst_stage)
{
    VkImageMemoryBarrier barrier = {.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER,
                                    .srcAccessMask = src_access, .dstAccessMask = dst_access,
                                    .oldLayout = from, .newLayout = to,
                                    .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                                    .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED, .image = image,
                                    .subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1}};
    vkCmdPipelineBarrier(cmd, src_stage, dst_stage, 0, 0, NULL, 0, NULL, 1, &barrier);
}

static void record(view_display *d, view_frame *f, uint32_t image_index, const DisplayParams *push)
{
    VkCommandBuffer cmd = f->cmd;
    VkImage image = d->swapchain.images[image_index];
    VkExtent2D e = d->swapchain.extent;
    gpu_dispatch(cmd, &d->pipeline, &f->set, push, e.width * e.height);
    /* Source stage transfer: the stage the acquire semaphore's wait names, so the transition
     * comes after the presentation engine let go of the image. */
    image_layout_barrier(cmd, image, VK_IMAGE_LAYOUT_UNDEFINED,
                         VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 0, VK_ACCESS_TRANSFER_WRITE_BIT,
                         VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT);
    VkBufferImageCopy region = {
        .imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
        .imageExtent = {e.width, e.height, 1},
    };
    vkCmdCopyBufferToImage(cmd, f->pixels.buffer, image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1,
                           &region);
    /* Presentation waits on the semaphore, which makes the copy's writes visible to it. */
    image_layout_barrier(cmd, image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                         VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, VK_ACCESS_TRANSFER_WRITE_BIT, 0,
                         VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT);
    /* The renderer's next submission writes the image this pass read (write after read: an
     * execution dependency is enough), and the next frame in this slot rewrites the pixels the
     * copy read (covered by the fence, which the host waits on first). */
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                         VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0,
                         0, NULL, 0, NULL, 0, NULL);
}

bool view_display_present(view_display *d, const gpu_buffer *image, uint32_t image_width,
                          uint32_t image_height, uint32_t passes,
                          const vkrt_finish_desc *finish, bool *out_of_date, vkrt_error *err)
{
    *out_of_date = false;
    view_frame *f = &d->frames[d->next];
    if (!wait_frame(d, f, err))
        return false;
    uint32_t index;
    VkResult acquired = vkAcquireNextImageKHR(d->ctx->device, d->swapchain.swapchain, UINT64_MAX,
                                              f->acquired, VK_NULL_HANDLE, &index);
    if (acquired == VK_ERROR_OUT_OF_DATE_KHR) {
        *out_of_date = true;
        return true;
    }
    if (acquired != VK_SUBOPTIMAL_KHR)
        GPU_CHECK(acquired);

    VkExtent2D e = d->swapchain.extent;
    vkrt_finish_display shown = vkrt_finish_display_params(finish);
    DisplayParams push = {
        .size = {image_width, image_height, e.width, e.height},
        .scale = {1.0f / (float)(passes ? passes : 1), shown.scale, d->swapchain.bgra ? 1 : 0,
                  passes ? 0 : 1},
        .curve = {shown.tonemap, 0, 0, 0},
    };
    gpu_storage_set_bind(d->ctx, &f->set, VKRT_DISPLAY_BINDING_IMAGE, image);
    gpu_storage_set_bind(d->ctx, &f->set, VKRT_DISPLAY_BINDING_WINDOW, &f->pixels);
    GPU_CHECK(vkResetCommandBuffer(f->cmd, 0));
    VkCommandBufferBeginInfo begin = {
        .sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
        .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT,
    };
    GPU_CHECK(vkBeginCommandBuffer(f->cmd, &begin));
    record(d, f, index, &push);
    GPU_CHECK(vkEndCommandBuffer(f->cmd));

    VkPipelineStageFlags wait_stage = VK_PIPELINE_STAGE_TRANSFER_BIT;
    VkSubmitInfo submit = {
        .sType = VK_STRUCTURE_TYPE_SUBMIT_INFO,
        .waitSemaphoreCount = 1,
        .pWaitSemaphores = &f->acquired,
        .pWaitDstStageMask = &wait_stage,
        .commandBufferCount = 1,
        .pCommandBuffers = &f->cmd,
        .signalSemaphoreCount = 1,
        .pSignalSemaphores = &d->swapchain.rendered[index],
    };
    GPU_CHECK(vkResetFences(d->ctx->device, 1, &f->done));
    GPU_CHECK(vkQueueSubmit(d->ctx->queue, 1, &submit, f->done));
    d->last = (int32_t)d->next;
    d->next = (d->next + 1) % VIEW_FRAMES_IN_FLIGHT;

    VkPresentInfoKHR present = {
        .sType = VK_STRUCTURE_TYPE_PRESENT_INFO_KHR,
        .waitSemaphoreCount = 1,
        .pWaitSemaphores = &d->swapchain.rendered[index],
        .swapchainCount = 1,
        .pSwapchains = &d->swapchain.swapchain,
        .pImageIndices = &index,
    };
    VkResult presented = vkQueuePresentKHR(d->ctx->queue, &present);
    if (presented == VK_ERROR_OUT_OF_DATE_KHR || presented == VK_SUBOPTIMAL_KHR ||
        acquired == VK_SUBOPTIMAL_KHR)
        *out_of_date = true;
    else
        GPU_CHECK(presented);
    return true;
fail:
    return false;
}

bool view_display_read(view_display *d, uint8_t *rgb, vkrt_error *err)
{
    if (d->last < 0)
        return vkrt_error_set(err, "no frame has been shown yet");
    view_frame *f = &d->frames[d->last];
    if (!wait_frame(d, f, err))
        return false;
    VkExtent2D e = d->swapchain.extent;
    size_t pixels = (size_t)e.width * e.height;
    uint32_t *packed = malloc(pixels * sizeof *packed);
    if (!packed)
        return vkrt_error_set(err, "out of memory reading %zu window pixels", pixels);
    bool ok = gpu_buffer_download(d->ctx, &f->pixels, packed, pixels * sizeof *packed, err);
    int red = d->swapchain.bgra ? 16 : 0, blue = d->swapchain.bgra ? 0 : 16;
    for (size_t i = 0; ok && i < pixels; ++i) {
        rgb[3 * i + 0] = (uint8_t)(packed[i] >> red);
        rgb[3 * i + 1] = (uint8_t)(packed[i] >> 8);
        rgb[3 * i + 2] = (uint8_t)(packed[i] >> blue);
    }
    free(packed);
    return ok;
}

void view_display_destroy(view_display *d)
{
    gpu_context *ctx = d->ctx;
    /* After a timeout or a lost device nothing is waited for or freed (see gpu_context.lost). */
    if (!ctx || !ctx->device || ctx->lost) {
        *d = (view_display){.last = -1};
        return;
    }
    vkQueueWaitIdle(ctx->queue);
    view_swapchain_destroy(&d->swapchain, ctx);
    gpu_pipeline_destroy(ctx, &d->pipeline);
    for (uint32_t i = 0; i < VIEW_FRAMES_IN_FLIGHT; ++i) {
        view_frame *f = &d->frames[i];
        gpu_buffer_destroy(ctx, &f->pixels);
        gpu_storage_set_destroy(ctx, &f->set);
        if (f->acquired)
            vkDestroySemaphore(ctx->device, f->acquired, NULL);
        if (f->done)
            vkDestroyFence(ctx->device, f->done, NULL);
    }
    if (d->pool)
        vkDestroyCommandPool(ctx->device, d->pool, NULL);
    *d = (view_display){.last = -1};
}
