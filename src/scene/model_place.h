/*
 * model_place.h: one scene model from several scene files, each placed once or many times
 * (scene.cfg's `geometry FILE translate ... rotate ... scale ...` lines).
 *
 * A file placed several times keeps its meshes once: each placement adds instances of them, so a
 * tree planted a thousand times costs the GPU one tree (the renderer's two-level structure).
 * Pure CPU, no Vulkan.
 */
#ifndef VKRT_MODEL_PLACE_H
#define VKRT_MODEL_PLACE_H

#include <stdbool.h>
#include <stdint.h>

#include "../error.h"
#include "model.h"

/* Moves src into dst, leaving src zeroed: src's meshes, materials and images once (its meshes'
 * material indices and its texture refs' image indices moved past dst's), and its instances,
 * lights and cameras once per placement, each placement (3x4 row-major) applied after the file's
 * own transforms. src's warnings and inputs are appended to dst's. dst's triangle count and box
 * are left for vkrt_model_finish, which the caller calls after the last file. False with err set
 * when memory runs out; dst and src are then still valid, and the caller frees both. */
bool vkrt_model_place(vkrt_model *dst, vkrt_model *src, const float (*placements)[12],
                      uint32_t placement_count, vkrt_error *err);

/* a * b for 3x4 row-major affine transforms (b applied first). */
void vkrt_transform_compose(const float a[12], const float b[12], float out[12]);

#endif
