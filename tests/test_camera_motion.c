/*
 * test_camera_motion.c: vkrt_camera_between (src/render/camera_frame.c), the camera of motion
 * blur between two frames, against closed forms: its ends are the two cameras, the eye moves on
 * the line between them, and a turn is taken at a constant angular rate the shorter way round
 * (the midpoint of a 90-degree turn looks 45 degrees round; of a 270-degree one, 45 the other
 * way, since slerp takes the 90-degree arc).
 */
#include <setjmp.h> /* cmocka needs these before its header */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>

#include "render/camera_frame.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static vkrt_config_camera looking(float yaw_deg, float x)
{
    float a = (float)(yaw_deg * M_PI / 180);
    return (vkrt_config_camera){.eye = {x, 1, 0},
                                .look = {x + sinf(a), 1, -cosf(a)},
                                .up = {0, 1, 0},
                                .fov_deg = 40};
}

/* The view direction of c, unit. */
static void view_of(const vkrt_config_camera *c, double v[3])
{
    double len = 0;
    for (int i = 0; i < 3; ++i) {
        v[i] = c->look[i] - c->eye[i];
        len += v[i] * v[i];
    }
    for (int i = 0; i < 3; ++i)
        v[i] /= sqrt(len);
}

static void assert_yaw(const vkrt_config_camera *c, double yaw_deg)
{
    double v[3], a = yaw_deg * M_PI / 180;
    view_of(c, v);
    if (!(fabs(v[0] - sin(a)) < 1e-5 && fabs(v[1]) < 1e-5 && fabs(v[2] + cos(a)) < 1e-5))
        fail_msg("view (%g, %g, %g), not at yaw %g", v[0], v[1], v[2], yaw_deg);
    assert_true(fabs(c->up[1] - 1) < 1e-5); /* a turn about up keeps up */
}

static void ends_and_midpoints(void **state)
{
    (void)state;
    vkrt_config_camera a = looking(0, 0), b = looking(90, 4), c;
    vkrt_camera_between(&a, &b, 0, &c);
    assert_yaw(&c, 0);
    vkrt_camera_between(&a, &b, 1, &c);
    assert_yaw(&c, 90);
    assert_true(fabsf(c.eye[0] - 4) < 1e-6f);
    for (int k = 1; k < 4; ++k) {
        vkrt_camera_between(&a, &b, k / 4.0f, &c);
        assert_yaw(&c, 90.0 * k / 4);
        assert_true(fabsf(c.eye[0] - k) < 1e-6f && c.eye[1] == 1 && c.eye[2] == 0);
    }
    /* The shorter way round: from 0 to 270 degrees is 90 degrees the other way. */
    b = looking(270, 0);
    vkrt_camera_between(&a, &b, 0.5f, &c);
    assert_yaw(&c, -45);
    /* The same camera at both ends stays put. */
    vkrt_camera_between(&a, &a, 0.3f, &c);
    assert_yaw(&c, 0);
}

/* A lens whose focus defaulted to |look - eye| keeps that distance, interpolated. */
static void focus_follows_the_look_distance(void **state)
{
    (void)state;
    vkrt_config_camera a = looking(0, 0), b = looking(0, 0), c;
    a.aperture = b.aperture = 0.1f;
    a.look[2] = -4; /* 4 ahead */
    b.look[2] = -8;
    vkrt_camera_between(&a, &b, 0.5f, &c);
    assert_true(fabsf(c.focus - 6) < 1e-5f);
}

/* The projection is the first camera's; its size moves only towards a camera of the same
 * projection: two orthographic cameras' widths are interpolated, and a perspective camera's
 * fov never leaks into an orthographic one (nor the other way). */
static void projection_sizes(void **state)
{
    (void)state;
    vkrt_config_camera a = looking(0, 0), b = looking(30, 2), c;
    a.ortho_width = 2;
    a.fov_deg = b.fov_deg = 0;
    b.ortho_width = 6;
    vkrt_camera_between(&a, &b, 0.25f, &c);
    assert_true(c.ortho_width == 3 && c.fov_deg == 0);
    assert_yaw(&c, 7.5);
    b = looking(30, 2); /* perspective, fov 40 */
    vkrt_camera_between(&a, &b, 0.5f, &c);
    assert_true(c.ortho_width == 2 && c.fov_deg == 0);
    vkrt_camera_between(&b, &a, 0.5f, &c);
    assert_true(c.ortho_width == 0 && c.fov_deg == 40);
    b.fov_deg = 60;
    vkrt_config_camera d = looking(0, 0);
    vkrt_camera_between(&d, &b, 0.5f, &c);
    assert_true(c.ortho_width == 0 && c.fov_deg == 50);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(ends_and_midpoints),
        cmocka_unit_test(focus_follows_the_look_distance),
        cmocka_unit_test(projection_sizes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
