/* scene_dir.c: temporary scene folders for tests (see scene_dir.h). */
#define _POSIX_C_SOURCE 200809L
#include "scene_dir.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>

#include <cmocka.h>

#include "gpu_fixture.h"
#include "scene/scene.h"

char scene_dir[64];

int scene_dir_make(void **state)
{
    (void)state;
    snprintf(scene_dir, sizeof scene_dir, "/tmp/vkrt-scene-XXXXXX");
    return mkdtemp(scene_dir) ? 0 : -1;
}

int scene_dir_remove(void **state)
{
    (void)state;
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", scene_dir);
    return system(cmd) == 0 ? 0 : -1;
}

FILE *scene_dir_open(const char *name)
{
    char path[256];
    snprintf(path, sizeof path, "%s/%s", scene_dir, name);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    return f;
}

void scene_dir_write(const char *name, const char *text)
{
    FILE *f = scene_dir_open(name);
    fputs(text, f);
    fclose(f);
}

void scene_dir_load(vkrt_scene *scene)
{
    char path[256];
    snprintf(path, sizeof path, "%s/scene.cfg", scene_dir);
    vkrt_error err = {{0}};
    if (!vkrt_scene_load(path, scene, &err))
        fail_msg("%s", err.msg);
}

bool scene_dir_render(uint32_t w, uint32_t h, const vkrt_render_desc *desc, float *rgb,
                      vkrt_frame_stats *stats, vkrt_error *err)
{
    return scene_dir_render_accel(w, h, desc, rgb, stats, NULL, err);
}

bool scene_dir_render_accel(uint32_t w, uint32_t h, const vkrt_render_desc *desc, float *rgb,
                            vkrt_frame_stats *stats, vkrt_accel_stats *accel, vkrt_error *err)
{
    char path[256];
    snprintf(path, sizeof path, "%s/scene.cfg", scene_dir);
    vkrt_scene scene;
    if (!vkrt_scene_load(path, &scene, err))
        return false;
    gpu_context ctx;
    fixture_context_create(&ctx);
    vkrt_render_desc d = desc ? *desc : (vkrt_render_desc){0};
    d.width = w;
    d.height = h;
    d.samples = d.samples ? d.samples : 1;
    d.shutter = d.shutter > 0 ? d.shutter : scene.config.shutter;
    vkrt_renderer *r = NULL;
    bool ok = vkrt_renderer_create(&r, &ctx, &scene, &d, err);
    /* The first camera, moving towards the second while the shutter is open (as vkrt render's
     * frame 0 does). */
    if (ok && scene.camera_count > 1)
        vkrt_renderer_set_next_camera(r, &scene.cameras[1]);
    ok = ok && vkrt_renderer_render(r, &scene.cameras[0], 0, rgb, stats, err);
    if (ok && accel)
        *accel = *vkrt_renderer_accel_stats(r);
    vkrt_renderer_destroy(r);
    fixture_context_destroy(&ctx);
    vkrt_scene_free(&scene);
    return ok;
}
