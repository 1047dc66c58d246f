/* render_desc.c (cmd): a command's options into the renderer's description (render_desc.h). */
#include "render_desc.h"

#include "../render/render_desc.h"

/* Without --spp the viewer gathers at least this many samples of a still picture: one pass of a
 * scene's usual `samples` looks too noisy to judge a view by. */
static const uint32_t view_default_samples = 16;

vkrt_render_desc vkrt_render_desc_for(const vkrt_config *cfg, const vkrt_command_line *cl)
{
    const vkrt_common_options *common = cl->command == VKRT_COMMAND_VIEW    ? &cl->view.common
                                        : cl->command == VKRT_COMMAND_BENCH ? &cl->bench.common
                                                                            : &cl->render.common;
    vkrt_render_desc d = {
        .width = common->width,
        .height = common->height,
        /* Given, `--accel auto` beats the scene's `accel` line: 0 here means auto, not unset. */
        .accel = common->accel_given ? common->accel : cfg->accel,
        .bvh_splits = common->bvh_splits_given ? common->bvh_splits : cfg->bvh_splits,
        .instancing = common->instancing,
        .integrator = common->integrator,
        .clamp = common->clamp,
        .target_error = common->target_error,
    };
    if (cl->command == VKRT_COMMAND_RENDER) {
        const vkrt_render_options *o = &cl->render;
        d.samples = o->samples;
        d.profile = o->profile;
        d.profile_repeat = o->profile_repeat;
        d.seed = o->seed;
        /* --denoise: the albedo and normal guide the denoiser (written only if --aov asks). */
        d.aovs = o->aovs | (vkrt_denoise_asked(cl, cfg) ? VKRT_AOV_SURFACE : 0u);
        d.shutter = cfg->shutter; /* the viewer's camera has no next frame to blur towards */
    } else if (cl->command == VKRT_COMMAND_VIEW) {
        uint32_t least = cfg->samples > view_default_samples ? cfg->samples : view_default_samples;
        d.samples = cl->view.samples ? cl->view.samples : least;
    } else if (cl->command == VKRT_COMMAND_BENCH) {
        d.samples = 1;
        d.tuning = cl->bench.tuning;
        d.traversal_stats = cl->bench.stats;
    }
    return vkrt_render_desc_complete(&d, cfg);
}

bool vkrt_denoise_asked(const vkrt_command_line *cl, const vkrt_config *cfg)
{
    bool flag = cl->command == VKRT_COMMAND_RENDER ? cl->render.denoise
                : cl->command == VKRT_COMMAND_VIEW ? cl->view.denoise
                                                   : false;
    bool frames = cl->command == VKRT_COMMAND_RENDER || cl->command == VKRT_COMMAND_VIEW;
    return flag || (frames && cfg && cfg->denoise);
}
