/*
 * config.c: the scene.cfg parser (see config.h, and docs/scene-format.md for the format).
 *
 * A scene.cfg is written by hand, so this file's job is less the parsing itself than refusing
 * every mistake with a message that points at the line and says what is wrong. It stops at the
 * first error: one precise message beats a cascade of follow-on ones. Everything a later stage
 * would otherwise have to check (finite numbers, unit directions, a usable camera basis, a valid
 * frame pattern) is checked here, so the GPU code can trust the values it gets.
 */
#define _POSIX_C_SOURCE 200809L

#include "config.h"
#include "affine.h"
#include "coordinate_limit.h"
#include "line_parser.h"
#include "text_file.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Limits. A scene.cfg is short; anything far past these is a mistake or not a scene.cfg. */
enum {
    MAX_TOKENS = VKRT_TEXT_MAX_TOKENS, /* the longest valid line (camera) has 21 */
    MAX_SIZE = 16384,
    MAX_SAMPLES = 65536,
    MAX_DEPTH = 64,
    MAX_LIGHTS = 65536,
    MAX_CAMERAS = 1000000,
    SHOWN_TOKEN_BYTES = VKRT_TEXT_SHOWN_BYTES,
};

/* vkrt_config_load refuses bigger files; a binary file named by mistake fails fast. */
#define MAX_FILE_BYTES ((size_t)64 << 20)

/* Vectors shorter than this count as zero: the renderer normalises in float, and squaring a
 * shorter length would underflow there. */
#define MIN_LENGTH 1e-18

/* Up closer than this (sine of the angle) to the view direction gives an unstable camera
 * basis, so it is refused as parallel. */
#define MIN_UP_SINE 1e-4

typedef vkrt_text_tokens tokens;

typedef struct parser {
    vkrt_line_parser at;  /* file name, line and error of messages */
    const char *base_dir; /* "" for the current folder */
    vkrt_config *cfg;
    int first_line[24];   /* per single-valued keyword: where it was given, 0 if not yet */
    uint32_t light_cap, camera_cap, geometry_cap;
} parser;

/* ---------------------------------------------------------------------------------------------
 * Messages
 * ------------------------------------------------------------------------------------------- */

/* Reports "file:line: message" and returns false (line_parser.h). */
#define fail(p, ...) vkrt_line_fail(&(p)->at, __VA_ARGS__)

/* A token as a message shows it, cut short if absurdly long (text_file.h). */
static const char *shown(const char *tok, char buf[SHOWN_TOKEN_BYTES + 4])
{
    return vkrt_text_shown(tok, buf);
}

/* ---------------------------------------------------------------------------------------------
 * Numbers
 * ------------------------------------------------------------------------------------------- */

/* what names the value in messages, e.g. "light spot direction y". */
static bool parse_float(parser *p, const char *tok, const char *what, float *out)
{
    char buf[SHOWN_TOKEN_BYTES + 4];
    const char *why = vkrt_text_float(tok, out);
    if (why)
        return fail(p, "%s '%s' %s", what, shown(tok, buf), why);
    return true;
}

static bool is_whole_number_text(const char *tok)
{
    size_t i = (tok[0] == '+' || tok[0] == '-') ? 1 : 0;
    if (tok[i] == '\0')
        return false;
    for (; tok[i] != '\0'; i++)
        if (tok[i] < '0' || tok[i] > '9')
            return false;
    return true;
}

static bool parse_uint(parser *p, const char *tok, const char *what, long long min, long long max,
                       uint32_t *out)
{
    char buf[SHOWN_TOKEN_BYTES + 4];
    if (!is_whole_number_text(tok)) {
        char *end;
        (void)strtod(tok, &end);
        if (end != tok && *end == '\0')
            return fail(p, "%s must be a whole number, got '%s'", what, shown(tok, buf));
        return fail(p, "%s '%s' is not a number", what, shown(tok, buf));
    }
    errno = 0;
    long long v = strtoll(tok, NULL, 10);
    if (errno == ERANGE || v < min || v > max)
        return fail(p, "%s must be between %lld and %lld, got %s", what, min, max,
                    shown(tok, buf));
    *out = (uint32_t)v;
    return true;
}

/* Parses 3 floats starting at t->tok[first]; what is e.g. "light spot position". */
static bool parse_vec3(parser *p, const tokens *t, int first, const char *what, float out[3])
{
    static const char *const axis[3] = {"x", "y", "z"};
    for (int i = 0; i < 3; i++) {
        char part[96];
        snprintf(part, sizeof part, "%s %s", what, axis[i]);
        if (!parse_float(p, t->tok[first + i], part, &out[i]))
            return false;
    }
    return true;
}

/* Parses a point as parse_vec3 does, and refuses a coordinate outside the range the kernels'
 * float arithmetic renders (coordinate_limit.h). */
