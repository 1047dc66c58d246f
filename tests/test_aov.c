/*
 * test_aov.c: the AOVs of --aov (vkrt_renderer_read_aovs) on the GPU, against closed forms.
 *
 * A square of Kd (0.2, 0.5, 0.8) in the plane z = 0, seen from (0, 0, 3) at one sample per pixel
 * (the pixel's centre) under an environment of (0.25, 0.5, 2): where a pixel's ray meets the
 * square (worked out here in double precision), albedo Kd, normal +z (towards the camera), depth
 * the distance along the ray to the plane and position the point of the plane it meets; where it
 * misses, the environment clamped to [0, 1], a zero normal, depth +inf and position 0. At 16
 * samples the albedo is anti-aliased: its mean over the picture is the square's share of the
 * view (a third) times Kd plus the rest times the environment. A perfect mirror in the same
 * place, facing a diffuse wall behind the camera, gives the wall's albedo and normal (the path
 * follows the delta bounce) but the mirror's depth and position (the first hit). Whitted at one
 * sample and the path tracer at 16, each rendering both (two cameras of one scene: a renderer's
 * start costs most of a test's time on a CPU device).
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>

#include <cmocka.h>

#include "../glsl/shared.h"
#include "gpu_fixture.h"
#include "render/camera_frame.h"
#include "scene/scene.h"
#include "scene_dir.h"

enum { W = 32, H = 32 };

/* What the renderer gave: the beauty and every AOV. */
typedef struct aov_frame {
    float rgb[W * H * 3], albedo[W * H * 3], normal[W * H * 3], depth[W * H],
        position[W * H * 3];
} aov_frame;

/* The square's camera, and the mirror's, 100 units to the side (the square's view, 1.73 units
 * wide at z = 0, sees nothing of it). */
static const char cameras[] = "camera eye 0 0 3 look 0 0 0 up 0 1 0 fov 60\n"
                              "camera eye 100 0 3 look 100 0 0 up 0 1 0 fov 60\n";

static int setup(void **state)
{
    if (scene_dir_make(state) != 0)
        return -1;
    /* The square; the mirror at z = 0 and a wall at z = 6, behind the mirror's camera, that the
     * mirror shows. */
    scene_dir_write("scene.obj", "mtllib scene.mtl\nusemtl paint\n"
                                 "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\n"
                                 "usemtl mirror\n"
                                 "v 90 -10 0\nv 110 -10 0\nv 110 10 0\nv 90 10 0\nf 5 6 7 8\n"
                                 "usemtl wall\n"
                                 "v 80 -20 6\nv 120 -20 6\nv 120 20 6\nv 80 20 6\nf 12 11 10 9\n");
    scene_dir_write("scene.mtl", "newmtl paint\nKd 0.2 0.5 0.8\n"
                                 "newmtl mirror\nillum 3\nKd 0 0 0\nKs 1 1 1\n"
                                 "newmtl wall\nKd 0.7 0.3 0.1\n");
    char cfg[256];
    snprintf(cfg, sizeof cfg, "geometry scene.obj\nenvironment 0.25 0.5 2\nmax-depth 4\n%s",
             cameras);
    scene_dir_write("scene.cfg", cfg);
    return 0;
}

/* Renders the scene's two cameras (the square, the mirror) at spp samples with integrator,
 * every AOV recorded. */
static void render(vkrt_integrator integrator, uint32_t spp, aov_frame out[2],
                   vkrt_config_camera camera[2])
{
    vkrt_scene scene;
    scene_dir_load(&scene);
    gpu_context ctx;
    fixture_context_create(&ctx);
    vkrt_error err = {{0}};
    vkrt_render_desc desc = {.width = W, .height = H, .samples = spp, .integrator = integrator,
                             .aovs = VKRT_AOV_ALL};
    vkrt_renderer *r = NULL;
    bool ok = vkrt_renderer_create(&r, &ctx, &scene, &desc, &err);
    for (int c = 0; ok && c < 2; ++c) {
        ok = vkrt_renderer_render(r, &scene.cameras[c], 0, out[c].rgb, NULL, &err) &&
             vkrt_renderer_read_aovs(r, 0, out[c].albedo, out[c].normal, out[c].depth,
                                     out[c].position, &err);
        camera[c] = scene.cameras[c];
    }
    vkrt_renderer_destroy(r);
    fixture_context_destroy(&ctx);
    vkrt_scene_free(&scene);
    if (!ok)
        fail_msg("%s", err.msg);
}

