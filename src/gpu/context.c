/*
 * context.c: instance, device and queue setup (see context.h).
 *
 * vkrt renders with a compute queue alone: no window, no surface, so `vkrt render` runs where
 * there is no display. The viewer adds a surface (desc.create_surface); then the queue family must
 * also present to it and the device gets VK_KHR_swapchain. Validation messages are counted in the
 * context so that tests can fail on any of them.
 */
#include "context.h"

#include <stdlib.h>
#include <string.h>

#include "../test_hooks.h"
#include "vk_check.h"

static const char *const validation_layer = "VK_LAYER_KHRONOS_validation";

static VKAPI_ATTR VkBool32 VKAPI_CALL on_validation_message(
    VkDebugUtilsMessageSeverityFlagBitsEXT severity, VkDebugUtilsMessageTypeFlagsEXT types,
    const VkDebugUtilsMessengerCallbackDataEXT *data, void *user)
{
    (void)types;
    gpu_context *ctx = user;
    /* Info and verbose messages are chatter (loader and layer announcements), not findings. */
    if (severity < VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT)
        return VK_FALSE;
    if (ctx->validation_messages == 0)
        snprintf(ctx->first_validation_message, sizeof ctx->first_validation_message, "%s",
                 data->pMessage);
    ctx->validation_messages++;
    if (!ctx->messenger_quiet)
        fprintf(stderr, "vkrt: validation: %s\n", data->pMessage);
    return VK_FALSE;
}

static bool layer_available(const char *name)
{
    uint32_t count = 0;
    if (vkEnumerateInstanceLayerProperties(&count, NULL) != VK_SUCCESS)
        return false;
    VkLayerProperties *layers = calloc(count ? count : 1, sizeof *layers);
    if (!layers)
        return false;
    bool found = false;
    if (vkEnumerateInstanceLayerProperties(&count, layers) == VK_SUCCESS)
        for (uint32_t i = 0; i < count && !found; ++i)
            found = strcmp(layers[i].layerName, name) == 0;
    free(layers);
    return found;
}

