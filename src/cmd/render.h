/*
 * render.h: `vkrt render`: loads the scene (all on the CPU, so bad input stops before any GPU
 * work), checks the output paths, renders every frame asked for and writes it (on one device, or
 * with --devices on several, a worker process each: device_pool.h), then prints a summary on
 * stderr. Ctrl-C stops between frames; --resume skips the frames whose files are complete.
 */
#ifndef VKRT_CMD_RENDER_H
#define VKRT_CMD_RENDER_H

#include "cli.h"

/* Runs a render command line; main_ms is the clock (clock.h) when main began, for --verbose's
 * start-up line. Returns the process exit status: 0, 1 on failure (printed), 130 interrupted. */
int vkrt_cmd_render(const vkrt_command_line *cl, double main_ms);

#endif