/* The ray through pixel (x, y)'s centre: from the eye, along the unit dir. */
static void centre_ray(const vkrt_config_camera *camera, int x, int y, double eye[3],
                       double dir[3])
{
    FrameParams f = {0};
    vkrt_camera_params(camera, W, H, &f);
    double u = 2.0 * (x + 0.5) / W - 1.0, v = 1.0 - 2.0 * (y + 0.5) / H;
    double d[3] = {f.forward.x + u * f.right.x + v * f.up.x, f.forward.y + u * f.right.y + v * f.up.y,
                   f.forward.z + u * f.right.z + v * f.up.z};
    double length = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int k = 0; k < 3; ++k)
        dir[k] = d[k] / length;
    eye[0] = f.eye.x;
    eye[1] = f.eye.y;
    eye[2] = f.eye.z;
}

static void assert_close3(const float *got, double x, double y, double z, double tolerance,
                          const char *what, int px, int py)
{
    double want[3] = {x, y, z};
    for (int k = 0; k < 3; ++k)
        if (!(fabs(got[k] - want[k]) <= tolerance))
            fail_msg("pixel (%d, %d): %s (%g, %g, %g), expected (%g, %g, %g)", px, py, what,
                     (double)got[0], (double)got[1], (double)got[2], x, y, z);
}

/* Every pixel of a one-sample render of the square, hit or missed, against the closed form. */
static void check_square(const aov_frame *f, const vkrt_config_camera *camera)
{
    int hits = 0, misses = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            double eye[3], dir[3];
            centre_ray(camera, x, y, eye, dir);
            double t = -eye[2] / dir[2];
            double p[3] = {eye[0] + t * dir[0], eye[1] + t * dir[1], 0.0};
            double margin = fmax(fabs(p[0]), fabs(p[1])) - 1.0;
            size_t i = (size_t)y * W + x;
            if (fabs(margin) < 1e-3)
                continue; /* on the square's edge: either answer is right */
            if (margin < 0) {
                ++hits;
                assert_close3(f->albedo + 3 * i, 0.2, 0.5, 0.8, 1e-6, "albedo", x, y);
                assert_close3(f->normal + 3 * i, 0, 0, 1, 1e-6, "normal", x, y);
                assert_close3(f->position + 3 * i, p[0], p[1], p[2], 1e-5, "position", x, y);
                if (!(fabs(f->depth[i] - t) <= 1e-5 * t))
                    fail_msg("pixel (%d, %d): depth %.9g, expected %.9g", x, y,
                             (double)f->depth[i], t);
            } else {
                ++misses;
                assert_close3(f->albedo + 3 * i, 0.25, 0.5, 1.0, 0, "albedo", x, y);
                assert_close3(f->normal + 3 * i, 0, 0, 0, 0, "normal", x, y);
                assert_close3(f->position + 3 * i, 0, 0, 0, 0, "position", x, y);
                assert_true(isinf(f->depth[i]) && f->depth[i] > 0);
            }
        }
    print_message("%d pixels on the square, %d missing it, as the closed form says\n", hits,
                  misses);
    assert_true(hits > 200 && misses > 200);
}

/* 16 samples of the path tracer on the square: pixels wholly on it exactly as at one sample,
 * those on its edge between it and the environment; the picture's mean albedo is the square's
 * share of the view, a third (its half width over the view's at its distance, 1 / (3 tan 30
 * deg), squared), times Kd plus the rest times the environment. */