static bool create_instance(gpu_context *ctx, bool validation, const gpu_context_desc *desc,
                            vkrt_error *err)
{
    if (validation && !layer_available(validation_layer))
        return vkrt_error_set(err, "validation was asked for but %s is not installed "
                                   "(Debian: apt-get install vulkan-validationlayers)",
                              validation_layer);
    VkApplicationInfo app = {
        .sType = VK_STRUCTURE_TYPE_APPLICATION_INFO,
        .pApplicationName = "vkrt",
        .pEngineName = "vkrt",
        .apiVersion = VK_API_VERSION_1_1,
    };
    /* Synchronization validation (hazards between dispatches, transfers and indirect reads) is
     * off by default in the layer, and slow; a test hook turns it on (test_hooks.h). */
    bool sync = validation && vkrt_test_hooks_get()->sync_validation;
    /* The validation extensions, then the window system's (for the viewer). */
    const uint32_t max_extensions = 16;
    const char *extensions[16] = {VK_EXT_DEBUG_UTILS_EXTENSION_NAME,
                                  VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME};
    uint32_t extension_count = validation ? (sync ? 2 : 1) : 0;
    uint32_t wanted = desc ? desc->instance_extension_count : 0;
    if (wanted > max_extensions - 2)
        return vkrt_error_set(err, "%u instance extensions asked for; at most %u are supported",
                              wanted, max_extensions - 2);
    for (uint32_t i = 0; i < wanted; ++i)
        extensions[extension_count++] = desc->instance_extensions[i];
    VkValidationFeatureEnableEXT sync_feature =
        VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT;
    VkValidationFeaturesEXT features = {
        .sType = VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT,
        .enabledValidationFeatureCount = 1,
        .pEnabledValidationFeatures = &sync_feature,
    };
    VkDebugUtilsMessengerCreateInfoEXT messenger_info = {
        .sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT,
        .messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                           VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT,
        .messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT,
        .pfnUserCallback = on_validation_message,
        .pUserData = ctx,
    };
    features.pNext = &messenger_info;
    VkInstanceCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO,
        /* Chained so that instance creation and destruction are validated too. */
        .pNext = sync ? (const void *)&features : validation ? (const void *)&messenger_info : NULL,
        .pApplicationInfo = &app,
        .enabledLayerCount = validation ? 1 : 0,
        .ppEnabledLayerNames = &validation_layer,
        .enabledExtensionCount = extension_count,
        .ppEnabledExtensionNames = extensions,
    };
    VkResult result = vkCreateInstance(&info, NULL, &ctx->instance);
    if (result == VK_ERROR_EXTENSION_NOT_PRESENT && wanted)
        return vkrt_error_set(err, "vkCreateInstance failed: %s (the Vulkan loader lacks the "
                                   "window system's surface extensions, such as %s)",
                              gpu_result_name(result), desc->instance_extensions[wanted - 1]);
    if (result == VK_ERROR_INCOMPATIBLE_DRIVER || result == VK_ERROR_INITIALIZATION_FAILED)
        return vkrt_error_set(err, "no Vulkan driver found (%s); install one, e.g. Debian's "
                                   "mesa-vulkan-drivers for a CPU device",
                              gpu_result_name(result));
    if (result != VK_SUCCESS)
        return vkrt_error_set(err, "vkCreateInstance failed: %s", gpu_result_name(result));
    if (validation) {
        PFN_vkCreateDebugUtilsMessengerEXT create_messenger =
            (PFN_vkCreateDebugUtilsMessengerEXT)vkGetInstanceProcAddr(
                ctx->instance, "vkCreateDebugUtilsMessengerEXT");
        if (!create_messenger)
            return vkrt_error_set(err, "validation: vkCreateDebugUtilsMessengerEXT is missing");
        result = create_messenger(ctx->instance, &messenger_info, NULL, &ctx->messenger);
        if (result != VK_SUCCESS)
            return vkrt_error_set(err, "vkCreateDebugUtilsMessengerEXT failed: %s",
                                  gpu_result_name(result));
    }
    return true;
}

static bool enumerate_devices(VkInstance instance, VkPhysicalDevice **devices, uint32_t *count,
                              vkrt_error *err)
{
    *devices = NULL;
    *count = 0;
    VkResult result = vkEnumeratePhysicalDevices(instance, count, NULL);
    if (result != VK_SUCCESS)
        return vkrt_error_set(err, "vkEnumeratePhysicalDevices failed: %s",
                              gpu_result_name(result));
    if (*count == 0)
        return vkrt_error_set(err, "no Vulkan device found");
    *devices = calloc(*count, sizeof **devices);
    if (!*devices)
        return vkrt_error_set(err, "out of memory");
    result = vkEnumeratePhysicalDevices(instance, count, *devices);
    if (result != VK_SUCCESS && result != VK_INCOMPLETE) {
        free(*devices);
        *devices = NULL;
        return vkrt_error_set(err, "vkEnumeratePhysicalDevices failed: %s",
                              gpu_result_name(result));
    }
    return true;
}

static bool pick_device(gpu_context *ctx, const gpu_context_desc *desc, vkrt_error *err)
{
    VkPhysicalDevice *devices;
    uint32_t count;
    if (!enumerate_devices(ctx->instance, &devices, &count, err))
        return false;
    uint32_t chosen = 0;
    if (desc->pick_default || desc->device_index < 0) {
        for (uint32_t i = 0; i < count; ++i) {
            VkPhysicalDeviceProperties props;
            vkGetPhysicalDeviceProperties(devices[i], &props);
            if (props.deviceType == VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU) {
                chosen = i;
                break;
            }
        }
    } else if ((uint32_t)desc->device_index >= count) {
        free(devices);
        return vkrt_error_set(err, "--device %d: there are only %u Vulkan devices (see --list-devices)",
                              desc->device_index, count);
    } else {
        chosen = (uint32_t)desc->device_index;
    }
    ctx->physical = devices[chosen];
    free(devices);
    vkGetPhysicalDeviceProperties(ctx->physical, &ctx->properties);
    vkGetPhysicalDeviceMemoryProperties(ctx->physical, &ctx->memory);
    return true;
}

