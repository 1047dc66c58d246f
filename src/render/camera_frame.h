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
 * camera frame raygen.comp reads. Perspective: right and up scaled by tan(fov/2), right also by
 * the aspect, forward.w 0. Orthographic (ortho_width > 0): right scaled by half the width, up by
 * half the width over the aspect (square pixels), forward.w 1. A thin lens's radius in right.w
 * and its focus distance in up.w, both 0 for a pinhole. The other fields are left as they are. */
void vkrt_camera_params(const vkrt_config_camera *camera, uint32_t width, uint32_t height,
                        FrameParams *params);

/* The camera a fraction t (0 to 1) of the way from a to b, for motion blur: the eye interpolated
 * linearly, the orientation by spherical interpolation of the two frames' rotations (slerp, the
 * shorter way round); the lens and the projection are a's, its size (the field of view, or the
 * orthographic width) interpolated linearly where b has the same projection, else a's. */
void vkrt_camera_between(const vkrt_config_camera *a, const vkrt_config_camera *b, float t,
                         vkrt_config_camera *out);

#endif
