/*
 * rtpipe_accel.h: the driver's acceleration structures over a mesh: one bottom-level structure
 * of the mesh's triangles (one opaque geometry, non-indexed, three R32G32B32_SFLOAT vertices per
 * triangle, in the mesh's order, PREFER_FAST_TRACE) and one top-level structure holding it once
 * with the identity transform. Built on the GPU, timed with timestamps.
 */
#ifndef RTPIPE_ACCEL_H
#define RTPIPE_ACCEL_H

#include <stdbool.h>
#include <stdint.h>

#include "error.h"
#include "gpu/buffer.h"
#include "rtpipe_device.h"

/* Builds timed back to back (into the same structures); their median is reported. */
enum { RTPIPE_BUILD_RUNS = 5 };

typedef struct rtpipe_accel {
    VkAccelerationStructureKHR blas, tlas;
    gpu_buffer blas_buffer, tlas_buffer;
    VkDeviceSize blas_bytes, tlas_bytes; /* accelerationStructureSize of each (not compacted) */
    VkDeviceSize scratch_bytes;          /* the build's scratch memory, freed after it */
    double build_ms;       /* BLAS + TLAS, median of RTPIPE_BUILD_RUNS builds */
    double build_ms_first; /* the first of them (a GPU coming out of idle) */
    double blas_ms, tlas_ms; /* medians of each part */
} rtpipe_accel;

/* Builds the structures over triangle_count triangles (positions: 9 floats each). On failure
 * returns false with err set and nothing left allocated. */
bool rtpipe_accel_create(rtpipe_device *dev, const float *positions, uint32_t triangle_count,
                         rtpipe_accel *accel, vkrt_error *err);

/* Frees the structures. Safe on a zeroed one. */
void rtpipe_accel_destroy(rtpipe_device *dev, rtpipe_accel *accel);

#endif