/* A queue family that computes and, with a surface, presents to it. */
static bool find_compute_queue(gpu_context *ctx, vkrt_error *err)
{
    uint32_t count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(ctx->physical, &count, NULL);
    VkQueueFamilyProperties *families = calloc(count ? count : 1, sizeof *families);
    if (!families)
        return vkrt_error_set(err, "out of memory");
    vkGetPhysicalDeviceQueueFamilyProperties(ctx->physical, &count, families);
    ctx->queue_family = UINT32_MAX;
    for (uint32_t i = 0; i < count; ++i) {
        VkBool32 presents = VK_TRUE;
        if (ctx->surface &&
            vkGetPhysicalDeviceSurfaceSupportKHR(ctx->physical, i, ctx->surface, &presents) !=
                VK_SUCCESS)
            presents = VK_FALSE;
        if ((families[i].queueFlags & VK_QUEUE_COMPUTE_BIT) && presents) {
            ctx->queue_family = i;
            break;
        }
    }
    free(families);
    if (ctx->queue_family == UINT32_MAX && ctx->surface)
        return vkrt_error_set(err, "%s has no queue that both computes and presents to the "
                                   "window; choose another device with --device (see "
                                   "--list-devices)",
                              ctx->properties.deviceName);
    if (ctx->queue_family == UINT32_MAX)
        return vkrt_error_set(err, "%s has no compute queue", ctx->properties.deviceName);
    return true;
}

/* The watchdog's limit: the caller's, else the test hook's (test_hooks.h), else 300 s, long
 * enough for any frame vkrt renders on a CPU device and far past a desktop driver's own reset. */
static uint64_t watchdog_ns(double seconds)
{
    const double default_seconds = 300;
    if (!(seconds > 0))
        seconds = vkrt_test_hooks_get()->gpu_timeout_s;
    if (!(seconds > 0))
        seconds = default_seconds;
    return seconds > 1e9 ? UINT64_MAX : (uint64_t)(seconds * 1e9);
}

static bool has_extension(const VkExtensionProperties *extensions, uint32_t count,
                          const char *name)
{
    for (uint32_t i = 0; i < count; ++i)
        if (strcmp(extensions[i].extensionName, name) == 0)
            return true;
    return false;
}

/* ctx->max_allocation where Vulkan 1.1 does not say (no limit), and ctx->memory_limit: the largest
 * device-local heap, or the test hook's device memory limit where that is smaller (a test's
 * small device; test_hooks.h). */
static void set_memory_limit(gpu_context *ctx)
{
    if (ctx->max_allocation == 0)
        ctx->max_allocation = UINT64_MAX;
    for (uint32_t i = 0; i < ctx->memory.memoryHeapCount; i++)
        if (ctx->memory.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT &&
            ctx->memory.memoryHeaps[i].size > ctx->memory_limit)
            ctx->memory_limit = ctx->memory.memoryHeaps[i].size;
    if (ctx->memory_limit == 0) /* no heap says device-local: the first one holds everything */
        ctx->memory_limit = ctx->memory.memoryHeaps[0].size;
    const vkrt_test_hooks *hooks = vkrt_test_hooks_get();
    uint64_t bytes = hooks->device_memory_limit;
    if (bytes > 0 && bytes < ctx->memory_limit)
        ctx->memory_limit = bytes;
    /* One buffer holds what a storage binding reaches and one allocation holds; arrays past it
     * are split (gpu/array.h). A test hook lowers where arrays split, so that tests split small
     * scenes (at least 128 bytes: two elements of every array). */
    ctx->max_buffer_bytes = ctx->properties.limits.maxStorageBufferRange;
    if (ctx->max_allocation < ctx->max_buffer_bytes)
        ctx->max_buffer_bytes = ctx->max_allocation;
    ctx->split_bytes = ctx->max_buffer_bytes;
    bytes = hooks->max_buffer_bytes;
    if (bytes >= 128 && bytes < ctx->split_bytes)
        ctx->split_bytes = bytes;
}

