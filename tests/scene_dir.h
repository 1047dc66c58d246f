/*
 * scene_dir.h: what the tests that write little scenes share: a temporary folder (a cmocka group
 * setup and teardown), files written into it, and a render of its scene.cfg through the real
 * renderer on a validated context.
 */
#ifndef VKRT_TEST_SCENE_DIR_H
#define VKRT_TEST_SCENE_DIR_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "error.h"
#include "render/renderer.h"

/* The folder of the current group, set by scene_dir_make. */
extern char scene_dir[64];

/* cmocka group setup and teardown: make and remove the temporary folder. */
int scene_dir_make(void **state);
int scene_dir_remove(void **state);

/* Opens name in the folder for writing (fails the test if it cannot). */
FILE *scene_dir_open(const char *name);

/* Writes text into name in the folder. */
void scene_dir_write(const char *name, const char *text);

/* Loads the folder's scene.cfg into scene (fails the test if it cannot); vkrt_scene_free frees
 * it. */
struct vkrt_scene;
void scene_dir_load(struct vkrt_scene *scene);

/* Renders the folder's scene.cfg at w x h, desc's samples per pixel (0: one), with the rest of
 * the settings from desc (may be NULL). False with err on failure. */
bool scene_dir_render(uint32_t w, uint32_t h, const vkrt_render_desc *desc, float *rgb,
                      vkrt_frame_stats *stats, vkrt_error *err);

/* scene_dir_render that also copies the structure's statistics (the BVH's references, say) into
 * *accel when accel is not NULL. */
bool scene_dir_render_accel(uint32_t w, uint32_t h, const vkrt_render_desc *desc, float *rgb,
                            vkrt_frame_stats *stats, vkrt_accel_stats *accel, vkrt_error *err);

#endif
