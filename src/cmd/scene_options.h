/*
 * scene_options.h (cmd): what `vkrt render` and `vkrt view` ask of a loaded scene over what its
 * files say (cli.h's vkrt_scene_options): one camera of several, the environment, the tone curve.
 */
#ifndef VKRT_CMD_SCENE_OPTIONS_H
#define VKRT_CMD_SCENE_OPTIONS_H

#include <stdbool.h>
#include <stdio.h>

#include "../error.h"
#include "../scene/scene.h"
#include "cli.h"

/* Applies o to the loaded scene: --tonemap replaces scene->config.tonemap (which the commands
 * hand to the finish stage, output/finish.h), --camera keeps that one camera
 * (vkrt_scene_select_camera), --environment and --environment-map replace the environment
 * (vkrt_scene_set_environment; the map must open, checked here before any GPU work). o->fps is not applied here: it is the
 * loader's, given to it when the scene is loaded. A --environment that the material file's own
 * `environment` entry overrides is said on warnings (NULL: not said). On failure returns false
 * with err naming the option ("--camera top: no camera named 'top': ..."). */
bool vkrt_scene_options_apply(const vkrt_scene_options *o, vkrt_scene *scene, FILE *warnings,
                              vkrt_error *err);

#endif