/* Whether the pNext chain holds a struct of type sType. */
static const VkBaseInStructure *chain_find(const void *chain, VkStructureType type)
{
    for (const VkBaseInStructure *s = chain; s; s = s->pNext)
        if (s->sType == type)
            return s;
    return NULL;
}

static bool create_device(gpu_context *ctx, const gpu_context_desc *desc, vkrt_error *err)
{
    VkPhysicalDeviceFeatures supported;
    vkGetPhysicalDeviceFeatures(ctx->physical, &supported);
    /* Out-of-range reads in a kernel (a user's shader, later) then return zeros instead of
     * reading other memory. */
    ctx->robust_buffer_access = supported.robustBufferAccess == VK_TRUE;
    VkPhysicalDeviceFeatures enabled = {.robustBufferAccess = supported.robustBufferAccess};

    /* Float atomic adds (VK_EXT_shader_atomic_float) let many rays add to one pixel at once;
     * without them the shading kernel falls back to compare-and-swap loops. */
    uint32_t extension_count = 0;
    GPU_CHECK(vkEnumerateDeviceExtensionProperties(ctx->physical, NULL, &extension_count, NULL));
    VkExtensionProperties *extensions = calloc(extension_count ? extension_count : 1,
                                               sizeof *extensions);
    if (!extensions)
        return vkrt_error_set(err, "out of memory");
    VkResult listed =
        vkEnumerateDeviceExtensionProperties(ctx->physical, NULL, &extension_count, extensions);
    if (listed != VK_SUCCESS) {
        free(extensions);
        return vkrt_error_set(err, "vkEnumerateDeviceExtensionProperties failed (%d)", listed);
    }
    bool has_atomic_float =
        has_extension(extensions, extension_count, VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME);
    /* The caller's extensions come all together or not at all: a ray tracing pipeline is no use
     * with half of what it needs. */
    enum { max_wanted = 16 };
    uint32_t wanted = desc->device_extension_count;
    if (wanted > max_wanted) {
        free(extensions);
        return vkrt_error_set(err, "%u device extensions asked for; at most %d are supported",
                              wanted, max_wanted);
    }
    for (uint32_t i = 0; i < wanted && !ctx->missing_extension; ++i)
        if (!has_extension(extensions, extension_count, desc->device_extensions[i]))
            ctx->missing_extension = desc->device_extensions[i];
    bool enable_wanted = wanted > 0 && !ctx->missing_extension;
    bool has_executable_properties =
        has_extension(extensions, extension_count, VK_KHR_PIPELINE_EXECUTABLE_PROPERTIES_EXTENSION_NAME);
    bool has_device_address =
        has_extension(extensions, extension_count, VK_KHR_BUFFER_DEVICE_ADDRESS_EXTENSION_NAME);
    free(extensions);
    VkPhysicalDeviceShaderAtomicFloatFeaturesEXT atomic_float = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_FLOAT_FEATURES_EXT,
    };
    if (has_atomic_float) {
        VkPhysicalDeviceFeatures2 features2 = {
            .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2,
            .pNext = &atomic_float,
        };
        vkGetPhysicalDeviceFeatures2(ctx->physical, &features2);
    }
    ctx->float_atomics = has_atomic_float && atomic_float.shaderBufferFloat32AtomicAdd;
    /* For testing the fallback on a device that has them (test_hooks.h). */
    if (vkrt_test_hooks_get()->no_float_atomics)
        ctx->float_atomics = false;
    void *wanted_features = enable_wanted ? desc->device_features : NULL;
    VkPhysicalDevicePipelineExecutablePropertiesFeaturesKHR executable_info = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PIPELINE_EXECUTABLE_PROPERTIES_FEATURES_KHR,
    };
    if (desc->pipeline_statistics && has_executable_properties) {
        VkPhysicalDeviceFeatures2 features2 = {
            .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2,
            .pNext = &executable_info,
        };
        vkGetPhysicalDeviceFeatures2(ctx->physical, &features2);
        ctx->pipeline_statistics = executable_info.pipelineExecutableInfo;
    }
    if (ctx->pipeline_statistics) {
        executable_info.pNext = wanted_features;
        wanted_features = &executable_info;
    }
    /* Buffer device addresses let the kernels reach an array split over several buffers
     * (gpu/array.h): on wherever the device has them, unless the caller's features already
     * turn them on (a ray tracing pipeline's). A test hook leaves them off, to test the
     * message a split scene then gets (test_hooks.h). */
    VkPhysicalDeviceBufferDeviceAddressFeatures address_info = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_BUFFER_DEVICE_ADDRESS_FEATURES,
    };
    const VkPhysicalDeviceBufferDeviceAddressFeatures *asked =
        (const void *)chain_find(wanted_features,
                                 VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_BUFFER_DEVICE_ADDRESS_FEATURES);
    bool address_extension_asked = false;
    for (uint32_t i = 0; enable_wanted && i < wanted; ++i)
        address_extension_asked |=
            strcmp(desc->device_extensions[i], VK_KHR_BUFFER_DEVICE_ADDRESS_EXTENSION_NAME) == 0;
    bool addresses_off = vkrt_test_hooks_get()->no_device_addresses;
    bool add_address_extension = false;
    if (asked) {
        ctx->device_addresses = asked->bufferDeviceAddress && !addresses_off;
    } else if (has_device_address && !addresses_off) {
        VkPhysicalDeviceFeatures2 features2 = {
            .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2,
            .pNext = &address_info,
        };
        vkGetPhysicalDeviceFeatures2(ctx->physical, &features2);
        ctx->device_addresses = address_info.bufferDeviceAddress;
        if (ctx->device_addresses) {
            address_info = (VkPhysicalDeviceBufferDeviceAddressFeatures){
                .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_BUFFER_DEVICE_ADDRESS_FEATURES,
                .pNext = wanted_features,
                .bufferDeviceAddress = VK_TRUE,
            };
            wanted_features = &address_info;
            add_address_extension = !address_extension_asked;
        }
    }
    /* Subgroup sums let the wave kernels reserve ray slots with one atomic per subgroup instead
     * of one per ray (glsl/count.comp); Vulkan 1.1 devices report which operations they have. */
    if (ctx->properties.apiVersion >= VK_API_VERSION_1_1) {
        VkPhysicalDeviceMaintenance3Properties maintenance3 = {
            .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES,
        };
        VkPhysicalDeviceSubgroupProperties subgroup = {
            .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES,
            .pNext = &maintenance3,
        };
        VkPhysicalDeviceProperties2 properties2 = {
            .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2,
            .pNext = &subgroup,
        };
        vkGetPhysicalDeviceProperties2(ctx->physical, &properties2);
        const VkSubgroupFeatureFlags needed = VK_SUBGROUP_FEATURE_BASIC_BIT |
                                              VK_SUBGROUP_FEATURE_ARITHMETIC_BIT |
                                              VK_SUBGROUP_FEATURE_BALLOT_BIT |
                                              VK_SUBGROUP_FEATURE_VOTE_BIT;
        ctx->subgroup_arithmetic = (subgroup.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) &&
                                   (subgroup.supportedOperations & needed) == needed;
        ctx->max_allocation = maintenance3.maxMemoryAllocationSize;
    }
    set_memory_limit(ctx);
    /* For testing the fallback on a device that has them (test_hooks.h). */
    if (vkrt_test_hooks_get()->no_subgroups)
        ctx->subgroup_arithmetic = false;
    VkPhysicalDeviceShaderAtomicFloatFeaturesEXT atomic_float_on = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_FLOAT_FEATURES_EXT,
        .pNext = wanted_features,
        .shaderBufferFloat32AtomicAdd = VK_TRUE,
    };
    const char *device_extensions[4 + max_wanted];
    uint32_t device_extension_count = 0;
    if (add_address_extension)
        device_extensions[device_extension_count++] = VK_KHR_BUFFER_DEVICE_ADDRESS_EXTENSION_NAME;
    if (ctx->float_atomics)
        device_extensions[device_extension_count++] = VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME;
    if (ctx->surface)
        device_extensions[device_extension_count++] = VK_KHR_SWAPCHAIN_EXTENSION_NAME;
    if (ctx->pipeline_statistics)
        device_extensions[device_extension_count++] =
            VK_KHR_PIPELINE_EXECUTABLE_PROPERTIES_EXTENSION_NAME;
    for (uint32_t i = 0; enable_wanted && i < wanted; ++i)
        device_extensions[device_extension_count++] = desc->device_extensions[i];
    float priority = 1.0f;
    VkDeviceQueueCreateInfo queue_info = {
        .sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO,
        .queueFamilyIndex = ctx->queue_family,
        .queueCount = 1,
        .pQueuePriorities = &priority,
    };
    VkDeviceCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO,
        .queueCreateInfoCount = 1,
        .pQueueCreateInfos = &queue_info,
        .pEnabledFeatures = &enabled,
        .pNext = ctx->float_atomics ? &atomic_float_on : wanted_features,
        .enabledExtensionCount = device_extension_count,
        .ppEnabledExtensionNames = device_extensions,
    };
    GPU_CHECK(vkCreateDevice(ctx->physical, &info, NULL, &ctx->device));
    vkGetDeviceQueue(ctx->device, ctx->queue_family, 0, &ctx->queue);
    if (ctx->device_addresses) {
        ctx->buffer_address = (PFN_vkGetBufferDeviceAddressKHR)vkGetDeviceProcAddr(
            ctx->device, "vkGetBufferDeviceAddressKHR");
        ctx->device_addresses = ctx->buffer_address != NULL;
    }

    VkCommandPoolCreateInfo pool_info = {
        .sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
        .flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT,
        .queueFamilyIndex = ctx->queue_family,
    };
    GPU_CHECK(vkCreateCommandPool(ctx->device, &pool_info, NULL, &ctx->command_pool));
    VkCommandBufferAllocateInfo alloc = {
        .sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
        .commandPool = ctx->command_pool,
        .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
        .commandBufferCount = 1,
    };
    GPU_CHECK(vkAllocateCommandBuffers(ctx->device, &alloc, &ctx->command_buffer));
    VkFenceCreateInfo fence_info = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    GPU_CHECK(vkCreateFence(ctx->device, &fence_info, NULL, &ctx->fence));
    return true;
