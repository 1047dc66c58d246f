/* temp_dir.c: a temporary folder per test (see temp_dir.h). */
#define _XOPEN_SOURCE 700
#include "temp_dir.h"

#include <dirent.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>

int temp_dir_make(void **state)
{
    temp_dir *fx = calloc(1, sizeof *fx);
    if (!fx)
        return -1;
    strcpy(fx->dir, "/tmp/vkrt_test_XXXXXX");
    if (!mkdtemp(fx->dir)) {
        free(fx);
        return -1;
    }
    *state = fx;
    return 0;
}

/* Removes dir and everything below it; lstat, so a link to a folder is unlinked, not entered. */
static void remove_tree(const char *dir)
{
    DIR *d = opendir(dir);
    struct dirent *e;
    while (d && (e = readdir(d))) {
        char p[700];
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, ".."))
            continue;
        snprintf(p, sizeof p, "%s/%s", dir, e->d_name);
        struct stat st;
        if (lstat(p, &st) == 0 && S_ISDIR(st.st_mode))
            remove_tree(p);
        else
            unlink(p);
    }
    if (d)
        closedir(d);
    rmdir(dir);
}

int temp_dir_remove(void **state)
{
    temp_dir *fx = *state;
    remove_tree(fx->dir);
    free(fx);
    return 0;
}

const char *temp_dir_path(temp_dir *fx, const char *name)
{
    snprintf(fx->path, sizeof fx->path, "%s/%s", fx->dir, name);
    return fx->path;
}

const char *temp_dir_write(temp_dir *fx, const char *name, const void *data, size_t len)
{
    FILE *f = fopen(temp_dir_path(fx, name), "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(data, 1, len, f), len);
    fclose(f);
    return fx->path;
}

const char *temp_dir_write_text(temp_dir *fx, const char *name, const char *text)
{
    return temp_dir_write(fx, name, text, strlen(text));
}
