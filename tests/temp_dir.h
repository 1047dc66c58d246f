/*
 * temp_dir.h: a temporary folder for one test, for the tests that write small files (OBJ and
 * .mtl files, images) and load them back: made under /tmp by a cmocka setup, removed with all
 * that the test put in it by the matching teardown.
 */
#ifndef VKRT_TEST_TEMP_DIR_H
#define VKRT_TEST_TEMP_DIR_H

#include <stddef.h>

typedef struct temp_dir {
    char dir[64];   /* the folder, e.g. "/tmp/vkrt_test_Ab12Cd" */
    char path[512]; /* the path temp_dir_path (or a write) named last */
} temp_dir;

/* An entry of a cmocka test list: test run in a fresh folder, its temp_dir in *state. */
#define temp_dir_test(test) cmocka_unit_test_setup_teardown(test, temp_dir_make, temp_dir_remove)

/* cmocka setup: a fresh folder, its temp_dir (heap) in *state. Returns 0, or -1 if it fails. */
int temp_dir_make(void **state);

/* cmocka teardown: removes the folder of the temp_dir in *state, with its files and sub-folders
 * (symbolic links are removed, not followed), and frees the temp_dir. Returns 0. */
int temp_dir_remove(void **state);

/* The path of name inside the folder, written into fx->path and returned. */
const char *temp_dir_path(temp_dir *fx, const char *name);

/* Writes len bytes of data to name inside the folder (fails the test if it cannot) and returns
 * its path (fx->path). */
const char *temp_dir_write(temp_dir *fx, const char *name, const void *data, size_t len);

/* temp_dir_write of a string, without its terminating NUL. */
const char *temp_dir_write_text(temp_dir *fx, const char *name, const char *text);

#endif
