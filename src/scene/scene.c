/* scene.c: loading a scene.cfg and its OBJ together (see scene.h). */
#include "scene.h"

#include <string.h>

bool vkrt_scene_load(const char *path, vkrt_scene *scene, vkrt_error *err)
{
    memset(scene, 0, sizeof *scene);
    if (!vkrt_config_load(path, &scene->config, err))
        return false;
    if (scene->config.materials) {
        /* User GLSL materials need the generated shading kernel of the wavefront pipeline,
         * which this version does not have; refusing is better than rendering them wrong. */
        vkrt_error_set(err, "%s: 'materials' (user shader materials) is not supported by this "
                            "version; remove the line to use the OBJ's .mtl",
                       path);
        vkrt_config_free(&scene->config);
        return false;
    }
    if (!vkrt_obj_load(scene->config.geometry, &scene->mesh, err)) {
        /* Say which scene file asked for the OBJ: the OBJ's own message follows. */
        vkrt_error_prefix(err, "%s:%d: geometry", path, scene->config.geometry_line);
        vkrt_config_free(&scene->config);
        return false;
    }
    return true;
}

void vkrt_scene_free(vkrt_scene *scene)
{
    vkrt_mesh_free(&scene->mesh);
    vkrt_config_free(&scene->config);
}
