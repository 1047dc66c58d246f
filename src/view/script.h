/*
 * script.h: `vkrt view --script FILE`, a testing aid: key and mouse events at given frames, so a
 * session under Xvfb (where nobody types) flies, waits, takes screenshots and quits the same way
 * every time. Pure CPU: the viewer feeds the events to its own input handlers.
 *
 * One command per line; `#` starts a comment (docs/viewer.md):
 *   key NAME [down|up]   press and release a key (a tap), or only press or release it
 *   hold NAME FRAMES     press a key, wait FRAMES frames, release it
 *   button down|up       the left mouse button
 *   move DX DY           the cursor, by DX, DY pixels (right and down positive)
 *   drag DX DY FRAMES    button down, the move spread evenly over FRAMES frames, button up
 *   scroll CLICKS        the wheel; positive scrolls up
 *   resize W H           the window's size, in pixels
 *   wait FRAMES          let FRAMES frames pass
 *   wait converged       until the image has every sample of the spp target
 * Events between two waits happen at the start of one frame. Held keys move the camera by a fixed
 * 1/30 s per frame while a script runs, so a script flies the same path on any machine.
 */
#ifndef VKRT_VIEW_SCRIPT_H
#define VKRT_VIEW_SCRIPT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "../error.h"

typedef enum view_event_kind {
    VIEW_EVENT_KEY_DOWN,       /* key */
    VIEW_EVENT_KEY_UP,         /* key */
    VIEW_EVENT_BUTTON_DOWN,
    VIEW_EVENT_BUTTON_UP,
    VIEW_EVENT_MOVE,           /* x, y: pixels */
    VIEW_EVENT_SCROLL,         /* y: clicks */
    VIEW_EVENT_RESIZE,         /* x, y: width and height */
    VIEW_EVENT_WAIT,           /* frames */
    VIEW_EVENT_WAIT_CONVERGED,
} view_event_kind;

typedef struct view_event {
    view_event_kind kind;
    int key;                   /* the code the key_code function gave for the name */
    float x, y;
    uint32_t frames;
    int line;                  /* in the script, for messages */
} view_event;

typedef struct view_script {
    view_event *events;
    size_t count;
} view_script;

/* Maps a key name of a script (lower case: "w", "shift", "escape", ...) to the caller's key code,
 * or returns -1 for a name it does not know. */
typedef int (*view_key_code_fn)(const char *name);

/* Parses script text (size bytes, named name in messages) into events; drag and hold become their
 * primitive events. On failure returns false with err as "name:LINE: what is wrong" and *script
 * empty. */
bool view_script_parse(const char *text, size_t size, const char *name, view_key_code_fn key_code,
                       view_script *script, vkrt_error *err);

/* Reads the file at path and parses it as above. */
bool view_script_load(const char *path, view_key_code_fn key_code, view_script *script,
                      vkrt_error *err);

/* Frees the events and zeroes *script. Safe on a zeroed one. */
void view_script_free(view_script *script);

#endif
