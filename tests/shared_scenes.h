/*
 * shared_scenes.h: where the tests find the shared scenes (../shared/scenes, given as
 * $VKRT_SCENES_DIR by tests/meson.build), for the tests that read them whole.
 */
#ifndef VKRT_TEST_SHARED_SCENES_H
#define VKRT_TEST_SHARED_SCENES_H

#ifdef __cplusplus
extern "C" {
#endif

/* $VKRT_SCENES_DIR when it names a folder; else NULL, after printing why the tests that need it
 * skip. */
const char *shared_scenes_dir(void);

#ifdef __cplusplus
}
#endif

#endif
