/* text_file.c: reading, lines, tokens, numbers and paths of hand-written text files (see
 * text_file.h). Nothing here opens a file but vkrt_text_read_file: joining a path only joins. */
#define _POSIX_C_SOURCE 200809L

#include "text_file.h"

#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

bool vkrt_text_read_file(const char *path, size_t max_bytes, const char *kind, char **text,
                         size_t *size, vkrt_error *err)
{
    *text = NULL;
    *size = 0;
    FILE *f = fopen(path, "rb");
    if (!f)
        return vkrt_error_set(err, "%s: cannot open: %s", path, strerror(errno));
    /* Read in chunks rather than trusting a size from fstat: it may be a pipe, or change while
     * read. A regular file's size only sizes the first chunk, so a large OBJ is read in one. */
    size_t used = 0, cap = 0;
    char *buf = NULL;
    struct stat st;
    if (fstat(fileno(f), &st) == 0 && S_ISREG(st.st_mode) && st.st_size > 0 &&
        (uintmax_t)st.st_size < max_bytes) {
        /* One byte more than the file, so that reading to its end needs no growth. */
        cap = (size_t)st.st_size + 1;
        if (!(buf = malloc(cap))) {
            fclose(f);
            return vkrt_error_set(err, "%s: out of memory", path);
        }
    }
    for (;;) {
        if (used == cap) {
            if (cap >= max_bytes) {
                free(buf);
                fclose(f);
                return vkrt_error_set(err, "%s: larger than %zu MiB; is this a %s?", path,
                                      max_bytes >> 20, kind);
            }
            cap = cap ? 2 * cap : 4096;
            char *grown = realloc(buf, cap);
            if (!grown) {
                free(buf);
                fclose(f);
                return vkrt_error_set(err, "%s: out of memory", path);
            }
            buf = grown;
        }
        size_t n = fread(buf + used, 1, cap - used, f);
        used += n;
        if (n == 0)
            break;
    }
    if (ferror(f)) {
        int saved = errno;
        free(buf);
        fclose(f);
        return vkrt_error_set(err, "%s: cannot read: %s", path, strerror(saved));
    }
    fclose(f);
    *text = buf;
    *size = used;
    return true;
}

void vkrt_text_skip_bom(const char **text, size_t *size)
{
    if (*size >= 3 && memcmp(*text, "\xEF\xBB\xBF", 3) == 0) {
        *text += 3;
        *size -= 3;
    }
}

const char *vkrt_text_next_line(const char *text, size_t size, size_t *pos, size_t *len)
{
    const char *line = text + *pos;
    size_t rest = size - *pos;
    const char *nl = memchr(line, '\n', rest);
    /* A '\r' not followed by '\n' ends a line too: files from classic Mac OS end their lines so,
     * and read as one long line they would give a message about the wrong thing. */
    const char *cr = memchr(line, '\r', nl ? (size_t)(nl - line) : rest);
    if (cr && cr + 1 != nl)
        nl = cr;
    *len = nl ? (size_t)(nl - line) : rest;
    *pos += *len + (nl ? 1 : 0);
    return line;
}

/* Length of the valid UTF-8 sequence at s (at most n bytes), or 0 if invalid. */
static size_t utf8_sequence(const unsigned char *s, size_t n)
{
    size_t len;
    unsigned min;
    if (s[0] < 0x80)
        return 1;
    if (s[0] >= 0xC2 && s[0] <= 0xDF)
        len = 2, min = 0x80;
    else if (s[0] >= 0xE0 && s[0] <= 0xEF)
        len = 3, min = 0x800;
    else if (s[0] >= 0xF0 && s[0] <= 0xF4)
        len = 4, min = 0x10000;
    else
        return 0;
    if (len > n)
        return 0;
    unsigned cp = s[0] & (0x7F >> len);
    for (size_t i = 1; i < len; i++) {
        if ((s[i] & 0xC0) != 0x80)
            return 0;
        cp = (cp << 6) | (s[i] & 0x3F);
    }
    if (cp < min || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF))
        return 0;
    return len;
}

