/*
 * context.h: the Vulkan instance, the chosen physical device, its compute queue and a command
 * buffer for one-shot submissions; for the viewer also a window's surface, which the queue can
 * present to. Knows nothing of scenes.
 */
#ifndef VKRT_GPU_CONTEXT_H
#define VKRT_GPU_CONTEXT_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <vulkan/vulkan.h>

#include "../error.h"

typedef struct gpu_context_desc {
    int device_index;    /* index into vkEnumeratePhysicalDevices; -1 (or leave 0 and set
                            pick_default) picks the first discrete GPU, else the first device */
    bool pick_default;   /* true: ignore device_index and pick as above */
    bool validation;     /* enable VK_LAYER_KHRONOS_validation; every message is counted */
    bool quiet_validation; /* count validation messages without printing them */
    double timeout_seconds; /* how long one submission may run before the watchdog gives up on
                               it; 0: VKRT_TEST_GPU_TIMEOUT from the environment, else 300 s */
    /* For a window (vkrt view); left zero, the context is headless and needs no display. */
    const char *const *instance_extensions; /* more instance extensions (a window system's) */
    uint32_t instance_extension_count;
    /* Called once the instance exists, to create the surface the device must present to. The
     * context then picks a queue family that both computes and presents to it, enables
     * VK_KHR_swapchain, and destroys the surface before the instance. */
    bool (*create_surface)(void *user, VkInstance instance, VkSurfaceKHR *surface,
                           vkrt_error *err);
    void *surface_user;
    /* Device extensions wanted together (a ray tracing pipeline's, for a benchmark). When
     * the device has every one, they are enabled with device_features (a pNext chain of feature
     * structs, e.g. VkPhysicalDeviceBufferDeviceAddressFeatures) chained into the device's
     * creation; when it lacks one, none is, ctx->missing_extension names the first it lacks,
     * and the context is still created: the caller decides. Left zero: vkrt's usual device. */
    const char *const *device_extensions;
    uint32_t device_extension_count;
    void *device_features;
    /* Ask the driver for its compiled kernels' statistics (VK_KHR_pipeline_executable_properties:
     * registers and the like, gpu_pipeline_statistics) where it reports them. For vkrt bench. */
    bool pipeline_statistics;
} gpu_context_desc;

typedef struct gpu_context {
    VkInstance instance;
    VkDebugUtilsMessengerEXT messenger;
    VkPhysicalDevice physical;
    VkPhysicalDeviceProperties properties;
    VkPhysicalDeviceMemoryProperties memory;
    VkDevice device;
    VkSurfaceKHR surface;        /* desc.create_surface's, or VK_NULL_HANDLE when headless */
    uint32_t queue_family;       /* computes (and presents to surface, when there is one) */
    VkQueue queue;
    VkCommandPool command_pool;
    VkCommandBuffer command_buffer; /* for gpu_commands_begin / gpu_commands_submit */
    VkFence fence;
    bool robust_buffer_access;
    bool float_atomics;          /* VK_EXT_shader_atomic_float's shaderBufferFloat32AtomicAdd is on */
    const char *missing_extension; /* the first of desc.device_extensions the device lacks (then
                                      none of them is enabled), or NULL */
    bool pipeline_statistics;    /* desc.pipeline_statistics asked and the device has them */
    bool subgroup_arithmetic;    /* compute shaders have subgroup basic, ballot, vote and arithmetic
                                    operations (Vulkan 1.1); VKRT_TEST_NO_SUBGROUPS=1 turns them off */
    uint64_t timeout_ns;         /* the watchdog's limit per submission */
    bool lost;                   /* a submission timed out or the device was lost: the device is
                                    not waited for again, only left to the process's exit */
    /* Device memory: a buffer that would take more than one allocation may hold or
     * more than the device-local heap has left is refused with the sizes (buffer.c), not left to
     * the driver's VK_ERROR_OUT_OF_DEVICE_MEMORY. */
    VkDeviceSize max_allocation;   /* maxMemoryAllocationSize (Vulkan 1.1), else no limit */
    VkDeviceSize memory_limit;     /* the device-local heap's size, or the test hook's limit
                                      (test_hooks.h; to test the message) where that is smaller */
    VkDeviceSize memory_used;      /* device-local memory allocated by gpu_buffer_* now */
    /* The largest buffer vkrt makes: maxStorageBufferRange, or maxMemoryAllocationSize where
     * smaller. Arrays larger than split_bytes are split over several buffers (gpu/array.h):
     * max_buffer_bytes, or the test hook's (test_hooks.h; at least 128 bytes) where that is
     * smaller, so that tests split small scenes. */
    VkDeviceSize max_buffer_bytes;
    VkDeviceSize split_bytes;
    /* Buffer device addresses are on (VK_KHR_buffer_device_address): kernels can reach an array
     * split over several buffers. buffer_address is vkGetBufferDeviceAddressKHR. */
    bool device_addresses;
    PFN_vkGetBufferDeviceAddressKHR buffer_address;
    /* The host-visible buffer transfers of up to GPU_STAGING_BYTES pass through (buffer.c), kept
     * from one to the next: making one pins its pages, which takes time per megabyte, and a
     * scene's upload would make one per array. Made on first use, grown by powers of two; freed with
     * the context. */
    VkBuffer staging_buffer;
    VkDeviceMemory staging_memory;
    void *staging_mapped;
    VkDeviceSize staging_size;
    uint32_t validation_messages;   /* messages the validation layers reported so far */
    bool messenger_quiet;
    char first_validation_message[512];
} gpu_context;

/* Creates the context. On failure returns false with err set and nothing left allocated. */
bool gpu_context_create(gpu_context *ctx, const gpu_context_desc *desc, vkrt_error *err);

/* Waits for the device to go idle and destroys everything the context owns. Safe on a zeroed
 * context. */
void gpu_context_destroy(gpu_context *ctx);

/* Destroys the context like gpu_context_destroy, then returns false with a message if the
 * validation layers reported anything during its life (they are the last word on a run). */
bool gpu_context_finish(gpu_context *ctx, vkrt_error *err);

/* The end of a command's run: after a run that went well (ok), gpu_context_finish; after one that
 * failed (err already says why), gpu_context_destroy. Returns whether the run stays good. */
bool gpu_context_close(gpu_context *ctx, bool ok, vkrt_error *err);

/* Prints one line per Vulkan physical device: index, name, type, API version. */
bool gpu_list_devices(FILE *out, vkrt_error *err);

/* Resets and begins ctx->command_buffer for one-shot work; returns it through *cmd. */
bool gpu_commands_begin(gpu_context *ctx, VkCommandBuffer *cmd, vkrt_error *err);

/* Ends ctx->command_buffer, submits it and waits for it to finish. A lost device is reported as
 * such. */
bool gpu_commands_submit(gpu_context *ctx, vkrt_error *err);

/* Index of a memory type allowed by type_bits that has all of wanted, or UINT32_MAX. */
uint32_t gpu_memory_type(const gpu_context *ctx, uint32_t type_bits, VkMemoryPropertyFlags wanted);

#endif
