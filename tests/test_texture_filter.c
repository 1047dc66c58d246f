/*
 * test_texture_filter.c: texture filtering by ray cones (glsl/lib/texture.glsl, surface.glsl)
 * against a closed form and against bilinear filtering, on a floor of a fine checker seen at a
 * slant (the floor fills the picture): a 1-texel checker of sRGB 0 and 255 (linear 0 and 1) lit
 * by an ambient light of 1 under Whitted, so that a pixel's radiance is the filtered texture.
 *
 * - No bias: the mean of a 1-sample frame with cones is the checker's mean, 0.5 (the mipmap
 *   levels are made in linear values; made from the encoded values they would read 0.22), within
 *   1% (8-bit levels round 0.5 to sRGB 188, 0.503).
 * - Stability: on a slow flythrough (the camera moving a fraction of a pixel's footprint per
 *   frame, a new pixel jitter each frame), the mean absolute change of a pixel between
 *   consecutive frames is at least 4 times smaller with cones than with bilinear filtering of
 *   the image alone (`textures bilinear`), which aliases.
 * One renderer per filter renders all frames: two kernel compilations in all.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "gpu_fixture.h"
#include "render/renderer.h"
#include "scene/scene.h"
#include "scene_dir.h"

enum { SIDE = 48, FRAMES = 6, TEXELS = 64 };

/* The checker: TEXELS x TEXELS, 1-texel squares of 0 and 255 (a grey TGA). */
static void write_checker(void)
{
    FILE *f = scene_dir_open("checker.tga");
    unsigned char header[18] = {0, 0, 3, 0, 0, 0, 0, 0, 0, 0, 0, 0, TEXELS, 0, TEXELS, 0, 8, 0x20};
    fwrite(header, 1, sizeof header, f);
    for (int y = 0; y < TEXELS; ++y)
        for (int x = 0; x < TEXELS; ++x)
            fputc((x + y) & 1 ? 255 : 0, f);
    fclose(f);
}

/* The floor, x and z in [-20, 20] at y = 0, its uv spanning 40 repeats: a texel is 1/64 of a
 * scene unit, about a pixel's footprint at the nearest point seen, many texels at the far edge. */
static void write_scene(const char *filter)
{
    write_checker();
    scene_dir_write("floor.mtl", "newmtl checker\nKd 1 1 1\nmap_Kd checker.tga\n");
    scene_dir_write("floor.obj", "mtllib floor.mtl\nusemtl checker\n"
                                 "v -20 0 -20\nv 20 0 -20\nv 20 0 20\nv -20 0 20\n"
                                 "vt 0 40\nvt 40 40\nvt 40 0\nvt 0 0\nf 1/1 4/4 3/3 2/2\n");
    char cfg[2048];
    int n = snprintf(cfg, sizeof cfg,
                     "geometry floor.obj\nresolution %d %d\nintegrator whitted\nmax-depth 1\n"
                     "textures %s\nlight ambient 1 1 1\n",
                     SIDE, SIDE, filter);
    /* Looking down 35 degrees with a 40-degree view: the floor fills the picture. The camera
     * moves 0.003 units a frame (a fifth of a texel, a fifth of a near pixel's footprint). */
    for (int i = 0; i < FRAMES; ++i)
        n += snprintf(cfg + n, sizeof cfg - (size_t)n,
                      "camera eye 0 1 %.4f look 0 0 %.4f up 0 1 0 fov 40\n", -0.003 * i,
                      -1.428 - 0.003 * i);
    scene_dir_write("scene.cfg", cfg);
}

/* Renders every frame of the folder's scene with filter at 1 sample per pixel, into
 * frames[FRAMES][SIDE * SIDE * 3]. */
static void render_frames(const char *filter, float *frames)
{
    write_scene(filter);
    char path[256];
    snprintf(path, sizeof path, "%s/scene.cfg", scene_dir);
    vkrt_error err = {{0}};
    vkrt_scene scene;
    if (!vkrt_scene_load(path, &scene, &err))
        fail_msg("load: %s", err.msg);
    assert_int_equal(scene.camera_count, FRAMES);
    gpu_context ctx;
    fixture_context_create(&ctx);
    vkrt_render_desc desc = {.width = SIDE, .height = SIDE, .samples = 1};
    vkrt_renderer *r = NULL;
    bool ok = vkrt_renderer_create(&r, &ctx, &scene, &desc, &err);
    for (uint32_t i = 0; ok && i < FRAMES; ++i)
        ok = vkrt_renderer_render(r, &scene.cameras[i], i, frames + (size_t)i * SIDE * SIDE * 3,
                                  NULL, &err);
    vkrt_renderer_destroy(r);
    fixture_context_destroy(&ctx);
    vkrt_scene_free(&scene);
    if (!ok)
        fail_msg("render: %s", err.msg);
}

static double frame_mean(const float *rgb)
{
    double sum = 0;
    for (int i = 0; i < SIDE * SIDE; ++i)
        sum += rgb[3 * i + 1];
    return sum / (SIDE * SIDE);
}

/* The mean absolute change of a pixel (green) from each frame to the next. */
static double flicker(const float *frames)
{
    double sum = 0;
    for (int f = 0; f + 1 < FRAMES; ++f)
        for (int i = 0; i < SIDE * SIDE; ++i)
            sum += fabs(frames[((size_t)(f + 1) * SIDE * SIDE + i) * 3 + 1] -
                        frames[((size_t)f * SIDE * SIDE + i) * 3 + 1]);
    return sum / ((FRAMES - 1) * SIDE * SIDE);
}

static void cones_unbiased_and_steadier_than_bilinear(void **state)
{
    (void)state;
    size_t floats = (size_t)FRAMES * SIDE * SIDE * 3;
    float *cone = malloc(floats * sizeof *cone), *bilinear = malloc(floats * sizeof *bilinear);
    assert_non_null(cone);
    assert_non_null(bilinear);
    render_frames("cone", cone);
    render_frames("bilinear", bilinear);
    double mean = frame_mean(cone);
    double cone_flicker = flicker(cone), bilinear_flicker = flicker(bilinear);
    printf("frame 0 mean: cone %.4f, bilinear %.4f (closed form 0.5); flicker: cone %.5f, "
           "bilinear %.5f (%.1fx)\n",
           mean, frame_mean(bilinear), cone_flicker, bilinear_flicker,
           bilinear_flicker / cone_flicker);
    assert_true(fabs(mean - 0.5) < 0.005);
    assert_true(bilinear_flicker > 4.0 * cone_flicker);
    free(cone);
    free(bilinear);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(cones_unbiased_and_steadier_than_bilinear),
    };
    return cmocka_run_group_tests(tests, scene_dir_make, scene_dir_remove);
}
