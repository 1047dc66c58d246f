/*
 * line_parser.h: the loop and the error form that vkrt's line-based text formats share.
 *
 * scene.cfg and material files are both read a line at a time: each line is checked and cut into
 * tokens (text_file.h), lines without tokens are passed over, the first bad line stops the parse,
 * and every message starts "file:line: ". This module is that loop and that prefix; what a line
 * means, and how its mistakes are phrased, stays with each format's parser.
 */
#ifndef VKRT_LINE_PARSER_H
#define VKRT_LINE_PARSER_H

#include <stdbool.h>
#include <stddef.h>

#include "../error.h"
#include "text_file.h"

/* Where a parse stands: what its messages start with, and where they go. */
typedef struct vkrt_line_parser {
    const char *name; /* the file name shown in messages */
    int line;         /* the line being parsed, counted from 1; 0 before the first */
    vkrt_error *err;  /* where a failure is reported (may be NULL: the message is dropped) */
} vkrt_line_parser;

/* Reports "name:line: " followed by the printf-formatted message into at->err (a message longer
 * than vkrt_error holds is cut short). Returns false, so a parser can write
 * `return vkrt_line_fail(at, ...)`. */
bool vkrt_line_fail(const vkrt_line_parser *at, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

/* What a format does with one line: t holds at least one token. Returns false after reporting the
 * failure (with vkrt_line_fail); ctx is the format's own parser state. */
typedef bool (*vkrt_line_fn)(void *ctx, const vkrt_text_tokens *t);

/* Runs line over every line of text[0..size) that has a token: skips a UTF-8 byte order mark,
 * counts lines in at->line, and refuses a line vkrt_text_split refuses (kind names the format in
 * the reason, e.g. "is this a scene.cfg?"). Stops at the first failure and returns false, with
 * the message in at->err; true when every line was accepted (an empty text included). */
bool vkrt_line_parse_all(vkrt_line_parser *at, const char *text, size_t size, const char *kind,
                         vkrt_line_fn line, void *ctx);

/* Reads all of path with vkrt_text_read_file (max_bytes and kind as there) and gives, in *dir,
 * the folder its relative paths are resolved against (vkrt_text_dir_of). Both malloc'd, for the
 * caller to free. On failure returns false with "path: message" in err and both NULL. */
bool vkrt_line_read_file(const char *path, size_t max_bytes, const char *kind, char **text,
                         size_t *size, char **dir, vkrt_error *err);

#endif