static bool parse_point(parser *p, const tokens *t, int first, const char *what, float out[3])
{
    static const char *const axis[3] = {"x", "y", "z"};
    char buf[SHOWN_TOKEN_BYTES + 4];
    if (!parse_vec3(p, t, first, what, out))
        return false;
    for (int i = 0; i < 3; i++)
        if (fabs(out[i]) > VKRT_COORDINATE_LIMIT)
            return fail(p, "%s %s %s is outside " VKRT_COORDINATE_RANGE_TEXT, what, axis[i],
                        shown(t->tok[first + i], buf));
    return true;
}

static bool parse_colour(parser *p, const tokens *t, int first, const char *what, float out[3])
{
    static const char *const channel[3] = {"r", "g", "b"};
    char buf[SHOWN_TOKEN_BYTES + 4];
    for (int i = 0; i < 3; i++) {
        char part[96];
        snprintf(part, sizeof part, "%s %s", what, channel[i]);
        if (!parse_float(p, t->tok[first + i], part, &out[i]))
            return false;
        /* A negative radiance would subtract light, which no physical source does. */
        if (out[i] < 0.0f)
            return fail(p, "%s must not be negative, got %s", part,
                        shown(t->tok[first + i], buf));
    }
    return true;
}

static double length3(const float v[3])
{
    return sqrt((double)v[0] * v[0] + (double)v[1] * v[1] + (double)v[2] * v[2]);
}

/* Normalises in double so that even tiny or huge (finite) vectors come out exactly unit. */
static bool normalise(parser *p, float v[3], const char *what)
{
    double len = length3(v);
    if (!(len > MIN_LENGTH))
        return fail(p, "%s has zero length", what);
    for (int i = 0; i < 3; i++)
        v[i] = (float)(v[i] / len);
    return true;
}

/* Checks that the line has exactly `want` arguments after its first `skip` tokens. */
static bool want_numbers(parser *p, const tokens *t, int skip, int want, const char *what)
{
    int got = t->count - skip;
    if (got == want)
        return true;
    if (got < want)
        return fail(p, "%s needs %d number%s, got %d", what, want, want == 1 ? "" : "s", got);
    char buf[SHOWN_TOKEN_BYTES + 4];
    const char *extra = skip + want < MAX_TOKENS ? t->tok[skip + want] : "...";
    return fail(p, "%s needs %d number%s, got %d: unexpected '%s'", what, want,
                want == 1 ? "" : "s", got, shown(extra, buf));
}

/* ---------------------------------------------------------------------------------------------
 * Paths
 * ------------------------------------------------------------------------------------------- */

/* Checks that the line holds exactly one path after its keyword. */
static bool check_path(parser *p, const tokens *t, const char *what)
{
    char buf[SHOWN_TOKEN_BYTES + 4];
    if (t->count < 2)
        return fail(p, "%s needs a path", what);
    /* Quotes would suggest that spaces work; say plainly that they do not. A single quote
     * inside a name ("o'brien.obj") is an ordinary character. */
    if (strchr(t->tok[1], '"') || t->tok[1][0] == '\'')
        return fail(p, "%s: quotes are not supported; paths may not contain spaces", what);
    if (t->count > 2)
        return fail(p, "%s needs 1 path, got %d parts: unexpected '%s' (paths may not contain "
                       "spaces)",
                    what, t->count - 1, shown(t->tok[2], buf));
    return true;
}

static bool parse_path(parser *p, const tokens *t, const char *what, bool escape_percent,
                       char **out)
{
    if (!check_path(p, t, what))
        return false;
    *out = vkrt_text_join_path(p->base_dir, t->tok[1], escape_percent);
    if (!*out)
        return fail(p, "out of memory");
    return true;
}

/* The same rules as vkrt_frame_path (output/image_write.c), checked here so that a bad pattern
 * is reported with its line before any rendering: only "%%" and one "%d", "%Nd" or "%0Nd" with
 * N of one or two digits. Returns NULL if valid, else the offending conversion. */
static const char *frame_pattern_problem(const char *pattern, bool *two_numbers)
{
    bool have_number = false;
    *two_numbers = false;
    for (const char *c = strchr(pattern, '%'); c; c = strchr(c, '%')) {
        if (c[1] == '%') {
            c += 2;
            continue;
        }
        size_t i = 1;
        bool zero = c[i] == '0';
        if (zero)
            i++;
        int digits = 0;
        while (c[i] >= '0' && c[i] <= '9' && digits < 2) {
            i++;
            digits++;
        }
        if (c[i] != 'd' || (zero && digits == 0))
            return c;
        if (have_number) {
            *two_numbers = true;
            return c;
        }
        have_number = true;
        c += i + 1;
    }
    return NULL;
}

