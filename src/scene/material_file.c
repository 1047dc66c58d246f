/*
 * material_file.c: the material file parser (see material_file.h, and docs/material-file.md for
 * the format).
 *
 * A line is positional: name, texture count, that many texture files, the shader, the numbers.
 * The one mistake that positions make easy is a texture count that disagrees with the files
 * written after it, which would silently shift a texture into the shader's place or the shader
 * into the numbers. Shaders are recognisable (user shaders end in .glsl, built-ins start with
 * @), so the parser finds where the shader really is and says which way the count is wrong.
 * Like config.c it stops at the first error, and it never opens the files a line names: the
 * code that reads them reports a missing one with the material's line.
 */
#define _POSIX_C_SOURCE 200809L

#include "material_file.h"
#include "line_parser.h"
#include "text_file.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum {
    MAX_TEXTURES = VKRT_MATERIAL_FILE_MAX_TEXTURES,
    MAX_PARAMS = VKRT_MATERIAL_FILE_MAX_PARAMS,
    MAX_TOKENS = VKRT_TEXT_MAX_TOKENS, /* the longest valid line has 2 + 8 + 1 + 21 = 32 */
    /* Far more than a hand-written file holds, and what keeps a 64 MiB file of one-token lines
     * from costing gigabytes of definitions. */
    MAX_MATERIALS = 65536,
    SHOWN = VKRT_TEXT_SHOWN_BYTES + 4, /* size of a buffer for vkrt_text_shown */
};

_Static_assert(2 + MAX_TEXTURES + 1 + MAX_PARAMS <= MAX_TOKENS,
               "every token of a valid line must be kept");

/* vkrt_material_file_load refuses bigger files; a binary file named by mistake fails fast. */
#define MAX_FILE_BYTES ((size_t)64 << 20)

#define DEFAULT_NAME "material file"
#define LINE_USAGE "write: NAME TEXTURE-COUNT TEXTURE-FILE... SHADER NUMBER..."

typedef struct parser {
    vkrt_line_parser at;  /* file name, line and error of messages */
    const char *base_dir; /* "" for the current folder */
    vkrt_material_file *file;
    uint32_t cap;         /* of file->defs */
    /* Open-addressing set of names seen so far, for duplicates in constant time per line (a
     * pairwise check would be quadratic in a machine-written file): each slot holds a def
     * index + 1, or 0 when empty; slot_count is a power of two kept above twice the count. */
    uint32_t *slots;
    uint32_t slot_count;
} parser;

/* ---------------------------------------------------------------------------------------------
 * Messages
 * ------------------------------------------------------------------------------------------- */

/* Reports "file:line: message" and returns false (line_parser.h). */
#define fail(p, ...) vkrt_line_fail(&(p)->at, __VA_ARGS__)

/* ---------------------------------------------------------------------------------------------
 * Names seen so far
 * ------------------------------------------------------------------------------------------- */

/* FNV-1a: short names, no adversary but the fuzzer, so a simple hash does. */
static uint32_t name_hash(const char *s)
{
    uint32_t h = 2166136261u;
    for (; *s; s++)
        h = (h ^ (unsigned char)*s) * 16777619u;
    return h;
}

/* The slot holding name, or the empty slot where it would go. */
static uint32_t *find_slot(uint32_t *slots, uint32_t slot_count, const vkrt_material_def *defs,
                           const char *name)
{
    uint32_t mask = slot_count - 1;
    for (uint32_t i = name_hash(name) & mask;; i = (i + 1) & mask)
        if (slots[i] == 0 || strcmp(defs[slots[i] - 1].name, name) == 0)
            return &slots[i];
}

/* Makes room for one more name: keeps the table at most half full, so probes stay short. */
static bool reserve_slot(parser *p)
{
    if (2 * (p->file->count + 1) <= p->slot_count)
        return true;
    uint32_t count = p->slot_count ? 2 * p->slot_count : 64;
    uint32_t *slots = calloc(count, sizeof *slots);
    if (!slots)
        return false;
    for (uint32_t i = 0; i < p->slot_count; i++)
        if (p->slots[i])
            *find_slot(slots, count, p->file->defs, p->file->defs[p->slots[i] - 1].name) =
                p->slots[i];
    free(p->slots);
    p->slots = slots;
    p->slot_count = count;
    return true;
}

/* ---------------------------------------------------------------------------------------------
 * One line
 * ------------------------------------------------------------------------------------------- */

/* A user shader ends in .glsl; a built-in starts with @. Texture files are neither. */
static bool looks_like_shader(const char *tok)
{
    return tok[0] == '@' || vkrt_text_ends_with(tok, ".glsl");
}

static bool is_number(const char *tok)
{
    float unused;
    return vkrt_text_float(tok, &unused) == NULL;
}

/* 0..MAX_TEXTURES written as plain digits ("3", "03"); false for anything else. */
static bool parse_texture_count(const char *tok, uint32_t *out)
{
    uint32_t v = 0;
    for (const char *c = tok; *c; c++) {
        if (*c < '0' || *c > '9')
            return false;
        v = 10 * v + (uint32_t)(*c - '0');
        if (v > MAX_TEXTURES)
            return false;
    }
    *out = v;
    return tok[0] != '\0';
}

