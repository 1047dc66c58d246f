/* error.c: formatting of vkrt_error messages (see error.h). */
#include "error.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

bool vkrt_error_set(vkrt_error *err, const char *fmt, ...)
{
    if (!err)
        return false;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err->msg, sizeof err->msg, fmt, ap);
    va_end(ap);
    return false;
}

bool vkrt_error_prefix(vkrt_error *err, const char *fmt, ...)
{
    if (!err)
        return false;
    char prefix[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(prefix, sizeof prefix, fmt, ap);
    va_end(ap);
    char old[sizeof err->msg];
    memcpy(old, err->msg, sizeof old);
    /* A message cut short is acceptable; the test keeps GCC from warning about it. */
    if (snprintf(err->msg, sizeof err->msg, "%s: %s", prefix, old) >= (int)sizeof err->msg)
        err->msg[sizeof err->msg - 1] = '\0';
    return false;
}

bool vkrt_error_set_file(vkrt_error *err, const char *referrer, const char *kind, const char *path,
                         const char *fmt, ...)
{
    char reason[700];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(reason, sizeof reason, fmt, ap);
    va_end(ap);
    if (referrer && *referrer)
        return vkrt_error_set(err, "%s: %s '%s': %s", referrer, kind, path, reason);
    return vkrt_error_set(err, "%s '%s': %s", kind, path, reason);
}
