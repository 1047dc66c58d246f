/*
 * rtpipe_accel.h: the driver's acceleration structures over a scene, in one of two forms:
 *
 * - flat (rtpipe_accel_create): one bottom-level structure (BLAS) of the given triangles (one
 *   opaque geometry, non-indexed, three R32G32B32_SFLOAT vertices per triangle, in their order)
 *   and one top-level structure (TLAS) holding it once with the identity transform. A hit's
 *   triangle is gl_PrimitiveID (RTPIPE_HIT_PRIMITIVE).
 * - two-level (rtpipe_accel_create_instanced): one BLAS per mesh that an instance uses, over the
 *   mesh's triangles in the mesh's own space (the same one geometry each), and a TLAS with one
 *   VkAccelerationStructureInstanceKHR per instance, its transform the instance's 3x4 row-major
 *   matrix as it is: real instancing, each mesh once in device memory. Instances of an empty
 *   mesh or with a singular (or non-finite) 3x3 part are left out, as vkrt's two-level BVH
 *   leaves them out. A hit's triangle is numbered as vkrt_model_world numbers it (instance
 *   after instance of the model, each instance's triangles in its mesh's order; what vkrt bench
 *   reports and bench_rays.h reads): the instance's first triangle in that order plus
 *   gl_PrimitiveID. The first triangle is the instance's instanceCustomIndex where every kept
 *   instance's fits its 24 bits (RTPIPE_HIT_CUSTOM_INDEX), else it is read from instance_first
 *   at gl_InstanceID (RTPIPE_HIT_INSTANCE_BUFFER).
 *
 * Every build uses PREFER_FAST_TRACE, runs on the GPU and is timed with timestamps: all BLAS
 * builds in one vkCmdBuildAccelerationStructuresKHR, then the TLAS build.
 */
#ifndef RTPIPE_ACCEL_H
#define RTPIPE_ACCEL_H

#include <stdbool.h>
#include <stdint.h>

#include "error.h"
#include "gpu/buffer.h"
#include "rtpipe_device.h"
#include "scene/model.h"

/* Builds timed back to back (into the same structures); their median is reported. */
enum { RTPIPE_BUILD_RUNS = 5 };

/* How closest.rchit numbers a hit's triangle: its specialization constant 0. */
typedef enum rtpipe_hit_numbering {
    RTPIPE_HIT_PRIMITIVE = 0,       /* gl_PrimitiveID */
    RTPIPE_HIT_CUSTOM_INDEX = 1,    /* gl_InstanceCustomIndexEXT + gl_PrimitiveID */
    RTPIPE_HIT_INSTANCE_BUFFER = 2, /* instance_first[gl_InstanceID] + gl_PrimitiveID */
} rtpipe_hit_numbering;

/* What a build takes: the BLASes' triangles (each one geometry, non-indexed, in its own space)
 * and the TLAS's instances, whose accelerationStructureReference holds its BLAS's index until
 * the structures' device addresses are known; instance_first[i] is TLAS instance i's first
 * triangle in vkrt_model_world's order. */
typedef struct rtpipe_plan {
    uint32_t blas_count;
    const float **positions; /* per BLAS, 9 floats a triangle (the model's, not copied) */
    uint32_t *triangles;     /* per BLAS */
    uint32_t instance_count;
    VkAccelerationStructureInstanceKHR *instances;
    uint32_t *instance_first;
    rtpipe_hit_numbering numbering;
} rtpipe_plan;

/* The two-level form's plan for model, on the CPU (no device): a BLAS per mesh a kept instance
 * uses, in the order of first use; the kept instances in the model's order. False with err set
 * (and nothing allocated) when memory runs out or no instance can be kept. */
bool rtpipe_plan_instanced(const vkrt_model *model, rtpipe_plan *p, vkrt_error *err);

/* Frees the plan's arrays and zeroes it. Safe on a zeroed plan. */
void rtpipe_plan_free(rtpipe_plan *p);

typedef struct rtpipe_accel {
    VkAccelerationStructureKHR *blas; /* blas_count, each at its own offset of blas_buffer */
    uint32_t blas_count;
    VkAccelerationStructureKHR tlas;
    gpu_buffer blas_buffer, tlas_buffer;
    /* Per TLAS instance (gl_InstanceID), its first triangle in vkrt_model_world's order, as
     * uint32; always there (one 0 for the flat form), bound for the closest-hit shader. */
    gpu_buffer instance_first;
    rtpipe_hit_numbering numbering;
    bool two_level;
    uint32_t instances;                  /* in the TLAS */
    uint64_t unique_triangles;           /* over the BLASes: each mesh once */
    VkDeviceSize blas_bytes, tlas_bytes; /* accelerationStructureSize summed (not compacted) */
    VkDeviceSize scratch_bytes;          /* the build's scratch memory, freed after it */
    double build_ms;       /* BLASes + TLAS, median of RTPIPE_BUILD_RUNS builds */
    double build_ms_first; /* the first of them (a GPU coming out of idle) */
    double blas_ms, tlas_ms; /* medians of each part */
} rtpipe_accel;

/* The flat form over triangle_count triangles (positions: 9 floats each). On failure returns
 * false with err set and nothing left allocated. */
bool rtpipe_accel_create(rtpipe_device *dev, const float *positions, uint32_t triangle_count,
                         rtpipe_accel *accel, vkrt_error *err);

/* The two-level form over model's meshes and instances (model->triangle_count, a 32-bit count,
 * bounds the hit numbers). Same contract as rtpipe_accel_create; err also says when no instance
 * can be kept or a count passes the device's limits. */
bool rtpipe_accel_create_instanced(rtpipe_device *dev, const vkrt_model *model,
                                   rtpipe_accel *accel, vkrt_error *err);

/* Frees the structures. Safe on a zeroed one. */
void rtpipe_accel_destroy(rtpipe_device *dev, rtpipe_accel *accel);

#endif
