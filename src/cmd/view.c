/* view.c: `vkrt view` (view.h). */
#include "view.h"

#include <stdio.h>

#ifdef VKRT_VIEWER
#include "../scene/scene.h"
#include "../view/viewer.h"
#include "render_desc.h"
#include "scene_options.h"

int vkrt_cmd_view(const vkrt_command_line *cl)
{
    const vkrt_view_options *opts = &cl->view;
    vkrt_error err = {{0}};
    vkrt_scene scene;
    /* --denoise without its library stops before any work; the window's frames are denoised
     * at OIDN's interactive quality. */
    vkrt_denoiser *denoiser = NULL;
    if (vkrt_denoise_asked(cl, NULL) &&
        !vkrt_denoiser_create(&denoiser, &(vkrt_denoiser_desc){.interactive = true}, &err)) {
        fprintf(stderr, "vkrt: %s\n", err.msg);
        return 1;
    }
    if (denoiser && opts->common.verbose)
        fprintf(stderr, "vkrt: denoise: %s\n", vkrt_denoiser_describe(denoiser));
    vkrt_load_options load = {.fps = opts->scene_options.fps};
    if (!vkrt_scene_load_with(opts->scene_path, &load, &scene, &err)) {
        fprintf(stderr, "vkrt: %s\n", err.msg);
        vkrt_denoiser_destroy(denoiser);
        return 1;
    }
    if (!vkrt_scene_options_apply(&opts->scene_options, &scene,
                                  opts->common.quiet ? NULL : stderr, &err)) {
        fprintf(stderr, "vkrt: %s\n", err.msg);
        vkrt_scene_free(&scene);
        vkrt_denoiser_destroy(denoiser);
        return 1;
    }
    /* `denoise on` in the scene file, where --denoise did not already make the denoiser. */
    if (!denoiser && vkrt_denoise_asked(cl, &scene.config) &&
        !vkrt_denoiser_create(&denoiser, &(vkrt_denoiser_desc){.interactive = true}, &err)) {
        fprintf(stderr, "vkrt: %s: denoise on: %s\n", opts->scene_path, err.msg);
        vkrt_scene_free(&scene);
        return 1;
    }
    if (!opts->common.quiet)
        vkrt_model_print_warnings(&scene.model, "vkrt: ", opts->common.verbose, stderr);
    vkrt_view_desc desc = {
        .scene_path = opts->scene_path,
        .scene = &scene,
        .render = vkrt_render_desc_for(&scene.config, cl),
        .finish = {.exposure = opts->exposure, .tonemap = scene.config.tonemap,
                   .denoiser = denoiser},
        .device = opts->common.device,
        .validation = opts->common.validation,
        .quiet = opts->common.quiet,
        .verbose = opts->common.verbose,
        .script = opts->script,
        .record = opts->record,
    };
    int status = vkrt_view_run(&desc);
    vkrt_scene_free(&scene);
    vkrt_denoiser_destroy(denoiser);
    return status;
}
#else
int vkrt_cmd_view(const vkrt_command_line *cl)
{
    (void)cl;
    fprintf(stderr, "vkrt: this vkrt was built without the viewer: GLFW was not found "
                    "(Debian: apt-get install libglfw3-dev, then rebuild)\n");
    return 1;
}
#endif
