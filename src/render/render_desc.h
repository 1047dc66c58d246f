/*
 * render_desc.h: a render description completed from the scene's own settings. Commands resolve
 * their options into a description (cmd/render_desc.h) and the renderer completes whatever
 * description it is given the same way, so that a test that leaves a field zero gets what
 * `vkrt render` would.
 */
#ifndef VKRT_RENDER_DESC_H
#define VKRT_RENDER_DESC_H

#include "../scene/config.h"
#include "renderer.h"

/* asked with every field that is zero where the scene has a setting taken from cfg: width,
 * height, samples, integrator (auto: the scene's `integrator`, which may be auto too: then the
 * renderer chooses from the lights) and max_depth. Other fields are copied. Completing a
 * completed description over the same cfg changes nothing. */
vkrt_render_desc vkrt_render_desc_complete(const vkrt_render_desc *asked, const vkrt_config *cfg);

#endif