static void check_square_antialiased(const aov_frame *f)
{
    double share = 1.0 / 3.0, mean[3] = {0};
    const double kd[3] = {0.2, 0.5, 0.8}, sky[3] = {0.25, 0.5, 1.0};
    int between = 0;
    for (int i = 0; i < W * H; ++i) {
        for (int k = 0; k < 3; ++k)
            mean[k] += f->albedo[3 * i + k] / (W * H);
        between += f->albedo[3 * i + 2] > 0.801f && f->albedo[3 * i + 2] < 0.999f;
    }
    print_message("mean albedo (%.5f, %.5f, %.5f); %d pixels on the edge\n", mean[0], mean[1],
                  mean[2], between);
    for (int k = 0; k < 3; ++k)
        assert_true(fabs(mean[k] - (share * kd[k] + (1 - share) * sky[k])) < 2e-3);
    /* The edge runs round the square, 4 x 18.5 pixels long: most pixels it crosses are mixed. */
    assert_true(between > 40);
    for (int y = 12; y < 20; ++y)
        for (int x = 12; x < 20; ++x) {
            size_t i = (size_t)y * W + x;
            assert_close3(f->albedo + 3 * i, 0.2, 0.5, 0.8, 1e-6, "albedo", x, y);
            assert_close3(f->normal + 3 * i, 0, 0, 1, 1e-6, "normal", x, y);
        }
}

/* The mirror fills the view: every pixel shows the wall's albedo and normal (facing the ray the
 * mirror sent back, -z), and the mirror's own depth and position, to within `spread` (relative
 * to the depth: 0 but rounding at one sample, the pixel's spread of depths at several). */
static void check_mirror(const aov_frame *f, const vkrt_config_camera *camera, double spread)
{
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            double eye[3], dir[3];
            centre_ray(camera, x, y, eye, dir);
            /* Float rounding at 100 units from the origin, and the spread. */
            double t = -eye[2] / dir[2], tolerance = 1e-5 * (1 + fabs(eye[0])) + spread * t;
            size_t i = (size_t)y * W + x;
            assert_close3(f->albedo + 3 * i, 0.7, 0.3, 0.1, 1e-6, "albedo", x, y);
            assert_close3(f->normal + 3 * i, 0, 0, -1, 1e-6, "normal", x, y);
            assert_close3(f->position + 3 * i, eye[0] + t * dir[0], eye[1] + t * dir[1], 0,
                          tolerance, "position", x, y);
            if (!(fabs(f->depth[i] - t) <= tolerance))
                fail_msg("pixel (%d, %d): depth %.9g, expected %.9g", x, y, (double)f->depth[i],
                         t);
        }
}

/* Renders both cameras with integrator at spp samples and checks them: at one sample against
 * the closed forms at the pixels' centres; at several, the square's anti-aliasing, and the
 * mirror's depth to the spread of a pixel's samples (3 units away a pixel is 0.11 units wide,
 * and the plane's depth changes by at most 0.6 of that across it). */
static void check_render(vkrt_integrator integrator, uint32_t spp)
{
    aov_frame *f = calloc(2, sizeof *f);
    assert_non_null(f);
    vkrt_config_camera camera[2];
    render(integrator, spp, f, camera);
    if (spp == 1)
        check_square(&f[0], &camera[0]);
    else
        check_square_antialiased(&f[0]);
    check_mirror(&f[1], &camera[1], spp == 1 ? 0 : 0.02);
    free(f);
}

static void whitted(void **state)
{
    (void)state;
    check_render(VKRT_INTEGRATOR_WHITTED, 1);
}

static void path(void **state)
{
    (void)state;
    check_render(VKRT_INTEGRATOR_PATH, 16);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(whitted),
        cmocka_unit_test(path),
    };
    return cmocka_run_group_tests(tests, setup, scene_dir_remove);
}
