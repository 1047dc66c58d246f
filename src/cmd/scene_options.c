/* scene_options.c (cmd): the command line's camera, environment and tone curve over the scene's
 * (scene_options.h). */
#include "scene_options.h"

#include <errno.h>
#include <string.h>

bool vkrt_scene_options_apply(const vkrt_scene_options *o, vkrt_scene *scene, FILE *warnings,
                              vkrt_error *err)
{
    if (o->tonemap_given)
        scene->config.tonemap = o->tonemap;
    if (o->camera && !vkrt_scene_select_camera(scene, o->camera, err))
        return vkrt_error_prefix(err, "--camera %s", o->camera);
    if (o->environment_map) {
        /* Opened now, so that a typo stops the run before the GPU starts; read by the renderer. */
        FILE *f = fopen(o->environment_map, "rb");
        if (!f)
            return vkrt_error_set(err, "--environment-map %s: cannot open: %s", o->environment_map,
                                  strerror(errno));
        fclose(f);
    }
    bool constant_used = true;
    if ((o->environment_given || o->environment_map) &&
        !vkrt_scene_set_environment(scene, o->environment_given ? o->environment : NULL,
                                    o->environment_map, &constant_used, err))
        return false;
    if (o->environment_given && !constant_used && warnings)
        fprintf(warnings, "vkrt: warning: --environment is not used: the material file's "
                          "`environment` entry is the environment\n");
    return true;
}