fail:
    return false;
}

bool gpu_context_create(gpu_context *ctx, const gpu_context_desc *desc, vkrt_error *err)
{
    memset(ctx, 0, sizeof *ctx);
    ctx->messenger_quiet = desc->quiet_validation;
    ctx->timeout_ns = watchdog_ns(desc->timeout_seconds);
    if (!create_instance(ctx, desc->validation, desc, err) ||
        (desc->create_surface &&
         !desc->create_surface(desc->surface_user, ctx->instance, &ctx->surface, err)) ||
        !pick_device(ctx, desc, err) || !find_compute_queue(ctx, err) ||
        !create_device(ctx, desc, err)) {
        gpu_context_destroy(ctx);
        return false;
    }
    return true;
}

void gpu_context_destroy(gpu_context *ctx)
{
    /* After a timeout or a device loss, waiting for the device could hang for ever, and freeing
     * what it may still use is undefined: the process's exit reclaims it all. */
    if (ctx->lost) {
        memset(ctx, 0, sizeof *ctx);
        return;
    }
    if (ctx->device) {
        vkDeviceWaitIdle(ctx->device);
        if (ctx->staging_buffer)
            vkDestroyBuffer(ctx->device, ctx->staging_buffer, NULL);
        if (ctx->staging_memory)
            vkFreeMemory(ctx->device, ctx->staging_memory, NULL);
        if (ctx->fence)
            vkDestroyFence(ctx->device, ctx->fence, NULL);
        if (ctx->command_pool)
            vkDestroyCommandPool(ctx->device, ctx->command_pool, NULL);
        vkDestroyDevice(ctx->device, NULL);
    }
    if (ctx->surface)
        vkDestroySurfaceKHR(ctx->instance, ctx->surface, NULL);
    if (ctx->messenger) {
        PFN_vkDestroyDebugUtilsMessengerEXT destroy_messenger =
            (PFN_vkDestroyDebugUtilsMessengerEXT)vkGetInstanceProcAddr(
                ctx->instance, "vkDestroyDebugUtilsMessengerEXT");
        if (destroy_messenger)
            destroy_messenger(ctx->instance, ctx->messenger, NULL);
    }
    if (ctx->instance)
        vkDestroyInstance(ctx->instance, NULL);
    /* What validation said outlives the context: it is the verdict on the whole run. */
    uint32_t messages = ctx->validation_messages;
    char first[sizeof ctx->first_validation_message];
    memcpy(first, ctx->first_validation_message, sizeof first);
    memset(ctx, 0, sizeof *ctx);
    ctx->validation_messages = messages;
    memcpy(ctx->first_validation_message, first, sizeof first);
}

