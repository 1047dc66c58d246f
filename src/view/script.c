/*
 * script.c: the viewer's event scripts (see script.h), read with the same line rules as scene.cfg
 * (src/scene/text_file.h).
 */
#include "script.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../scene/text_file.h"

/* A script is a few dozen lines; anything this large is the wrong file. */
#define SCRIPT_MAX_BYTES (1u << 20)
/* Frames one wait or drag may name: hours at any frame rate, and far from overflow. */
#define SCRIPT_MAX_FRAMES 1000000u

typedef struct parser {
    const char *name;
    int line;
    view_script *script;
    size_t capacity;
    vkrt_error *err;
} parser;

static bool fail(parser *p, const char *what, const char *tok)
{
    char shown[VKRT_TEXT_SHOWN_BYTES + 4];
    return vkrt_error_set(p->err, "%s:%d: %s%s%s%s", p->name, p->line, what, tok ? " '" : "",
                          tok ? vkrt_text_shown(tok, shown) : "", tok ? "'" : "");
}

static bool push(parser *p, view_event event)
{
    if (p->script->count == p->capacity) {
        size_t capacity = p->capacity ? 2 * p->capacity : 32;
        view_event *grown = realloc(p->script->events, capacity * sizeof *grown);
        if (!grown)
            return vkrt_error_set(p->err, "%s: out of memory", p->name);
        p->script->events = grown;
        p->capacity = capacity;
    }
    event.line = p->line;
    p->script->events[p->script->count++] = event;
    return true;
}

static bool number(parser *p, const char *tok, float *out)
{
    if (vkrt_text_float(tok, out))
        return fail(p, "a finite number was expected; got", tok);
    return true;
}

static bool frames(parser *p, const char *tok, uint32_t min, uint32_t *out)
{
    char *end;
    errno = 0;
    long long value = strtoll(tok, &end, 10);
    if (errno || end == tok || *end || value < (long long)min || value > SCRIPT_MAX_FRAMES) {
        char what[96];
        snprintf(what, sizeof what, "a frame count from %u to %u was expected; got", min,
                 SCRIPT_MAX_FRAMES);
        return fail(p, what, tok);
    }
    *out = (uint32_t)value;
    return true;
}

static bool key(parser *p, const char *tok, view_key_code_fn key_code, int *out)
{
    char lower[32];
    size_t n = strlen(tok);
    for (size_t i = 0; i < n && i + 1 < sizeof lower; ++i)
        lower[i] = (char)(tok[i] >= 'A' && tok[i] <= 'Z' ? tok[i] - 'A' + 'a' : tok[i]);
    lower[n < sizeof lower ? n : sizeof lower - 1] = '\0';
    *out = n < sizeof lower ? key_code(lower) : -1;
    char shown[VKRT_TEXT_SHOWN_BYTES + 4];
    if (*out < 0)
        return vkrt_error_set(p->err, "%s:%d: unknown key '%s' (docs/viewer.md lists the names)",
                              p->name, p->line, vkrt_text_shown(tok, shown));
    return true;
}

static bool arity(parser *p, const vkrt_text_tokens *t, int min, int max, const char *usage)
{
    if (t->count < min || t->count > max) {
        char what[128];
        snprintf(what, sizeof what, "%s takes: %s", t->tok[0], usage);
        return fail(p, what, NULL);
    }
    return true;
}

