/*
 * error.h: how vkrt reports a failure up the stack.
 *
 * Every function that can fail for a reason a user can cause returns bool (true on success) and,
 * on failure, fills a vkrt_error with one line of text that names its context, for example
 * "scenes/x/scene.cfg:12: light spot needs 10 numbers, got 7". Library code never exits or
 * aborts; only main decides how to exit.
 */
#ifndef VKRT_ERROR_H
#define VKRT_ERROR_H

#include <stdbool.h>

typedef struct vkrt_error {
    char msg[1024];
} vkrt_error;

/* Formats a message into err (printf style) and returns false, so callers can write
 * `return vkrt_error_set(err, "...")`. err may be NULL, then the message is dropped. */
bool vkrt_error_set(vkrt_error *err, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* A message about a file a scene names: "<referrer>: <kind> '<path>': <reason>", the referrer
 * (where the file was named, e.g. "scene.cfg:4") left out when NULL or empty. Returns false. */
bool vkrt_error_set_file(vkrt_error *err, const char *referrer, const char *kind, const char *path,
                         const char *fmt, ...) __attribute__((format(printf, 5, 6)));

/* Prefixes an existing message with context: "ctx: old message". Returns false. */
bool vkrt_error_prefix(vkrt_error *err, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#endif
