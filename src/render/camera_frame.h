/*
 * camera_frame.h: a scene.cfg camera as the frame raygen.comp reads. Pure CPU, so that `vkrt
 * bench` (bench_rays.c) makes the very rays raygen does.
 */
#ifndef VKRT_CAMERA_FRAME_H
#define VKRT_CAMERA_FRAME_H

#include <stdint.h>

#include "../scene/config.h"

/* The struct of glsl/shared.h. */
typedef struct FrameParams FrameParams;

/* Fills params->eye, forward, right and up for camera and an image of width x height: the
 * camera frame raygen.comp reads (right and up scaled by tan(fov/2), right also by the aspect;
 * a thin lens's radius in right.w and its focus distance in up.w, both 0 for a pinhole).
 * The other fields are left as they are. */
void vkrt_camera_params(const vkrt_config_camera *camera, uint32_t width, uint32_t height,
                        FrameParams *params);

/* The camera a fraction t (0 to 1) of the way from a to b, for motion blur: the eye and the field
 * of view interpolated linearly, the orientation by spherical interpolation of the two frames'
 * rotations (slerp, the shorter way round); the lens is a's. */
void vkrt_camera_between(const vkrt_config_camera *a, const vkrt_config_camera *b, float t,
                         vkrt_config_camera *out);

#endif
