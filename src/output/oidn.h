/*
 * oidn.h: the part of Intel Open Image Denoise 2's C API that vkrt calls, declared here because
 * the library is loaded at run time (denoise.h) and no Debian package ships its header. Names,
 * enum values and signatures are those of OIDN 2's include/OpenImageDenoise/oidn.h (API 2.x,
 * checked against 2.5's exported symbols); only what denoise.c uses is here.
 *
 * The functions are not declared as functions but as members of oidn_api, a table of pointers
 * that denoise.c fills with dlsym: a missing library is then a message at run time, never a link
 * error, and a build needs no OIDN at all.
 */
#ifndef VKRT_OIDN_H
#define VKRT_OIDN_H

#include <stdbool.h>
#include <stddef.h>

typedef struct OIDNDeviceImpl *OIDNDevice;
typedef struct OIDNBufferImpl *OIDNBuffer;
typedef struct OIDNFilterImpl *OIDNFilter;

typedef enum {
    OIDN_DEVICE_TYPE_DEFAULT = 0, /* the library picks: a supported GPU, else the CPU */
    OIDN_DEVICE_TYPE_CPU = 1,
    OIDN_DEVICE_TYPE_SYCL = 2,
    OIDN_DEVICE_TYPE_CUDA = 3,
    OIDN_DEVICE_TYPE_HIP = 4,
    OIDN_DEVICE_TYPE_METAL = 5,
} OIDNDeviceType;

typedef enum {
    OIDN_ERROR_NONE = 0,
    OIDN_ERROR_UNKNOWN = 1,
    OIDN_ERROR_INVALID_ARGUMENT = 2,
    OIDN_ERROR_INVALID_OPERATION = 3,
    OIDN_ERROR_OUT_OF_MEMORY = 4,
    OIDN_ERROR_UNSUPPORTED_HARDWARE = 5,
    OIDN_ERROR_CANCELLED = 6,
} OIDNError;

typedef enum {
    OIDN_FORMAT_UNDEFINED = 0,
    OIDN_FORMAT_FLOAT3 = 3, /* three 32-bit floats per pixel: our RGB, albedo and normal */
} OIDNFormat;

typedef enum {
    OIDN_QUALITY_DEFAULT = 0,
    OIDN_QUALITY_BALANCED = 5, /* interactive rendering */
    OIDN_QUALITY_HIGH = 6,     /* final frames */
} OIDNQuality;

/* The functions, under their own names. */
typedef struct oidn_api {
    OIDNDevice (*oidnNewDevice)(OIDNDeviceType type);
    void (*oidnCommitDevice)(OIDNDevice device);
    /* "type" (an OIDNDeviceType) and "version" (major * 10000 + minor * 100 + patch). */
    int (*oidnGetDeviceInt)(OIDNDevice device, const char *name);
    /* The first error not yet asked for on this thread, and its message; clears it. A NULL
     * device asks why a device could not be made. */
    OIDNError (*oidnGetDeviceError)(OIDNDevice device, const char **message);
    void (*oidnReleaseDevice)(OIDNDevice device);

    /* A buffer both the host and the device can reach, copied to and from with Write/Read. */
    OIDNBuffer (*oidnNewBuffer)(OIDNDevice device, size_t byte_size);
    void (*oidnWriteBuffer)(OIDNBuffer buffer, size_t byte_offset, size_t byte_size,
                            const void *source);
    void (*oidnReadBuffer)(OIDNBuffer buffer, size_t byte_offset, size_t byte_size,
                           void *destination);
    void (*oidnReleaseBuffer)(OIDNBuffer buffer);

    OIDNFilter (*oidnNewFilter)(OIDNDevice device, const char *type);
    /* Strides of 0 are computed (packed pixels and rows). */
    void (*oidnSetFilterImage)(OIDNFilter filter, const char *name, OIDNBuffer buffer,
                               OIDNFormat format, size_t width, size_t height, size_t byte_offset,
                               size_t pixel_byte_stride, size_t row_byte_stride);
    void (*oidnSetFilterBool)(OIDNFilter filter, const char *name, bool value);
    void (*oidnSetFilterInt)(OIDNFilter filter, const char *name, int value);
    void (*oidnCommitFilter)(OIDNFilter filter);
    void (*oidnExecuteFilter)(OIDNFilter filter);
    void (*oidnReleaseFilter)(OIDNFilter filter);
} oidn_api;

#endif