bool gpu_context_finish(gpu_context *ctx, vkrt_error *err)
{
    gpu_context_destroy(ctx);
    if (ctx->validation_messages)
        return vkrt_error_set(err, "Vulkan validation reported %u message(s); the first: %s",
                              ctx->validation_messages, ctx->first_validation_message);
    return true;
}

bool gpu_context_close(gpu_context *ctx, bool ok, vkrt_error *err)
{
    if (ok)
        return gpu_context_finish(ctx, err);
    gpu_context_destroy(ctx);
    return false;
}

static const char *device_type_name(VkPhysicalDeviceType type)
{
    switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "CPU";
    default: return "other";
    }
}

bool gpu_list_devices(FILE *out, vkrt_error *err)
{
    gpu_context ctx = {0};
    if (!create_instance(&ctx, false, NULL, err))
        return false;
    VkPhysicalDevice *devices;
    uint32_t count;
    if (!enumerate_devices(ctx.instance, &devices, &count, err)) {
        vkDestroyInstance(ctx.instance, NULL);
        return false;
    }
    for (uint32_t i = 0; i < count; ++i) {
        VkPhysicalDeviceProperties props;
        vkGetPhysicalDeviceProperties(devices[i], &props);
        fprintf(out, "%u: %s (%s, Vulkan %u.%u.%u)\n", i, props.deviceName,
                device_type_name(props.deviceType), VK_API_VERSION_MAJOR(props.apiVersion),
                VK_API_VERSION_MINOR(props.apiVersion), VK_API_VERSION_PATCH(props.apiVersion));
    }
    free(devices);
    vkDestroyInstance(ctx.instance, NULL);
    return true;
}

