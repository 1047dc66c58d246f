/*
 * view.h: `vkrt view`: loads the scene, resolves what to render (render_desc.h) and what the
 * window shows (the finish stage, output/finish.h), and hands them to the viewer (view/viewer.h).
 * A vkrt built without GLFW says so instead.
 */
#ifndef VKRT_CMD_VIEW_H
#define VKRT_CMD_VIEW_H

#include "cli.h"

/* Runs a view command line until the window closes; returns the process exit status. */
int vkrt_cmd_view(const vkrt_command_line *cl);

#endif
