/* temporary.c: frames' temporary files, named and cleaned up (temporary.h). */
#define _POSIX_C_SOURCE 200809L
#include "temporary.h"

#include <dirent.h>
#include <errno.h>
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define TMP_MARK ".tmp-"

/* gethostname's name with only [A-Za-z0-9._] kept (others '_'), so that it can stand in a file
 * name and the pid after it is found at the last '-'. */
static void host_name(char out[256])
{
    if (gethostname(out, 255) != 0 || !out[0])
        snprintf(out, 256, "unknown");
    out[255] = '\0';
    for (char *c = out; *c; c++)
        if (!((*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z') || (*c >= '0' && *c <= '9') ||
              *c == '.' || *c == '_'))
            *c = '_';
}

bool vkrt_temporary_name(char *out, size_t size, const char *target)
{
    char host[256];
    host_name(host);
    int n = snprintf(out, size, "%s" TMP_MARK "%s-%ld", target, host, (long)getpid());
    return n >= 0 && (size_t)n < size;
}

/* Whether tail (what follows ".tmp-" in a file name) names a writer of this host that is gone. */
static bool writer_gone(const char *tail, const char *host)
{
    const char *dash = strrchr(tail, '-');
    const char *digits = dash ? dash + 1 : tail;
    if (dash && ((size_t)(dash - tail) != strlen(host) || strncmp(tail, host, strlen(host)) != 0))
        return false; /* another host's, or not ours at all */
    if (!*digits || strspn(digits, "0123456789") != strlen(digits) || strlen(digits) > 9)
        return false;
    long pid = strtol(digits, NULL, 10);
    if (pid <= 0 || pid > INT_MAX)
        return false;
    return kill((pid_t)pid, 0) != 0 && errno == ESRCH;
}

/* A file name split as a pattern's last part is: prefix, then (if number) a frame number of
 * digits and spaces, then suffix. */
typedef struct name_shape {
    char prefix[1024], suffix[1024];
    bool number;
} name_shape;

/* Whether name is "<a name of shape>.tmp-<tail>"; *tail then points at the tail. */
static bool matches(const char *name, const name_shape *shape, const char **tail)
{
    size_t p = strlen(shape->prefix);
    if (strncmp(name, shape->prefix, p) != 0)
        return false;
    const char *at = name + p;
    if (shape->number) {
        size_t n = strspn(at, " 0123456789");
        if (strcspn(at, "0123456789") >= n) /* no digit among them */
            return false;
        at += n;
    }
    size_t s = strlen(shape->suffix);
    if (strncmp(at, shape->suffix, s) != 0 || strncmp(at + s, TMP_MARK, strlen(TMP_MARK)) != 0)
        return false;
    *tail = at + s + strlen(TMP_MARK);
    return true;
}

static unsigned remove_in_folder(const char *folder, const name_shape *shape)
{
    DIR *dir = opendir(folder);
    if (!dir)
        return 0;
    char host[256];
    host_name(host);
    unsigned removed = 0;
    for (struct dirent *e; (e = readdir(dir));) {
        const char *tail;
        if (!matches(e->d_name, shape, &tail) || !writer_gone(tail, host))
            continue;
        char path[8400];
        snprintf(path, sizeof path, "%s/%s", folder, e->d_name);
        removed += unlink(path) == 0;
    }
    closedir(dir);
    return removed;
}

/* path's folder ("." for a bare name, "/" for the root) into folder; its last part returned. */
static const char *split_folder(const char *path, char folder[4096])
{
    const char *slash = strrchr(path, '/');
    if (!slash)
        snprintf(folder, 4096, ".");
    else if (slash == path)
        snprintf(folder, 4096, "/");
    else
        snprintf(folder, 4096, "%.*s", (int)(slash - path), path);
    return slash ? slash + 1 : path;
}

unsigned vkrt_temporaries_remove_dead_beside(const char *path)
{
    char folder[4096];
    name_shape shape = {.number = false};
    snprintf(shape.prefix, sizeof shape.prefix, "%s", split_folder(path, folder));
    return remove_in_folder(folder, &shape);
}

/* Copies a pattern's text (stop excluded) into out, "%%" as '%'; false at a conversion. */
static bool unescape(const char *from, const char *stop, char *out, size_t size)
{
    size_t n = 0;
    for (const char *c = from; c < stop; c++) {
        if (*c == '%' && c[1] != '%')
            return false;
        if (*c == '%')
            c++;
        if (n + 1 < size)
            out[n++] = *c;
    }
    out[n] = '\0';
    return true;
}

unsigned vkrt_temporaries_remove_dead(const char *pattern)
{
    char folder_pattern[4096], folder[4096];
    const char *base = split_folder(pattern, folder_pattern);
    if (!unescape(folder_pattern, folder_pattern + strlen(folder_pattern), folder, sizeof folder))
        return 0; /* a number in a folder name */
    /* The conversion: the first '%' not doubled. */
    const char *conv = NULL;
    for (const char *c = base; *c && !conv; c++) {
        if (*c == '%' && c[1] == '%')
            c++;
        else if (*c == '%')
            conv = c;
    }
    name_shape shape = {.number = conv != NULL};
    const char *end = base + strlen(base);
    if (!unescape(base, conv ? conv : end, shape.prefix, sizeof shape.prefix))
        return 0;
    if (conv) {
        const char *after = conv + 1 + strspn(conv + 1, "0123456789");
        if (*after != 'd' || !unescape(after + 1, end, shape.suffix, sizeof shape.suffix))
            return 0;
    }
    return remove_in_folder(folder, &shape);
}