static bool command(parser *p, const vkrt_text_tokens *t, view_key_code_fn key_code)
{
    const char *cmd = t->tok[0];
    view_event e = {0};
    if (strcmp(cmd, "key") == 0) {
        if (!arity(p, t, 2, 3, "key NAME [down|up]") || !key(p, t->tok[1], key_code, &e.key))
            return false;
        const char *how = t->count == 3 ? t->tok[2] : "tap";
        bool tap = strcmp(how, "tap") == 0;
        if (!tap && strcmp(how, "down") != 0 && strcmp(how, "up") != 0)
            return fail(p, "key: down or up was expected; got", how);
        e.kind = strcmp(how, "up") == 0 ? VIEW_EVENT_KEY_UP : VIEW_EVENT_KEY_DOWN;
        if (!push(p, e))
            return false;
        e.kind = VIEW_EVENT_KEY_UP;
        return !tap || push(p, e);
    }
    if (strcmp(cmd, "hold") == 0) {
        uint32_t n;
        if (!arity(p, t, 3, 3, "hold NAME FRAMES") || !key(p, t->tok[1], key_code, &e.key) ||
            !frames(p, t->tok[2], 1, &n))
            return false;
        e.kind = VIEW_EVENT_KEY_DOWN;
        view_event wait = {.kind = VIEW_EVENT_WAIT, .frames = n};
        view_event up = {.kind = VIEW_EVENT_KEY_UP, .key = e.key};
        return push(p, e) && push(p, wait) && push(p, up);
    }
    if (strcmp(cmd, "button") == 0) {
        if (!arity(p, t, 2, 2, "button down|up"))
            return false;
        if (strcmp(t->tok[1], "down") != 0 && strcmp(t->tok[1], "up") != 0)
            return fail(p, "button: down or up was expected; got", t->tok[1]);
        e.kind = strcmp(t->tok[1], "down") == 0 ? VIEW_EVENT_BUTTON_DOWN : VIEW_EVENT_BUTTON_UP;
        return push(p, e);
    }
    if (strcmp(cmd, "move") == 0 || strcmp(cmd, "resize") == 0) {
        bool move = cmd[0] == 'm';
        if (!arity(p, t, 3, 3, move ? "move DX DY" : "resize WIDTH HEIGHT"))
            return false;
        if (move) {
            if (!number(p, t->tok[1], &e.x) || !number(p, t->tok[2], &e.y))
                return false;
            e.kind = VIEW_EVENT_MOVE;
        } else {
            uint32_t w, h;
            if (!frames(p, t->tok[1], 1, &w) || !frames(p, t->tok[2], 1, &h))
                return false;
            if (w > 16384 || h > 16384)
                return fail(p, "resize: the size is larger than 16384", NULL);
            e = (view_event){.kind = VIEW_EVENT_RESIZE, .x = (float)w, .y = (float)h};
        }
        return push(p, e);
    }
    if (strcmp(cmd, "drag") == 0) {
        float dx, dy;
        uint32_t n;
        if (!arity(p, t, 4, 4, "drag DX DY FRAMES") || !number(p, t->tok[1], &dx) ||
            !number(p, t->tok[2], &dy) || !frames(p, t->tok[3], 1, &n))
            return false;
        if (!push(p, (view_event){.kind = VIEW_EVENT_BUTTON_DOWN}))
            return false;
        for (uint32_t i = 0; i < n; ++i)
            if (!push(p, (view_event){.kind = VIEW_EVENT_MOVE, .x = dx / n, .y = dy / n}) ||
                !push(p, (view_event){.kind = VIEW_EVENT_WAIT, .frames = 1}))
                return false;
        return push(p, (view_event){.kind = VIEW_EVENT_BUTTON_UP});
    }
    if (strcmp(cmd, "scroll") == 0) {
        if (!arity(p, t, 2, 2, "scroll CLICKS") || !number(p, t->tok[1], &e.y))
            return false;
        e.kind = VIEW_EVENT_SCROLL;
        return push(p, e);
    }
    if (strcmp(cmd, "wait") == 0) {
        if (!arity(p, t, 2, 2, "wait FRAMES | wait converged"))
            return false;
        if (strcmp(t->tok[1], "converged") == 0)
            return push(p, (view_event){.kind = VIEW_EVENT_WAIT_CONVERGED});
        e.kind = VIEW_EVENT_WAIT;
        return frames(p, t->tok[1], 0, &e.frames) && push(p, e);
    }
    return fail(p, "unknown command (key, hold, button, move, drag, scroll, resize, wait)", cmd);
}

bool view_script_parse(const char *text, size_t size, const char *name, view_key_code_fn key_code,
                       view_script *script, vkrt_error *err)
{
    *script = (view_script){0};
    parser p = {.name = name, .script = script, .err = err};
    vkrt_text_skip_bom(&text, &size);
    vkrt_text_tokens *t = malloc(sizeof *t);
    if (!t)
        return vkrt_error_set(err, "%s: out of memory", name);
    bool ok = true;
    for (size_t pos = 0; ok && pos < size;) {
        size_t len;
        const char *line = vkrt_text_next_line(text, size, &pos, &len);
        ++p.line;
        char why[160];
        if (!vkrt_text_split(line, len, "viewer script", t, why, sizeof why))
            ok = vkrt_error_set(err, "%s:%d: %s", name, p.line, why);
        else if (t->count > 0)
            ok = command(&p, t, key_code);
    }
    free(t);
    if (!ok)
        view_script_free(script);
    return ok;
}

bool view_script_load(const char *path, view_key_code_fn key_code, view_script *script,
                      vkrt_error *err)
{
    char *text;
    size_t size;
    *script = (view_script){0};
    if (!vkrt_text_read_file(path, SCRIPT_MAX_BYTES, "viewer script", &text, &size, err))
        return false;
    bool ok = view_script_parse(text, size, path, key_code, script, err);
    free(text);
    return ok;
}

void view_script_free(view_script *script)
{
    free(script->events);
    *script = (view_script){0};
}
