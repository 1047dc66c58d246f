/*
 * render_desc.h (cmd): the one place a command's options become the renderer's description.
 * `render`, `view` and `bench` each call it; what differs between them (the viewer's sample
 * default, render's profile, seed and motion blur, bench's single sample and tuning) is decided
 * here, and the scene's own settings fill the rest (render/render_desc.h).
 */
#ifndef VKRT_CMD_RENDER_DESC_H
#define VKRT_CMD_RENDER_DESC_H

#include "../render/renderer.h"
#include "../scene/config.h"
#include "cli.h"

/* The complete description cl's command asks for over the scene cfg: every option given beats
 * the scene's setting; the renderer need not fill anything in. */
vkrt_render_desc vkrt_render_desc_for(const vkrt_config *cfg, const vkrt_command_line *cl);

/* Whether cl's command denoises what it makes (render's files, view's window): --denoise. */
bool vkrt_denoise_asked(const vkrt_command_line *cl, const vkrt_config *cfg);

#endif
