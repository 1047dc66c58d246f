/* line_parser.c: the line loop and "file:line: " messages of scene.cfg and material files (see
 * line_parser.h). */
#include "line_parser.h"

#include <limits.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

bool vkrt_line_fail(const vkrt_line_parser *at, const char *fmt, ...)
{
    char msg[900]; /* leaves room in vkrt_error for the name and line in front */
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return vkrt_error_set(at->err, "%s:%d: %s", at->name, at->line, msg);
}

bool vkrt_line_parse_all(vkrt_line_parser *at, const char *text, size_t size, const char *kind,
                         vkrt_line_fn line, void *ctx)
{
    vkrt_text_skip_bom(&text, &size);
    vkrt_text_tokens t;
    size_t pos = 0;
    while (pos < size) {
        if (at->line == INT_MAX)
            return vkrt_line_fail(at, "too many lines");
        at->line++;
        size_t len;
        const char *start = vkrt_text_next_line(text, size, &pos, &len);
        char why[200];
        if (!vkrt_text_split(start, len, kind, &t, why, sizeof why))
            return vkrt_line_fail(at, "%s", why);
        if (t.count > 0 && !line(ctx, &t))
            return false;
    }
    return true;
}

bool vkrt_line_read_file(const char *path, size_t max_bytes, const char *kind, char **text,
                         size_t *size, char **dir, vkrt_error *err)
{
    *dir = NULL;
    if (!vkrt_text_read_file(path, max_bytes, kind, text, size, err))
        return false;
    if (!(*dir = vkrt_text_dir_of(path))) {
        free(*text);
        *text = NULL;
        *size = 0;
        return vkrt_error_set(err, "%s: out of memory", path);
    }
    return true;
}
