/*
 * viewer.h: `vkrt view`: a GLFW window on a Vulkan swapchain, flown through with the keyboard and
 * mouse (the controls are in `vkrt --help` and docs/viewer.md). The image is traced again only
 * when the camera changes; while it is still, sample passes are added until the spp target, and
 * the window shows their running average. The same renderer object as `vkrt render` traces it.
 */
#ifndef VKRT_VIEW_VIEWER_H
#define VKRT_VIEW_VIEWER_H

#include "../cli.h"

/* Runs the viewer the options describe until the window closes (or the script presses Escape);
 * returns the process exit code: 0, or 1 after printing what failed (a validation message
 * included). */
int vkrt_view_run(const vkrt_view_options *opts);

#endif