/* Finds the shader of a line whose count says n textures and checks that the count agrees with
 * the files written; returns the shader's token index through *at. */
static bool locate_shader(parser *p, const vkrt_text_tokens *t, uint32_t n, int *at)
{
    char nb[SHOWN], sb[SHOWN];
    const char *name = vkrt_text_shown(t->tok[0], nb);
    int want = 2 + (int)n; /* where the count puts the shader */
    int kept = t->count < MAX_TOKENS ? t->count : MAX_TOKENS;
    int first = -1; /* where a shader really is */
    for (int i = 2; i < kept && first < 0; i++)
        if (looks_like_shader(t->tok[i]))
            first = i;

    if (first >= 0 && first < want) {
        int files = first - 2;
        const char *shader = vkrt_text_shown(t->tok[first], sb);
        if (files == 0)
            return fail(p, "texture count says %u but no file name follows before the shader "
                           "'%s'",
                        n, shader);
        return fail(p, "texture count says %u but only %d file name%s before the shader '%s'",
                    n, files, files == 1 ? " follows" : "s follow", shader);
    }
    if (t->count < want)
        return fail(p, "texture count says %u but the line ends after %d file name%s, with no "
                       "shader (a .glsl file or a built-in @name)",
                    n, t->count - 2, t->count - 2 == 1 ? "" : "s");
    if (t->count == want) {
        if (n == 0)
            return fail(p, "material '%s' needs a shader after its texture count (a .glsl file "
                           "or a built-in @name)",
                        name);
        return fail(p, "material '%s' needs a shader after its %u texture%s (a .glsl file or a "
                       "built-in @name)",
                    name, n, n == 1 ? "" : "s");
    }

    const char *tok = t->tok[want];
    if (looks_like_shader(tok)) {
        *at = want;
        return true;
    }
    bool files_before_shader = first > want;
    for (int i = want; i < first && files_before_shader; i++)
        files_before_shader = !is_number(t->tok[i]);
    if (files_before_shader) {
        int files = first - 2;
        return fail(p, "texture count says %u but %d file name%s before the shader '%s'", n,
                    files, files == 1 ? " follows" : "s follow",
                    vkrt_text_shown(t->tok[first], sb));
    }
    if (is_number(tok))
        return fail(p, "material '%s' needs a shader before its numbers (a .glsl file or a "
                       "built-in @name), got the number '%s'",
                    name, vkrt_text_shown(tok, sb));
    return fail(p, "'%s' is not a shader: user shaders end in .glsl, built-ins start with @",
                vkrt_text_shown(tok, sb));
}

/* A built-in's name becomes part of GLSL identifiers and a file name under glsl/materials/. */
static bool check_builtin(parser *p, const char *shader)
{
    char sb[SHOWN];
    bool ok = shader[1] != '\0';
    for (const char *c = shader + 1; *c && ok; c++)
        ok = (*c >= 'a' && *c <= 'z') || (*c >= '0' && *c <= '9') || *c == '_';
    if (!ok)
        return fail(p, "built-in shader '%s' is not a valid name: @ followed by a-z, 0-9 and _ "
                       "only",
                    vkrt_text_shown(shader, sb));
    return true;
}

static void free_def(vkrt_material_def *d)
{
    free(d->name);
    for (uint32_t i = 0; d->textures && i < d->texture_count; i++)
        free(d->textures[i]);
    free(d->textures);
    free(d->shader);
    memset(d, 0, sizeof *d);
}

/* Copies the checked line into d, resolving paths. On failure d holds what was copied. */
static bool fill_def(parser *p, const vkrt_text_tokens *t, uint32_t n, int shader_at,
                     vkrt_material_def *d)
{
    d->line = p->at.line;
    d->texture_count = n;
    if (!(d->name = strdup(t->tok[0])))
        return false;
    if (n > 0 && !(d->textures = calloc(n, sizeof *d->textures)))
        return false;
    for (uint32_t i = 0; i < n; i++)
        if (!(d->textures[i] = vkrt_text_join_path(p->base_dir, t->tok[2 + i], false)))
            return false;
    const char *shader = t->tok[shader_at];
    d->shader = shader[0] == '@' ? strdup(shader)
                                 : vkrt_text_join_path(p->base_dir, shader, false);
    return d->shader != NULL;
}

