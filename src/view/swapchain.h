/*
 * swapchain.h: the window's swapchain: its images, in a format of 8-bit channels whose pixels the
 * display pass writes, and one semaphore per image for presentation. Vulkan only, no GLFW.
 */
#ifndef VKRT_VIEW_SWAPCHAIN_H
#define VKRT_VIEW_SWAPCHAIN_H

#include <stdbool.h>
#include <stdint.h>
#include <vulkan/vulkan.h>

#include "../error.h"
#include "../gpu/context.h"

#define VIEW_SWAPCHAIN_MAX_IMAGES 8

typedef struct view_swapchain {
    VkSwapchainKHR swapchain;
    VkFormat format;
    bool bgra;                   /* the format stores blue in the first byte, red in the third */
    VkExtent2D extent;
    uint32_t image_count;
    VkImage images[VIEW_SWAPCHAIN_MAX_IMAGES];
    /* Per image: signalled when the frame copied into it is done; presentation waits on it. Per
     * image rather than per frame in flight, because presentation holds it until the image comes
     * back, which may be after the frame's fence. */
    VkSemaphore rendered[VIEW_SWAPCHAIN_MAX_IMAGES];
} view_swapchain;

/* Creates the swapchain for ctx->surface at width x height (the window's framebuffer; the
 * surface's own extent wins where it has one), with FIFO presentation (every device has it) and
 * images that copies can write. When sc already holds a swapchain, that one is handed over as the
 * old one and destroyed; the caller must have waited for the frames that used it. Both sizes must
 * be above 0 (a minimised window waits instead). On failure returns false with err set and *sc
 * empty. */
bool view_swapchain_create(view_swapchain *sc, gpu_context *ctx, uint32_t width, uint32_t height,
                           vkrt_error *err);

/* Destroys the swapchain and its semaphores, and zeroes *sc. The caller must have waited for the
 * device. Safe on a zeroed one. */
void view_swapchain_destroy(view_swapchain *sc, gpu_context *ctx);

#endif