bool gpu_commands_begin(gpu_context *ctx, VkCommandBuffer *cmd, vkrt_error *err)
{
    GPU_CHECK(vkResetCommandBuffer(ctx->command_buffer, 0));
    VkCommandBufferBeginInfo begin = {
        .sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
        .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT,
    };
    GPU_CHECK(vkBeginCommandBuffer(ctx->command_buffer, &begin));
    *cmd = ctx->command_buffer;
    return true;
fail:
    return false;
}

bool gpu_commands_submit(gpu_context *ctx, vkrt_error *err)
{
    GPU_CHECK(vkEndCommandBuffer(ctx->command_buffer));
    GPU_CHECK(vkResetFences(ctx->device, 1, &ctx->fence));
    VkSubmitInfo submit = {
        .sType = VK_STRUCTURE_TYPE_SUBMIT_INFO,
        .commandBufferCount = 1,
        .pCommandBuffers = &ctx->command_buffer,
    };
    GPU_CHECK(vkQueueSubmit(ctx->queue, 1, &submit, ctx->fence));
    VkResult waited = vkWaitForFences(ctx->device, 1, &ctx->fence, VK_TRUE, ctx->timeout_ns);
    if (waited == VK_TIMEOUT) {
        /* A kernel that never ends (a user's shader looping forever) would hang the program;
         * Vulkan cannot cancel a submission, so the device is given up. */
        ctx->lost = true;
        return vkrt_error_set(err,
                              "the GPU did not finish within %.3g s (the watchdog's limit; set "
                              "VKRT_TEST_GPU_TIMEOUT=SECONDS to change it): a kernel seems to run "
                              "forever",
                              ctx->timeout_ns * 1e-9);
    }
    if (waited == VK_ERROR_DEVICE_LOST) {
        ctx->lost = true;
        return vkrt_error_set(err, "the GPU was lost (VK_ERROR_DEVICE_LOST) while running the "
                                   "work: the driver reset it, often because a kernel ran too "
                                   "long (a shader looping forever) or read out of bounds");
    }
    GPU_CHECK(waited);
    return true;
fail:
    return false;
}

