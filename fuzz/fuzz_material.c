/*
 * fuzz_material.c: libFuzzer target for the material file parser (vkrt_material_file_parse).
 *
 * Each input is taken as the whole text of a material file. The parser must either succeed or
 * fail with a "name:LINE: message"; AddressSanitizer/UBSan catch memory and undefined-behaviour
 * bugs, and LeakSanitizer catches anything a parse leaves allocated.
 *
 * Parsing must not touch the file system: a material line names textures and shaders that are
 * read later, by code that reports a missing one with the line. A parser that looked at them
 * (to test whether a texture exists, or to resolve a path with realpath) would make parse
 * results depend on the working folder and would be slow on network drives. So this target
 * replaces the libc calls that reach the file system with guards that abort while a parse is
 * running, which libFuzzer reports as a crash with the stack of the offending call. Outside a
 * parse they pass through to libc (libFuzzer itself reads the corpus with them).
 */
#define _GNU_SOURCE

#include <dirent.h>
#include <dlfcn.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

#include "scene/material_file.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static volatile int parsing;

/* Aborts if called during a parse; else returns libc's own function of that name. */
static void *guard(const char *name)
{
    if (parsing) {
        fprintf(stderr,
                "fuzz_material: the parser called %s() while parsing; it must not "
                "touch the file system\n",
                name);
        abort();
    }
    void *real = dlsym(RTLD_NEXT, name);
    if (!real)
        abort();
    return real;
}

FILE *fopen(const char *path, const char *mode)
{
    FILE *(*real)(const char *, const char *) = guard("fopen");
    return real(path, mode);
}

int open(const char *path, int flags, ...)
{
    mode_t mode = 0;
    if (flags & (O_CREAT | O_TMPFILE)) {
        va_list ap;
        va_start(ap, flags);
        mode = va_arg(ap, mode_t);
        va_end(ap);
    }
    int (*real)(const char *, int, ...) = guard("open");
    return real(path, flags, mode);
}

int openat(int dir, const char *path, int flags, ...)
{
    mode_t mode = 0;
    if (flags & (O_CREAT | O_TMPFILE)) {
        va_list ap;
        va_start(ap, flags);
        mode = va_arg(ap, mode_t);
        va_end(ap);
    }
    int (*real)(int, const char *, int, ...) = guard("openat");
    return real(dir, path, flags, mode);
}

int stat(const char *path, struct stat *st)
{
    int (*real)(const char *, struct stat *) = guard("stat");
    return real(path, st);
}

int lstat(const char *path, struct stat *st)
{
    int (*real)(const char *, struct stat *) = guard("lstat");
    return real(path, st);
}

int access(const char *path, int mode)
{
    int (*real)(const char *, int) = guard("access");
    return real(path, mode);
}

char *realpath(const char *path, char *resolved)
{
    char *(*real)(const char *, char *) = guard("realpath");
    return real(path, resolved);
}

DIR *opendir(const char *path)
{
    DIR *(*real)(const char *) = guard("opendir");
    return real(path);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    vkrt_material_file file;
    vkrt_error err;
    /* A fixed base_dir that exists nowhere exercises the path joining; with the guards above,
     * a parser that looked for the files would stop here at once. */
    parsing = 1;
    bool ok = vkrt_material_file_parse((const char *)data, size, "fuzz.mat",
                                       "/nonexistent/vkrt-fuzz", &file, &err);
    parsing = 0;
    /* The contract the renderer relies on: a success has a unique name per material and
     * everything it promises in range; a failure says where. */
    if (ok) {
        for (uint32_t i = 0; i < file.count; i++) {
            const vkrt_material_def *d = &file.defs[i];
            if (vkrt_material_file_find(&file, d->name) != d || !d->shader ||
                d->texture_count > VKRT_MATERIAL_FILE_MAX_TEXTURES ||
                d->param_count > VKRT_MATERIAL_FILE_MAX_PARAMS || d->line < 1)
                abort();
            /* base_dir is absolute, so every resolved path is too. */
            if (d->shader[0] != '@' && d->shader[0] != '/')
                abort();
            for (uint32_t k = 0; k < d->texture_count; k++)
                if (d->textures[k][0] != '/')
                    abort();
        }
    } else if (strncmp(err.msg, "fuzz.mat:", 9) != 0) {
        abort();
    }
    /* After a failure *file is left empty (nothing to free), so one unconditional free is right
     * in both cases; anything still allocated afterwards is the parser's leak, reported by LSan. */
    vkrt_material_file_free(&file);
    return 0;
}
