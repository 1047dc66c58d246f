/*
 * bench_rays.h: the rays `vkrt bench` traces, made on the CPU, so that another tracer can be
 * timed on exactly the same ones (tools/embree-bench.c). Callers pass the arrays in.
 */
#ifndef VKRT_BENCH_RAYS_H
#define VKRT_BENCH_RAYS_H

#include <stdint.h>

#include "scene/scene.h"

/* The structs of glsl/shared.h. */
typedef struct Ray Ray;
typedef struct Hit Hit;

/* Fills width * height rays through the pixel centres of the scene's first camera, row by row
 * from the top, bit for bit what the renderer's raygen traces at one sample per pixel. */
void bench_primary_rays(const vkrt_scene *scene, uint32_t width, uint32_t height, Ray *rays);

/* For each of the count primary rays that hit (hits[i].triangle != VKRT_NO_HIT), one shadow ray
 * from just off the hit towards the scene's first point or spot light (tmax the distance to it),
 * or against its first directional light; info.x is the primary ray's index. Writes them to
 * shadow (room for count) in order and returns how many. */
uint32_t bench_shadow_rays(const vkrt_scene *scene, const Ray *primary, const Hit *hits,
                           uint32_t count, Ray *shadow);

/* As bench_shadow_rays, but each ray leaves the hit in a cosine-distributed direction about the
 * normal on the camera's side, from a fixed hash of the primary ray's index: the same rays on
 * every run. */
uint32_t bench_diffuse_rays(const vkrt_scene *scene, const Ray *primary, const Hit *hits,
                            uint32_t count, Ray *diffuse);

#endif