uint32_t gpu_memory_type(const gpu_context *ctx, uint32_t type_bits, VkMemoryPropertyFlags wanted)
{
    for (uint32_t i = 0; i < ctx->memory.memoryTypeCount; ++i)
        if ((type_bits & (1u << i)) && (ctx->memory.memoryTypes[i].propertyFlags & wanted) == wanted)
            return i;
    return UINT32_MAX;
}

const char *gpu_result_name(VkResult result)
{
    switch (result) {
#define NAME(r) case r: return #r;
    NAME(VK_SUCCESS)
    NAME(VK_NOT_READY)
    NAME(VK_TIMEOUT)
    NAME(VK_EVENT_SET)
    NAME(VK_EVENT_RESET)
    NAME(VK_INCOMPLETE)
    NAME(VK_ERROR_OUT_OF_HOST_MEMORY)
    NAME(VK_ERROR_OUT_OF_DEVICE_MEMORY)
    NAME(VK_ERROR_INITIALIZATION_FAILED)
    NAME(VK_ERROR_DEVICE_LOST)
    NAME(VK_ERROR_MEMORY_MAP_FAILED)
    NAME(VK_ERROR_LAYER_NOT_PRESENT)
    NAME(VK_ERROR_EXTENSION_NOT_PRESENT)
    NAME(VK_ERROR_FEATURE_NOT_PRESENT)
    NAME(VK_ERROR_INCOMPATIBLE_DRIVER)
    NAME(VK_ERROR_TOO_MANY_OBJECTS)
    NAME(VK_ERROR_FORMAT_NOT_SUPPORTED)
    NAME(VK_ERROR_FRAGMENTED_POOL)
    NAME(VK_ERROR_UNKNOWN)
    NAME(VK_ERROR_OUT_OF_POOL_MEMORY)
    NAME(VK_ERROR_INVALID_EXTERNAL_HANDLE)
    NAME(VK_ERROR_FRAGMENTATION)
    NAME(VK_ERROR_INVALID_OPAQUE_CAPTURE_ADDRESS)
    NAME(VK_ERROR_SURFACE_LOST_KHR)
    NAME(VK_ERROR_NATIVE_WINDOW_IN_USE_KHR)
    NAME(VK_SUBOPTIMAL_KHR)
    NAME(VK_ERROR_OUT_OF_DATE_KHR)
    NAME(VK_ERROR_VALIDATION_FAILED_EXT)
#undef NAME
    default: return "unknown VkResult";
    }
}
