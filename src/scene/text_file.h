/*
 * text_file.h: what vkrt's hand-written text formats (scene.cfg, material files) share.
 *
 * Both are read whole, split into lines, each line checked (text, not binary; UTF-8 before any
 * '#') and cut into tokens at spaces and tabs; both resolve relative paths against their own
 * folder and read finite floats. Keeping these rules in one place keeps the two formats alike:
 * a file that one parser calls "not a text line" the other calls the same. Each parser still
 * phrases its own messages, so the functions here report a reason, not a finished message.
 */
#ifndef VKRT_TEXT_FILE_H
#define VKRT_TEXT_FILE_H

#include <stdbool.h>
#include <stddef.h>

#include "../error.h"

enum {
    VKRT_TEXT_MAX_LINE_BYTES = 4096, /* a longer line is a mistake or not a hand-written file */
    VKRT_TEXT_MAX_TOKENS = 32,       /* tokens kept per line; more are counted, not kept */
    VKRT_TEXT_SHOWN_BYTES = 60,      /* how much of a bad token a message quotes */
};

/* One line cut into tokens. tok[i] point into buf; count is the number of tokens on the line,
 * even past VKRT_TEXT_MAX_TOKENS, so that a message can say "got N" truthfully. */
typedef struct vkrt_text_tokens {
    char buf[VKRT_TEXT_MAX_LINE_BYTES + 1];
    char *tok[VKRT_TEXT_MAX_TOKENS];
    int count;
} vkrt_text_tokens;

/* Reads all of path (a file or a pipe) into a malloc'd buffer of *size bytes (not terminated).
 * kind names the format in the message for a file over max_bytes ("larger than N MiB; is this a
 * <kind>?"). On failure returns false with "path: message" in err and *text NULL. */
bool vkrt_text_read_file(const char *path, size_t max_bytes, const char *kind, char **text,
                         size_t *size, vkrt_error *err);

/* Skips a UTF-8 byte order mark (some Windows editors write one) at the start of text. */
void vkrt_text_skip_bom(const char **text, size_t *size);

/* The next line of text[0..size) from *pos on: returns its start, sets *len (without the '\n')
 * and moves *pos past it. Call only while *pos < size. A line ends at '\n' (Unix), "\r\n"
 * (Windows: the '\r' is left in the line, a separator for vkrt_text_split) or a '\r' alone
 * (classic Mac OS), so each counts its lines as an editor does. */
const char *vkrt_text_next_line(const char *text, size_t size, size_t *pos, size_t *len);

/* Checks one line (len bytes, without its '\n') and splits the part before any '#' into tokens
 * separated by spaces, tabs and '\r'. Refused: a NUL or other control character anywhere
 * (comments included), more than VKRT_TEXT_MAX_LINE_BYTES bytes, invalid UTF-8 before the '#'.
 * On refusal returns false and writes the reason into why, e.g. "not a text line (NUL byte at
 * column 3); is this a <kind>?". */
bool vkrt_text_split(const char *line, size_t len, const char *kind, vkrt_text_tokens *t, char *why,
                     size_t why_size);

/* tok as a message quotes it: itself, or cut at a UTF-8 boundary after VKRT_TEXT_SHOWN_BYTES
 * bytes and ended with "..." in buf, so one absurd token cannot push the useful part of a
 * message out of the fixed-size vkrt_error. */
const char *vkrt_text_shown(const char *tok, char buf[VKRT_TEXT_SHOWN_BYTES + 4]);

/* Reads tok, all of it, as a finite float. Returns NULL on success, else why not: "is not a
 * number", "is not a finite number" (nan, inf, 1e999) or "is too large (the limit is about
 * 3.4e38)", to follow the quoted token in a message. */
const char *vkrt_text_float(const char *tok, float *out);

/* Whether s ends in suffix (ASCII letters of s compared without case; suffix in lower case). */
bool vkrt_text_ends_with(const char *s, const char *suffix);

/* base_dir joined with path, unless path is absolute or base_dir is "": a malloc'd string, NULL
 * when out of memory. With escape_percent a '%' of base_dir is written "%%" (for frame patterns,
 * where '%' is special). */
char *vkrt_text_join_path(const char *base_dir, const char *path, bool escape_percent);

/* The folder part of path (before the last '/'), malloc'd: "" for a bare name, "/" for a file in
 * the root folder. NULL when out of memory. */
char *vkrt_text_dir_of(const char *path);

#endif
