/*
 * bench_rays.h: the rays `vkrt bench` traces, made on the CPU so that any tracer (vkrt's
 * kernels, or a yardstick on the driver's ray tracing pipeline) gets exactly the same ones: primary rays through pixel centres, then from their hits shadow rays (any hit) and
 * cosine-distributed diffuse bounce rays (closest hit). Pure CPU, no Vulkan.
 */
#ifndef VKRT_BENCH_RAYS_H
#define VKRT_BENCH_RAYS_H

#include <stdbool.h>
#include <stdint.h>

#include "scene/scene.h"

/* The structs of glsl/shared.h. */
typedef struct Ray Ray;
typedef struct Hit Hit;

/* Fills width * height rays through the pixel centres of camera for an image of that size, in
 * the order raygen.comp makes them at one sample per pixel (8x8 pixel tiles); info.x is the
 * pixel index (row by row, the top row first). */
void bench_primary_rays(const vkrt_config_camera *camera, uint32_t width, uint32_t height,
                        Ray *rays);

/* For each of the count primary rays that hit (hits[i].triangle != VKRT_NO_HIT, the triangle an
 * index into the model's triangles in world space, vkrt_model_world), one shadow ray from just off the surface towards the first point or
 * spot light (or against the first directional light; without any, towards a point above the
 * scene's bounds). Writes them to shadow (room for count) and returns how many (0 where memory
 * runs out). */
uint32_t bench_shadow_rays(const vkrt_scene *scene, const Ray *primary, const Hit *hits,
                           uint32_t count, Ray *shadow);

/* For each primary hit, one diffuse bounce ray in a cosine-distributed direction about the
 * normal facing the camera, from a hash of the ray's index (the same rays every run). Writes
 * them to diffuse (room for count) and returns how many. */
uint32_t bench_diffuse_rays(const vkrt_scene *scene, const Ray *primary, const Hit *hits,
                            uint32_t count, Ray *diffuse);

#endif
