/*
 * swapchain.c: the window's swapchain (see swapchain.h).
 *
 * The display pass writes packed 8-bit pixels to a buffer and copies them into the swapchain
 * image, so a format is acceptable when its channels are four bytes in RGBA or BGRA order. The
 * pixels are already sRGB-encoded: a UNORM format shows them as they are (what X11 does with
 * every window), an SRGB format takes them as the encoded values they are, and a copy converts
 * nothing either way.
 */
#include "swapchain.h"

#include <stdlib.h>
#include <string.h>

#include "../gpu/vk_check.h"

/* Formats the display pass can write, best first. */
static const struct {
    VkFormat format;
    bool bgra;
} usable_formats[] = {
    {VK_FORMAT_B8G8R8A8_UNORM, true},         {VK_FORMAT_R8G8B8A8_UNORM, false},
    {VK_FORMAT_A8B8G8R8_UNORM_PACK32, false}, {VK_FORMAT_B8G8R8A8_SRGB, true},
    {VK_FORMAT_R8G8B8A8_SRGB, false},         {VK_FORMAT_A8B8G8R8_SRGB_PACK32, false},
};

static bool choose_format(gpu_context *ctx, view_swapchain *sc, vkrt_error *err)
{
    uint32_t count = 0;
    GPU_CHECK(vkGetPhysicalDeviceSurfaceFormatsKHR(ctx->physical, ctx->surface, &count, NULL));
    VkSurfaceFormatKHR *formats = calloc(count ? count : 1, sizeof *formats);
    if (!formats)
        return vkrt_error_set(err, "out of memory");
    VkResult listed =
        vkGetPhysicalDeviceSurfaceFormatsKHR(ctx->physical, ctx->surface, &count, formats);
    bool found = false;
    for (size_t f = 0;
         listed == VK_SUCCESS && !found && f < sizeof usable_formats / sizeof *usable_formats; ++f)
        for (uint32_t i = 0; i < count && !found; ++i)
            if (formats[i].format == usable_formats[f].format &&
                formats[i].colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR) {
                sc->format = usable_formats[f].format;
                sc->bgra = usable_formats[f].bgra;
                found = true;
            }
    free(formats);
    if (listed != VK_SUCCESS && listed != VK_INCOMPLETE)
        return vkrt_error_set(err, "vkGetPhysicalDeviceSurfaceFormatsKHR failed: %s",
                              gpu_result_name(listed));
    if (!found)
        return vkrt_error_set(err, "the window offers no 8-bit RGBA or BGRA sRGB format on %s",
                              ctx->properties.deviceName);
    return true;
fail:
    return false;
}

static uint32_t clamp_u32(uint32_t value, uint32_t lo, uint32_t hi)
{
    return value < lo ? lo : value > hi ? hi : value;
}

bool view_swapchain_create(view_swapchain *sc, gpu_context *ctx, uint32_t width, uint32_t height,
                           vkrt_error *err)
{
    view_swapchain old = *sc;
    *sc = (view_swapchain){0};
    VkSurfaceCapabilitiesKHR caps;
    GPU_CHECK(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(ctx->physical, ctx->surface, &caps));
    if (!(caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_DST_BIT)) {
        vkrt_error_set(err, "the window's images cannot be written by copies on %s",
                       ctx->properties.deviceName);
        goto fail;
    }
    if (!choose_format(ctx, sc, err))
        goto fail;
    /* A surface with a fixed extent (most) says so; UINT32_MAX means the swapchain decides. */
    if (caps.currentExtent.width != UINT32_MAX)
        sc->extent = caps.currentExtent;
    else
        sc->extent =
            (VkExtent2D){clamp_u32(width, caps.minImageExtent.width, caps.maxImageExtent.width),
                         clamp_u32(height, caps.minImageExtent.height, caps.maxImageExtent.height)};
    if (sc->extent.width == 0 || sc->extent.height == 0) {
        vkrt_error_set(err, "the window has no area (%ux%u)", sc->extent.width, sc->extent.height);
        goto fail;
    }
    /* One image more than the minimum, so that acquiring need not wait for the presentation
     * engine to let go of one. */
    uint32_t images = caps.minImageCount + 1;
    if (caps.maxImageCount && images > caps.maxImageCount)
        images = caps.maxImageCount;
    VkCompositeAlphaFlagBitsKHR alpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
    if (!(caps.supportedCompositeAlpha & alpha))
        alpha = (VkCompositeAlphaFlagBitsKHR)(caps.supportedCompositeAlpha &
                                              -caps.supportedCompositeAlpha);
    VkSwapchainCreateInfoKHR info = {
        .sType = VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR,
        .surface = ctx->surface,
        .minImageCount = images,
        .imageFormat = sc->format,
        .imageColorSpace = VK_COLOR_SPACE_SRGB_NONLINEAR_KHR,
        .imageExtent = sc->extent,
        .imageArrayLayers = 1,
        .imageUsage = VK_IMAGE_USAGE_TRANSFER_DST_BIT,
        .imageSharingMode = VK_SHARING_MODE_EXCLUSIVE,
        .preTransform = caps.currentTransform,
        .compositeAlpha = alpha,
        .presentMode = VK_PRESENT_MODE_FIFO_KHR,
        .clipped = VK_TRUE,
        .oldSwapchain = old.swapchain,
    };
    GPU_CHECK(vkCreateSwapchainKHR(ctx->device, &info, NULL, &sc->swapchain));
    view_swapchain_destroy(&old, ctx);
    GPU_CHECK(vkGetSwapchainImagesKHR(ctx->device, sc->swapchain, &sc->image_count, NULL));
    if (sc->image_count > VIEW_SWAPCHAIN_MAX_IMAGES) {
        vkrt_error_set(err, "the swapchain has %u images; vkrt handles at most %u", sc->image_count,
                       VIEW_SWAPCHAIN_MAX_IMAGES);
        goto fail;
    }
    GPU_CHECK(vkGetSwapchainImagesKHR(ctx->device, sc->swapchain, &sc->image_count, sc->images));
    VkSemaphoreCreateInfo semaphore_info = {.sType = VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    for (uint32_t i = 0; i < sc->image_count; ++i)
        GPU_CHECK(vkCreateSemaphore(ctx->device, &semaphore_info, NULL, &sc->rendered[i]));
    return true;
fail:
    view_swapchain_destroy(&old, ctx);
    view_swapchain_destroy(sc, ctx);
    return false;
}

void view_swapchain_destroy(view_swapchain *sc, gpu_context *ctx)
{
    for (uint32_t i = 0; i < VIEW_SWAPCHAIN_MAX_IMAGES; ++i)
        if (sc->rendered[i])
            vkDestroySemaphore(ctx->device, sc->rendered[i], NULL);
    if (sc->swapchain)
        vkDestroySwapchainKHR(ctx->device, sc->swapchain, NULL);
    *sc = (view_swapchain){0};
}
