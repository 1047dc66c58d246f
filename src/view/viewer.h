/*
 * viewer.h: `vkrt view`'s window: a GLFW window on a Vulkan swapchain, flown through with the
 * keyboard and mouse (the controls are in `vkrt --help` and docs/viewer.md). The image is traced
 * again only when the camera changes; while it is still, sample passes are added until the spp
 * target, and the window shows their running average through the finish stage
 * (output/finish.h). The same renderer object as `vkrt render` traces it. The command that
 * loads the scene and resolves the description is cmd/view.c.
 */
#ifndef VKRT_VIEW_VIEWER_H
#define VKRT_VIEW_VIEWER_H

#include <stdbool.h>

#include "../output/finish.h"
#include "../render/renderer.h"
#include "../scene/scene.h"

/* What the viewer shows and how. */
typedef struct vkrt_view_desc {
    const char *scene_path;   /* the window's title, and where screenshots go beside */
    const vkrt_scene *scene;  /* loaded; the viewer reads it while it runs */
    vkrt_render_desc render;  /* resolved (cmd/render_desc.h); the window opens at its size */
    vkrt_finish_desc finish;  /* what the window shows of the image (--exposure) */
    int device;               /* Vulkan device; -1: the default */
    bool validation, quiet, verbose;
    const char *script;       /* events to play (a testing aid); NULL: none */
    const char *record;       /* where K appends camera lines; NULL: none */
} vkrt_view_desc;

/* Runs the viewer until the window closes (or the script presses Escape); returns the process
 * exit code: 0, or 1 after printing what failed (a validation message included). */
int vkrt_view_run(const vkrt_view_desc *desc);

#endif