bool vkrt_text_split(const char *line, size_t len, const char *kind, vkrt_text_tokens *t, char *why,
                     size_t why_size)
{
    /* Control characters anywhere, comments included, mean this is not a text file. */
    for (size_t i = 0; i < len; i++) {
        unsigned char c = (unsigned char)line[i];
        if (c == '\0') {
            snprintf(why, why_size, "not a text line (NUL byte at column %zu); is this a %s?",
                     i + 1, kind);
            return false;
        }
        if ((c < 0x20 && c != '\t' && c != '\r') || c == 0x7F) {
            snprintf(why, why_size, "not a text line (control character 0x%02X at column %zu)", c,
                     i + 1);
            return false;
        }
    }
    if (len > VKRT_TEXT_MAX_LINE_BYTES) {
        snprintf(why, why_size, "line is longer than %d bytes", VKRT_TEXT_MAX_LINE_BYTES);
        return false;
    }

    const char *hash = memchr(line, '#', len);
    size_t used = hash ? (size_t)(hash - line) : len;
    /* Only the part that is parsed must be UTF-8, so a Latin-1 comment does no harm. */
    for (size_t i = 0; i < used;) {
        size_t n = utf8_sequence((const unsigned char *)line + i, used - i);
        if (n == 0) {
            snprintf(why, why_size, "not a text line (invalid UTF-8 at column %zu)", i + 1);
            return false;
        }
        i += n;
    }

    memcpy(t->buf, line, used);
    t->buf[used] = '\0';
    t->count = 0;
    char *s = t->buf;
    for (;;) {
        s += strspn(s, " \t\r");
        if (*s == '\0')
            break;
        if (t->count < VKRT_TEXT_MAX_TOKENS)
            t->tok[t->count] = s;
        t->count++;
        s += strcspn(s, " \t\r");
        if (*s != '\0')
            *s++ = '\0';
    }
    return true;
}

const char *vkrt_text_shown(const char *tok, char buf[VKRT_TEXT_SHOWN_BYTES + 4])
{
    size_t n = strlen(tok);
    if (n <= VKRT_TEXT_SHOWN_BYTES)
        return tok;
    n = VKRT_TEXT_SHOWN_BYTES;
    while (n > 0 && ((unsigned char)tok[n] & 0xC0) == 0x80)
        n--;
    memcpy(buf, tok, n);
    memcpy(buf + n, "...", 4);
    return buf;
}

const char *vkrt_text_float(const char *tok, float *out)
{
    char *end;
    errno = 0;
    double d = strtod(tok, &end);
    if (end == tok || *end != '\0')
        return "is not a number";
    /* strtod accepts "nan" and "inf" and turns 1e999 into inf; none of them can be rendered. */
    if (!isfinite(d))
        return "is not a finite number";
    if (fabs(d) > FLT_MAX)
        return "is too large (the limit is about 3.4e38)";
    *out = (float)d;
    return NULL;
}

bool vkrt_text_ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix);
    if (n < m)
        return false;
    for (size_t i = 0; i < m; i++) {
        char c = s[n - m + i];
        if (c >= 'A' && c <= 'Z')
            c = (char)(c - 'A' + 'a');
        if (c != suffix[i])
            return false;
    }
    return true;
}

char *vkrt_text_join_path(const char *base_dir, const char *path, bool escape_percent)
{
    if (path[0] == '/' || base_dir[0] == '\0')
        return strdup(path);
    size_t base_len = strlen(base_dir), path_len = strlen(path);
    char *out = malloc(2 * base_len + 1 + path_len + 1);
    if (!out)
        return NULL;
    size_t n = 0;
    for (size_t i = 0; i < base_len; i++) {
        out[n++] = base_dir[i];
        if (escape_percent && base_dir[i] == '%')
            out[n++] = '%';
    }
    if (out[n - 1] != '/')
        out[n++] = '/';
    memcpy(out + n, path, path_len + 1);
    return out;
}

char *vkrt_text_dir_of(const char *path)
{
    const char *slash = strrchr(path, '/');
    size_t dir_len = slash ? (slash == path ? 1 : (size_t)(slash - path)) : 0;
    char *dir = malloc(dir_len + 1);
    if (!dir)
        return NULL;
    memcpy(dir, path, dir_len);
    dir[dir_len] = '\0';
    return dir;
}
