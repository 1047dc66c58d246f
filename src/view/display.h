/*
 * display.h: shows the renderer's image in the window. Per shown frame: a compute pass
 * (glsl/display.comp) turns the image, a sum of sample passes, into the window's 8-bit sRGB
 * pixels in a buffer; a copy puts them into the acquired swapchain image; the image is presented.
 * At most VIEW_FRAMES_IN_FLIGHT frames are on their way at once, each with its own command
 * buffer, fence, semaphore and pixel buffer. Vulkan only, no GLFW.
 */
#ifndef VKRT_VIEW_DISPLAY_H
#define VKRT_VIEW_DISPLAY_H

#include <stdbool.h>
#include <stdint.h>
#include <vulkan/vulkan.h>

#include "../error.h"
#include "../gpu/buffer.h"
#include "../gpu/context.h"
#include "../gpu/pipeline.h"
#include "../output/finish.h"
#include "swapchain.h"

#define VIEW_FRAMES_IN_FLIGHT 2

typedef struct view_frame {
    VkCommandBuffer cmd;
    VkFence done;                /* signalled: the frame's commands finished */
    VkSemaphore acquired;        /* the swapchain image may be written */
    gpu_buffer pixels;           /* the window's pixels, packed in the swapchain's byte order */
    gpu_storage_set set;         /* binding 0: the renderer's image, 1: pixels */
} view_frame;

typedef struct view_display {
    gpu_context *ctx;
    view_swapchain swapchain;
    VkCommandPool pool;
    gpu_pipeline pipeline;
    view_frame frames[VIEW_FRAMES_IN_FLIGHT];
    uint32_t next;               /* the frame slot the next present uses */
    int32_t last;                /* the slot of the last frame presented, -1 before the first */
} view_display;

/* Compiles the display pass and creates the swapchain at width x height (the window's
 * framebuffer, above 0) and the frames. ctx must have a surface. On failure returns false with
 * err set and nothing left. */
bool view_display_create(view_display *d, gpu_context *ctx, uint32_t width, uint32_t height,
                         vkrt_error *err);

/* Waits for the frames in flight, then recreates the swapchain at width x height (both above 0)
 * and the pixel buffers to match. */
bool view_display_resize(view_display *d, uint32_t width, uint32_t height, vkrt_error *err);

/* Shows image (image_width x image_height vec4 sums of `passes` passes, or with passes 0 of the
 * count in each pixel's w: sampling to a target error; scaled to the window when the sizes
 * differ), finished for the window as finish says (output/finish.h: vkrt_finish_display_params,
 * applied by glsl/display.comp). Waits for this slot's previous frame, not for this one.
 * Sets *out_of_date when the swapchain no longer matches the window (nothing was shown, or it
 * was shown but should be recreated): the caller resizes and shows again. */
bool view_display_present(view_display *d, const gpu_buffer *image, uint32_t image_width,
                          uint32_t image_height, uint32_t passes,
                          const vkrt_finish_desc *finish, bool *out_of_date, vkrt_error *err);

/* Waits for the last frame presented and reads its pixels as 8-bit sRGB RGB, top row first, into
 * rgb (swapchain.extent.width * height * 3 bytes): what the window shows. False with err set when
 * nothing was presented yet. */
bool view_display_read(view_display *d, uint8_t *rgb, vkrt_error *err);

/* Waits for the device and destroys everything. Safe on a zeroed one. */
void view_display_destroy(view_display *d);

#endif