/* One line with at least one token (vkrt_line_fn). */
static bool parse_material(void *ctx, const vkrt_text_tokens *t)
{
    parser *p = ctx;
    char nb[SHOWN], tb[SHOWN];
    const char *name = vkrt_text_shown(t->tok[0], nb);

    uint32_t n = 0;
    if (t->count < 2)
        return fail(p, "expected a texture count (0..%d) after the material name '%s' (%s)",
                    MAX_TEXTURES, name, LINE_USAGE);
    if (!parse_texture_count(t->tok[1], &n))
        return fail(p, "expected a texture count (0..%d) after the material name '%s', got "
                       "'%s' (%s)",
                    MAX_TEXTURES, name, vkrt_text_shown(t->tok[1], tb), LINE_USAGE);

    /* Quotes would suggest that spaces work; say plainly that they do not. Names may hold any
     * character but space and '#' (OBJ's usemtl allows them), numbers hold none. */
    int kept = t->count < MAX_TOKENS ? t->count : MAX_TOKENS;
    for (int i = 2; i < kept; i++)
        if (strchr(t->tok[i], '"'))
            return fail(p, "material '%s': quotes are not supported; paths may not contain "
                           "spaces",
                        name);

    int at = 0;
    if (!locate_shader(p, t, n, &at))
        return false;
    const char *shader = t->tok[at];
    if (shader[0] == '@' && !check_builtin(p, shader))
        return false;

    int params = t->count - at - 1;
    if (params > MAX_PARAMS)
        return fail(p, "material '%s' has %d numbers; at most %d are allowed", name, params,
                    MAX_PARAMS);
    vkrt_material_def d;
    memset(&d, 0, sizeof d);
    d.param_count = (uint32_t)params;
    for (int i = 0; i < params; i++) {
        const char *tok = t->tok[at + 1 + i];
        const char *why = vkrt_text_float(tok, &d.params[i]);
        if (why)
            return fail(p, "material '%s': param(%d) '%s' %s", name, i,
                        vkrt_text_shown(tok, tb), why);
    }

    vkrt_material_file *file = p->file;
    if (file->count > 0) {
        uint32_t *slot = find_slot(p->slots, p->slot_count, file->defs, t->tok[0]);
        if (*slot)
            return fail(p, "material '%s' is defined twice (first on line %d)", name,
                        file->defs[*slot - 1].line);
    }
    if (file->count >= MAX_MATERIALS)
        return fail(p, "too many materials (the limit is %d)", MAX_MATERIALS);
    if (!reserve_slot(p))
        return fail(p, "out of memory");
    if (file->count == p->cap) {
        uint32_t cap = p->cap ? 2 * p->cap : 16;
        vkrt_material_def *grown = realloc(file->defs, cap * sizeof *grown);
        if (!grown)
            return fail(p, "out of memory");
        file->defs = grown;
        p->cap = cap;
    }
    if (!fill_def(p, t, n, at, &d)) {
        free_def(&d);
        return fail(p, "out of memory");
    }
    file->defs[file->count++] = d;
    *find_slot(p->slots, p->slot_count, file->defs, d.name) = file->count;
    return true;
}

/* ---------------------------------------------------------------------------------------------
 * Public API
 * ------------------------------------------------------------------------------------------- */

bool vkrt_material_file_parse(const char *text, size_t size, const char *name,
                              const char *base_dir, vkrt_material_file *file, vkrt_error *err)
{
    const char *shown_name = name ? name : DEFAULT_NAME;
    if (!file)
        return vkrt_error_set(err, "%s: no material file to fill", shown_name);
    memset(file, 0, sizeof *file);
    if (!text && size > 0)
        return vkrt_error_set(err, "%s: no text to parse", shown_name);

    vkrt_material_file f;
    memset(&f, 0, sizeof f);
    if (!(f.path = strdup(shown_name)))
        return vkrt_error_set(err, "%s: out of memory", shown_name);

    parser p;
    memset(&p, 0, sizeof p);
    p.at.name = shown_name;
    p.at.err = err;
    p.base_dir = base_dir ? base_dir : "";
    p.file = &f;
    bool ok = vkrt_line_parse_all(&p.at, text ? text : "", text ? size : 0, "material file",
                                  parse_material, &p);
    free(p.slots);
    if (!ok) {
        vkrt_material_file_free(&f);
        return false;
    }
    *file = f;
    return true;
}

bool vkrt_material_file_load(const char *path, vkrt_material_file *file, vkrt_error *err)
{
    if (file)
        memset(file, 0, sizeof *file);
    if (!path)
        return vkrt_error_set(err, DEFAULT_NAME ": no path given");
    char *text, *dir;
    size_t size;
    if (!vkrt_line_read_file(path, MAX_FILE_BYTES, "material file", &text, &size, &dir, err))
        return false;
    bool ok = vkrt_material_file_parse(text, size, path, dir, file, err);
    free(dir);
    free(text);
    return ok;
}

const vkrt_material_def *vkrt_material_file_find(const vkrt_material_file *file,
                                                 const char *name)
{
    if (!file || !name)
        return NULL;
    for (uint32_t i = 0; i < file->count; i++)
        if (strcmp(file->defs[i].name, name) == 0)
            return &file->defs[i];
    return NULL;
}

void vkrt_material_file_free(vkrt_material_file *file)
{
    if (!file)
        return;
    for (uint32_t i = 0; i < file->count; i++)
        free_def(&file->defs[i]);
    free(file->defs);
    free(file->path);
    memset(file, 0, sizeof *file);
}