/* ---------------------------------------------------------------------------------------------
 * Keywords
 * ------------------------------------------------------------------------------------------- */

/* Room for one more item in a growing array of count items of size bytes, its capacity *cap
 * doubled (first when it is 0) when full; false, with the message said, when memory runs out. */
static bool make_room(parser *p, void **array, uint32_t count, uint32_t *cap, uint32_t first,
                      size_t size)
{
    if (count < *cap)
        return true;
    uint32_t grown_cap = *cap ? 2 * *cap : first;
    void *grown = realloc(*array, grown_cap * size);
    if (!grown)
        return fail(p, "out of memory");
    *array = grown;
    *cap = grown_cap;
    return true;
}

/* The placement words after a geometry line's path, applied in the order written:
 * translate X Y Z | rotate x|y|z DEG | rotate AX AY AZ DEG | scale S | scale SX SY SZ. */
static bool parse_placement(parser *p, const tokens *t, vkrt_config_geometry *g)
{
    static const char *const usage =
        "geometry FILE [translate X Y Z] [rotate x|y|z DEGREES] [rotate AX AY AZ DEGREES] "
        "[scale S] [scale SX SY SZ]";
    char buf[SHOWN_TOKEN_BYTES + 4];
    double m[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    /* Only MAX_TOKENS words of a line are kept; a longer placement is split over lines by
     * nobody, so it is refused rather than read in part. */
    if (t->count > MAX_TOKENS)
        return fail(p, "geometry: %d words on one line, at most %d (write: %s)", t->count,
                    (int)MAX_TOKENS, usage);
    for (int at = 2; at < t->count;) {
        const char *word = t->tok[at];
        int left = t->count - at - 1; /* tokens after the word */
        double op[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
        float v[4];
        if (strcmp(word, "translate") == 0) {
            if (left < 3 || !parse_vec3(p, t, at + 1, "geometry translate", v))
                return left < 3 ? fail(p, "geometry translate needs 3 numbers (write: %s)", usage)
                                : false;
            op[3] = v[0], op[7] = v[1], op[11] = v[2];
            at += 4;
        } else if (strcmp(word, "rotate") == 0) {
            double axis[3] = {0, 0, 0};
            const char *name = left >= 1 ? t->tok[at + 1] : "";
            int named = !strcmp(name, "x") ? 0 : !strcmp(name, "y") ? 1 : !strcmp(name, "z") ? 2 : -1;
            if (named >= 0 && left >= 2) {
                axis[named] = 1.0;
                if (!parse_float(p, t->tok[at + 2], "geometry rotate angle", &v[3]))
                    return false;
                at += 3;
            } else if (named < 0 && left >= 4) {
                if (!parse_vec3(p, t, at + 1, "geometry rotate axis", v) ||
                    !normalise(p, v, "geometry rotate axis") ||
                    !parse_float(p, t->tok[at + 4], "geometry rotate angle", &v[3]))
                    return false;
                axis[0] = v[0], axis[1] = v[1], axis[2] = v[2];
                at += 5;
            } else {
                return fail(p, "geometry rotate needs an axis and an angle in degrees (write: %s)",
                            usage);
            }
            vkrt_affine_rotation(axis, v[3], op);
        } else if (strcmp(word, "scale") == 0) {
            /* One number scales uniformly; three scale each axis. */
            bool three = left >= 3 && vkrt_text_float(t->tok[at + 2], &v[1]) == NULL;
            if (left < 1)
                return fail(p, "geometry scale needs 1 or 3 numbers (write: %s)", usage);
            if (three ? !parse_vec3(p, t, at + 1, "geometry scale", v)
                      : !parse_float(p, t->tok[at + 1], "geometry scale", &v[0]))
                return false;
            if (!three)
                v[1] = v[2] = v[0];
            /* A zero scale flattens the file into a plane whose normals are undefined. */
            for (int i = 0; i < 3; i++)
                if (v[i] == 0.0f)
                    return fail(p, "geometry scale must not be 0");
            op[0] = v[0], op[5] = v[1], op[10] = v[2];
            at += three ? 4 : 2;
        } else {
            return fail(p, "geometry: unexpected '%s' (write: %s; paths may not contain spaces)",
                        shown(word, buf), usage);
        }
        vkrt_affine_then(m, op);
        g->placed = true;
    }
    for (int i = 0; i < 12; i++) {
        g->transform[i] = (float)m[i];
        if (i % 4 == 3 && fabs(m[i]) > VKRT_COORDINATE_LIMIT)
            return fail(p, "geometry translate %g is outside [-%g, %g], the range vkrt's float "
                           "arithmetic renders",
                        m[i], VKRT_COORDINATE_LIMIT, VKRT_COORDINATE_LIMIT);
    }
    return true;
}

static bool kw_geometry(parser *p, const tokens *t)
{
    vkrt_config *cfg = p->cfg;
    if (t->count < 2)
        return fail(p, "geometry needs a path");
    if (strchr(t->tok[1], '"') || t->tok[1][0] == '\'')
        return fail(p, "geometry: quotes are not supported; paths may not contain spaces");
    if (!make_room(p, (void **)&cfg->geometries, cfg->geometry_count, &p->geometry_cap, 4,
                   sizeof *cfg->geometries))
        return false;
    vkrt_config_geometry *g = &cfg->geometries[cfg->geometry_count];
    memset(g, 0, sizeof *g);
    g->line = p->at.line;
    if (!parse_placement(p, t, g))
        return false;
    if (!(g->path = vkrt_text_join_path(p->base_dir, t->tok[1], false)))
        return fail(p, "out of memory");
    cfg->geometry_count++;
    return true;
}

static bool kw_materials(parser *p, const tokens *t)
{
    return parse_path(p, t, "materials", false, &p->cfg->materials);
}

static bool kw_output(parser *p, const tokens *t)
{
    char buf[SHOWN_TOKEN_BYTES + 4];
    if (!check_path(p, t, "output"))
        return false;
    const char *path = t->tok[1];
    if (!vkrt_text_ends_with(path, ".png") && !vkrt_text_ends_with(path, ".exr"))
        return fail(p, "output '%s' must end in .png or .exr", shown(path, buf));
    bool two;
    const char *bad = frame_pattern_problem(path, &two);
    if (bad && two)
        return fail(p, "output '%s' has more than one frame number", shown(path, buf));
    if (bad) {
        /* Quote the conversion alone: '%', any digits, then the letter that ended it. */
        int len = 1 + (int)strspn(bad + 1, "0123456789");
        if (bad[len] != '\0' && len < 8)
            len++;
        return fail(p, "output '%s': unsupported conversion '%.*s' (use %%d, %%04d, or %%%% "
                       "for a literal %%)",
                    shown(path, buf), len > 8 ? 8 : len, bad);
    }
    /* A frame pattern (vkrt_frame_path expands it): a '%' in the folder is written "%%". */
    return parse_path(p, t, "output", true, &p->cfg->output);
}

static bool kw_resolution(parser *p, const tokens *t)
{
    if (!want_numbers(p, t, 1, 2, "resolution"))
        return false;
    return parse_uint(p, t->tok[1], "resolution width", 1, MAX_SIZE, &p->cfg->width) &&
           parse_uint(p, t->tok[2], "resolution height", 1, MAX_SIZE, &p->cfg->height);
}

static bool kw_samples(parser *p, const tokens *t)
{
    return want_numbers(p, t, 1, 1, "samples") &&
           parse_uint(p, t->tok[1], "samples", 1, MAX_SAMPLES, &p->cfg->samples);
}

static bool kw_shutter(parser *p, const tokens *t)
{
    char buf[SHOWN_TOKEN_BYTES + 4];
    if (!want_numbers(p, t, 1, 1, "shutter") ||
        !parse_float(p, t->tok[1], "shutter", &p->cfg->shutter))
        return false;
    if (!(p->cfg->shutter >= 0.0f && p->cfg->shutter <= 1.0f))
        return fail(p, "shutter is the share of a frame's interval the shutter is open: from 0 to "
                       "1, got %s",
                    shown(t->tok[1], buf));
    return true;
}

static bool kw_max_depth(parser *p, const tokens *t)
{
    return want_numbers(p, t, 1, 1, "max-depth") &&
           parse_uint(p, t->tok[1], "max-depth", 0, MAX_DEPTH, &p->cfg->max_depth);
}

static bool kw_accel(parser *p, const tokens *t)
{
    char buf[SHOWN_TOKEN_BYTES + 4], names[VKRT_NAMES_BYTES];
    if (t->count != 2)
        return fail(p, "accel needs one name (%s), got %d", vkrt_accel_names(names), t->count - 1);
    if (!vkrt_accel_parse(t->tok[1], &p->cfg->accel))
        return fail(p, "unknown accel '%s' (expected %s)", shown(t->tok[1], buf),
                    vkrt_accel_names(names));
    return true;
}

static bool kw_integrator(parser *p, const tokens *t)
{
    char buf[SHOWN_TOKEN_BYTES + 4], names[VKRT_NAMES_BYTES];
    if (t->count != 2)
        return fail(p, "integrator needs one name (%s), got %d", vkrt_integrator_names(names),
                    t->count - 1);
    if (!vkrt_integrator_parse(t->tok[1], &p->cfg->integrator))
        return fail(p, "unknown integrator '%s' (expected %s)", shown(t->tok[1], buf),
                    vkrt_integrator_names(names));
    return true;
}

static bool kw_bvh_splits(parser *p, const tokens *t)
{
    char buf[SHOWN_TOKEN_BYTES + 4], names[VKRT_NAMES_BYTES];
    if (t->count != 2)
        return fail(p, "bvh-splits needs one name (%s), got %d", vkrt_bvh_splits_names(names),
                    t->count - 1);
    if (!vkrt_bvh_splits_parse(t->tok[1], &p->cfg->bvh_splits))
        return fail(p, "unknown bvh-splits '%s' (expected %s)", shown(t->tok[1], buf),
                    vkrt_bvh_splits_names(names));
    return true;
}

static bool kw_textures(parser *p, const tokens *t)
{
    char buf[SHOWN_TOKEN_BYTES + 4];
    if (t->count != 2)
        return fail(p, "textures needs one name (cone, bilinear or nearest), got %d",
                    t->count - 1);
    if (!vkrt_texture_filter_parse(t->tok[1], &p->cfg->texture_filter))
        return fail(p, "unknown textures '%s' (expected cone, bilinear or nearest)",
                    shown(t->tok[1], buf));
    return true;
}

static bool kw_tonemap(parser *p, const tokens *t)
{
    char buf[SHOWN_TOKEN_BYTES + 4];
    if (t->count != 2)
        return fail(p, "tonemap needs one name (none, aces or agx), got %d", t->count - 1);
    if (!vkrt_tonemap_parse(t->tok[1], &p->cfg->tonemap))
        return fail(p, "unknown tonemap '%s' (expected none, aces or agx)", shown(t->tok[1], buf));
    return true;
}

/* denoise on|off: Open Image Denoise on every frame (src/output/denoise.h), as --denoise. */
static bool kw_denoise(parser *p, const tokens *t)
{
    char buf[SHOWN_TOKEN_BYTES + 4];
    if (t->count != 2)
        return fail(p, "denoise needs on or off, got %d words", t->count - 1);
    bool on = strcmp(t->tok[1], "on") == 0;
    if (!on && strcmp(t->tok[1], "off") != 0)
        return fail(p, "denoise: '%s' is not on or off", shown(t->tok[1], buf));
    p->cfg->denoise = on;
    return true;
}

static bool kw_environment(parser *p, const tokens *t)
{
    return want_numbers(p, t, 1, 3, "environment") &&
           parse_colour(p, t, 1, "environment", p->cfg->environment);
}

/* environment-map FILE [scale S] [rotate DEG], the options in any order, each at most once. The
 * file itself is read later (src/scene/envmap.h), like the OBJ, and its errors name this line. */
static bool kw_environment_map(parser *p, const tokens *t)
{
    static const char *const usage = "environment-map FILE [scale S] [rotate DEGREES]";
    char buf[SHOWN_TOKEN_BYTES + 4];
    if (t->count < 2)
        return fail(p, "environment-map needs a path (write: %s)", usage);
    if (strchr(t->tok[1], '"') || t->tok[1][0] == '\'')
        return fail(p, "environment-map: quotes are not supported; paths may not contain spaces");

    vkrt_config *cfg = p->cfg;
    bool have_scale = false, have_rotate = false;
    for (int at = 2; at < t->count; at += 2) {
        if (at >= MAX_TOKENS)
            return fail(p, "environment-map: too many parts (write: %s)", usage);
        const char *name = t->tok[at];
        bool is_scale = strcmp(name, "scale") == 0;
        if (!is_scale && strcmp(name, "rotate") != 0)
            return fail(p, "environment-map: unexpected '%s' (write: %s; paths may not contain "
                           "spaces)",
                        shown(name, buf), usage);
        if (is_scale ? have_scale : have_rotate)
            return fail(p, "environment-map %s given twice", name);
        if (at + 1 >= t->count)
            return fail(p, "environment-map %s needs a number", name);
        if (is_scale) {
            have_scale = true;
            if (!parse_float(p, t->tok[at + 1], "environment-map scale", &cfg->environment_scale))
                return false;
            /* A negative scale would make the sky subtract light. */
            if (cfg->environment_scale < 0.0f)
                return fail(p, "environment-map scale must not be negative, got %s",
                            shown(t->tok[at + 1], buf));
        } else {
            have_rotate = true;
            if (!parse_float(p, t->tok[at + 1], "environment-map rotate",
                             &cfg->environment_rotate))
                return false;
        }
    }
    cfg->environment_map_line = p->at.line;
    cfg->environment_map = vkrt_text_join_path(p->base_dir, t->tok[1], false);
    if (!cfg->environment_map)
        return fail(p, "out of memory");
    return true;
}

static bool kw_light(parser *p, const tokens *t)
{
    char buf[SHOWN_TOKEN_BYTES + 4];
    static const struct {
        const char *name;
        vkrt_light_kind kind;
        int numbers;
    } kinds[] = {
        {"ambient", VKRT_LIGHT_AMBIENT, 3},
        {"directional", VKRT_LIGHT_DIRECTIONAL, 6},
        {"point", VKRT_LIGHT_POINT, 6},
        {"spot", VKRT_LIGHT_SPOT, 10},
    };
    if (t->count < 2)
        return fail(p, "light needs a kind: ambient, directional, point or spot");
    int k = -1;
    for (int i = 0; i < (int)(sizeof kinds / sizeof kinds[0]); i++)
        if (strcmp(t->tok[1], kinds[i].name) == 0)
            k = i;
    if (k < 0)
        return fail(p, "unknown light kind '%s' (expected ambient, directional, point or spot)",
                    shown(t->tok[1], buf));

    char what[32];
    snprintf(what, sizeof what, "light %s", kinds[k].name);
    if (!want_numbers(p, t, 2, kinds[k].numbers, what))
        return false;

    vkrt_config_light l;
    memset(&l, 0, sizeof l);
    l.kind = kinds[k].kind;
    l.line = p->at.line;
    switch (l.kind) {
    case VKRT_LIGHT_AMBIENT:
        if (!parse_colour(p, t, 2, "light ambient colour", l.colour))
            return false;
        break;
    case VKRT_LIGHT_DIRECTIONAL:
        if (!parse_vec3(p, t, 2, "light directional direction", l.direction) ||
            !parse_colour(p, t, 5, "light directional colour", l.colour) ||
            !normalise(p, l.direction, "light directional direction"))
            return false;
        break;
    case VKRT_LIGHT_POINT:
        if (!parse_point(p, t, 2, "light point position", l.position) ||
            !parse_colour(p, t, 5, "light point colour", l.colour))
            return false;
        break;
    case VKRT_LIGHT_SPOT:
        if (!parse_point(p, t, 2, "light spot position", l.position) ||
            !parse_vec3(p, t, 5, "light spot direction", l.direction) ||
            !parse_float(p, t->tok[8], "light spot half angle", &l.half_angle_deg) ||
            !parse_colour(p, t, 9, "light spot colour", l.colour))
            return false;
        /* Past 90 degrees the cone is no longer a cone around the axis. */
        if (!(l.half_angle_deg > 0.0f && l.half_angle_deg <= 90.0f))
            return fail(p, "light spot half angle must be in (0, 90] degrees, got %s",
                        shown(t->tok[8], buf));
        if (!normalise(p, l.direction, "light spot direction"))
            return false;
        break;
    }

    vkrt_config *cfg = p->cfg;
    if (cfg->light_count >= MAX_LIGHTS)
        return fail(p, "too many lights (the limit is %d)", MAX_LIGHTS);
    if (!make_room(p, (void **)&cfg->lights, cfg->light_count, &p->light_cap, 8,
                   sizeof *cfg->lights))
        return false;
    cfg->lights[cfg->light_count++] = l;
    return true;
}

/* The fourth part of a camera line names its projection: `fov F` (perspective) or `ortho W`. */
static bool is_camera_part(const char *tok)
{
    static const char *const names[] = {"eye", "look", "up", "fov", "ortho"};
    for (size_t j = 0; j < sizeof names / sizeof *names; j++)
        if (strcmp(tok, names[j]) == 0)
            return true;
    return false;
}

static bool kw_camera(parser *p, const tokens *t)
{
    char buf[SHOWN_TOKEN_BYTES + 4];
    static const char *const usage = "camera eye X Y Z look X Y Z up X Y Z fov F|ortho W "
                                     "[aperture A] [focus D] [name NAME]";
    static const struct {
        const char *name;
        int numbers;
    } parts[] = {{"eye", 3}, {"look", 3}, {"up", 3}, {"fov", 1}};

    vkrt_config_camera c;
    memset(&c, 0, sizeof c);
    c.line = p->at.line;
    float *dest[4] = {c.eye, c.look, c.up, &c.fov_deg};

    int at = 1;
    bool ortho = false;
    for (int i = 0; i < 4; i++) {
        const char *name = parts[i].name;
        if (at >= t->count)
            return fail(p, "camera is missing '%s' (write: %s)", i == 3 ? "fov' or 'ortho" : name,
                        usage);
        /* The projection: `ortho W` in place of `fov F` makes an orthographic camera. */
        ortho = i == 3 && at < MAX_TOKENS && strcmp(t->tok[at], "ortho") == 0;
        if (ortho) {
            name = "ortho";
            dest[3] = &c.ortho_width;
        }
        if (at >= MAX_TOKENS || strcmp(t->tok[at], name) != 0)
            return fail(p, "camera: expected '%s' but found '%s' (write: %s)",
                        i == 3 ? "fov' or 'ortho" : name,
                        at < MAX_TOKENS ? shown(t->tok[at], buf) : "...", usage);
        at++;
        int n = parts[i].numbers;
        /* Count the numbers up to the next word, so "eye 1 2 look" says "got 2". */
        int got = 0;
        while (got < n && at + got < t->count && at + got < MAX_TOKENS &&
               !is_camera_part(t->tok[at + got]))
            got++;
        if (got < n)
            return fail(p, "camera %s needs %d number%s, got %d", name, n, n == 1 ? "" : "s",
                        got);
        char what[32];
        snprintf(what, sizeof what, "camera %s", name);
        if (n == 3) {
            bool point = i < 2; /* eye and look are points; up is a direction */
            if (!(point ? parse_point : parse_vec3)(p, t, at, what, dest[i]))
                return false;
        } else if (!parse_float(p, t->tok[at], what, dest[i])) {
            return false;
        }
        at += n;
    }
    const char *projection_token = t->tok[at - 1];
    /* Then, optional and in any order: the thin lens (`aperture A`, its radius, and `focus D`)
     * and the camera's name (`name NAME`, what --camera NAME picks). */
    bool focus_given = false;
    while (at < t->count && at < MAX_TOKENS) {
        const char *word = t->tok[at];
        bool is_aperture = strcmp(word, "aperture") == 0, is_focus = strcmp(word, "focus") == 0;
        bool is_name = strcmp(word, "name") == 0;
        if (!is_aperture && !is_focus && !is_name)
            return fail(p, "camera: unexpected '%s' after %s (write: %s)", shown(word, buf),
                        ortho ? "ortho" : "fov", usage);
        if (at + 1 >= t->count || at + 1 >= MAX_TOKENS)
            return fail(p, "camera %s needs a %s", word, is_name ? "word" : "number");
        if (is_name) {
            const char *name = t->tok[at + 1];
            if (strlen(name) >= sizeof c.name)
                return fail(p, "camera name '%s' is longer than %zu bytes", shown(name, buf),
                            sizeof c.name - 1);
            memcpy(c.name, name, strlen(name) + 1);
            at += 2;
            continue;
        }
        float *value = is_aperture ? &c.aperture : &c.focus;
        if (!parse_float(p, t->tok[at + 1], is_aperture ? "camera aperture" : "camera focus",
                         value))
            return false;
        if (is_aperture && !(c.aperture >= 0.0f))
            return fail(p, "camera aperture (the lens radius) must not be negative, got %s",
                        shown(t->tok[at + 1], buf));
        if (is_focus && !(c.focus > 0.0f))
            return fail(p, "camera focus (the distance in focus) must be positive, got %s",
                        shown(t->tok[at + 1], buf));
        focus_given = focus_given || is_focus;
        at += 2;
    }
    if (at < t->count)
        return fail(p, "camera: unexpected '%s' after %s",
                    at < MAX_TOKENS ? shown(t->tok[at], buf) : "...", ortho ? "ortho" : "fov");
    if (focus_given && c.aperture == 0.0f)
        return fail(p, "camera focus needs an aperture (a pinhole is in focus everywhere)");

    if (ortho && !(c.ortho_width > 0.0f && c.ortho_width <= VKRT_COORDINATE_LIMIT))
        return fail(p, "camera ortho (the view's width in scene units) must be positive and at "
                       "most %g, got %s",
                    VKRT_COORDINATE_LIMIT, shown(projection_token, buf));
    if (!ortho && !(c.fov_deg > 0.0f && c.fov_deg < 180.0f))
        return fail(p, "camera fov must be between 0 and 180 degrees (exclusive), got %s",
                    shown(projection_token, buf));
    /* In double: the difference of two finite floats may not be a finite float. */
    double view[3] = {(double)c.look[0] - c.eye[0], (double)c.look[1] - c.eye[1],
                      (double)c.look[2] - c.eye[2]};
    double view_len = sqrt(view[0] * view[0] + view[1] * view[1] + view[2] * view[2]);
    double up_len = length3(c.up);
    if (!(view_len > MIN_LENGTH))
        return fail(p, "camera eye and look are the same point; the camera has no direction");
    if (!(up_len > MIN_LENGTH))
        return fail(p, "camera up has zero length");
    double cx = view[1] * c.up[2] - view[2] * c.up[1];
    double cy = view[2] * c.up[0] - view[0] * c.up[2];
    double cz = view[0] * c.up[1] - view[1] * c.up[0];
    double sine = sqrt(cx * cx + cy * cy + cz * cz) / (view_len * up_len);
    if (!(sine > MIN_UP_SINE))
        return fail(p, "camera up is parallel to the view direction (look - eye)");

    vkrt_config *cfg = p->cfg;
    if (cfg->camera_count >= MAX_CAMERAS)
        return fail(p, "too many cameras (the limit is %d frames)", MAX_CAMERAS);
    if (!make_room(p, (void **)&cfg->cameras, cfg->camera_count, &p->camera_cap, 4,
                   sizeof *cfg->cameras))
        return false;
    cfg->cameras[cfg->camera_count++] = c;
    return true;
}

typedef struct keyword {
    const char *word;
    bool single; /* may be given once only */
    bool (*parse)(parser *p, const tokens *t);
} keyword;

static const keyword keywords[] = {
    {"geometry", false, kw_geometry},
    {"materials", true, kw_materials},
    {"resolution", true, kw_resolution},
    {"samples", true, kw_samples},
    {"max-depth", true, kw_max_depth},
    {"shutter", true, kw_shutter},
    {"accel", true, kw_accel},
    {"integrator", true, kw_integrator},
    {"bvh-splits", true, kw_bvh_splits},
    {"textures", true, kw_textures},
    {"tonemap", true, kw_tonemap},
    {"denoise", true, kw_denoise},
    {"output", true, kw_output},
    {"environment", true, kw_environment},
    {"environment-map", true, kw_environment_map},
    {"light", false, kw_light},
    {"camera", false, kw_camera},
};

_Static_assert(sizeof keywords / sizeof keywords[0] <= sizeof((parser *)0)->first_line /
                                                          sizeof(int),
               "parser.first_line needs a slot per keyword");

/* ---------------------------------------------------------------------------------------------
 * Lines
 * ------------------------------------------------------------------------------------------- */

/* One line with at least one token (vkrt_line_fn). */
static bool parse_line(void *ctx, const tokens *t)
{
    parser *p = ctx;
    char buf[SHOWN_TOKEN_BYTES + 4];
    int n = (int)(sizeof keywords / sizeof keywords[0]);
    for (int i = 0; i < n; i++) {
        if (strcmp(t->tok[0], keywords[i].word) != 0)
            continue;
        if (keywords[i].single) {
            if (p->first_line[i])
                return fail(p, "%s given twice (first on line %d)", keywords[i].word,
                            p->first_line[i]);
            p->first_line[i] = p->at.line;
        }
        return keywords[i].parse(p, t);
    }
    /* Every keyword of the table, so the list cannot fall behind it. */
    char expected[400] = "";
    size_t used = 0;
    for (int i = 0; i < n && used < sizeof expected; i++)
        used += (size_t)snprintf(expected + used, sizeof expected - used, "%s%s",
                                 i == 0 ? "" : i + 1 == n ? " or " : ", ", keywords[i].word);
    return fail(p, "unknown keyword '%s' (expected %s)", shown(t->tok[0], buf), expected);
}

static bool parse_all(parser *p, const char *text, size_t size)
{
    if (!vkrt_line_parse_all(&p->at, text, size, "scene.cfg", parse_line, p))
        return false;
    vkrt_config *cfg = p->cfg;
    if (cfg->geometry_count == 0)
        return vkrt_error_set(p->at.err,
                              "%s: no 'geometry' line; a scene file (OBJ or glTF) is required",
                              p->at.name);
    return true;
}

/* ---------------------------------------------------------------------------------------------
 * Public API
 * ------------------------------------------------------------------------------------------- */

bool vkrt_config_parse(const char *text, size_t size, const char *name, const char *base_dir,
                       vkrt_config *cfg, vkrt_error *err)
{
    if (!cfg)
        return vkrt_error_set(err, "%s: no config to fill", name ? name : "scene.cfg");
    memset(cfg, 0, sizeof *cfg);

    vkrt_config c;
    vkrt_config_defaults(&c);

    parser p;
    memset(&p, 0, sizeof p);
    p.at.name = name ? name : "scene.cfg";
    p.at.err = err;
    p.base_dir = base_dir ? base_dir : "";
    p.cfg = &c;

    if (name && !(c.path = strdup(name)))
        return vkrt_error_set(err, "%s: out of memory", p.at.name);
    if (!text && size > 0) {
        vkrt_config_free(&c);
        return vkrt_error_set(err, "%s: no text to parse", p.at.name);
    }
    if (!parse_all(&p, text ? text : "", text ? size : 0)) {
        vkrt_config_free(&c);
        return false;
    }
    *cfg = c;
    return true;
}

bool vkrt_config_load(const char *path, vkrt_config *cfg, vkrt_error *err)
{
    if (cfg)
        memset(cfg, 0, sizeof *cfg);
    if (!path)
        return vkrt_error_set(err, "scene.cfg: no path given");

    char *text, *dir;
    size_t size;
    if (!vkrt_line_read_file(path, MAX_FILE_BYTES, "scene.cfg", &text, &size, &dir, err))
        return false;
    bool ok = vkrt_config_parse(text, size, path, dir, cfg, err);
    free(dir);
    free(text);
    return ok;
}
