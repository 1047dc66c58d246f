/*
 * test_view_camera.c: the viewer's camera math (src/view/camera.c), without a window.
 *
 * Directions are checked against the renderer's own camera frame (right = forward x up, as
 * src/render/camera_frame.c builds it), so "drag right turns right" means right in the picture.
 * Framing is checked by projecting the box's corners, not by repeating the formula. Tolerances
 * are a few float ULPs of unit vectors (1e-5) or of the scene's coordinates (1e-5 relative).
 */
#define _POSIX_C_SOURCE 200809L

#include <setjmp.h> /* cmocka needs these before its header */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "scene/config.h"
#include "view/camera.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static double dot(const float *a, const float *b)
{
    return (double)a[0] * b[0] + (double)a[1] * b[1] + (double)a[2] * b[2];
}

static void cross(const float *a, const float *b, float *out)
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

static void normalize(float *v)
{
    float length = (float)sqrt(dot(v, v));
    for (int i = 0; i < 3; ++i)
        v[i] /= length;
}

static double angle_degrees(const float *a, const float *b)
{
    double c = dot(a, b) / sqrt(dot(a, a) * dot(b, b));
    return acos(c > 1 ? 1 : c < -1 ? -1 : c) * 180 / M_PI;
}

static vkrt_config_camera make_camera(float ex, float ey, float ez, float lx, float ly, float lz,
                                      float ux, float uy, float uz, float fov)
{
    return (vkrt_config_camera){
        .eye = {ex, ey, ez}, .look = {lx, ly, lz}, .up = {ux, uy, uz}, .fov_deg = fov};
}

/* A level camera, one looking steeply down, and one whose world up is z and not unit length;
 * ortho_camera is the first made orthographic. */
static vkrt_config_camera cameras[3], ortho_camera;

static int setup(void **state)
{
    (void)state;
    cameras[0] = make_camera(278, 273, -800, 278, 273, 0, 0, 1, 0, 39.3077f);
    cameras[1] = make_camera(-14, 2.5f, 0, 10, -20, 3, 0, 1, 0, 60);
    cameras[2] = make_camera(1, 2, 3, 4, -1, 2.5f, 0, 0, 7, 50);
    ortho_camera = make_camera(278, 273, -800, 278, 273, 0, 0, 1, 0, 0);
    ortho_camera.ortho_width = 600;
    return 0;
}

static void view_direction(const vkrt_config_camera *c, float *d)
{
    for (int i = 0; i < 3; ++i)
        d[i] = c->look[i] - c->eye[i];
    normalize(d);
}

static void test_init_keeps_the_scene_camera(void **state)
{
    (void)state;
    for (int c = 0; c < 3; ++c) {
        view_camera cam;
        view_camera_init(&cam, &cameras[c], 2);
        vkrt_config_camera out;
        view_camera_to_config(&cam, &out);
        /* Unmoved, the traced camera is the scene's, bit for bit. */
        assert_memory_equal(&out, &cameras[c], sizeof out);
        /* And the yaw/pitch form points the same way. */
        float forward[3], expected[3];
        view_camera_forward(&cam, forward);
        view_direction(&cameras[c], expected);
        for (int i = 0; i < 3; ++i)
            assert_true(fabsf(forward[i] - expected[i]) < 1e-5f);
        assert_true(fabs(dot(cam.up, cam.up) - 1) < 1e-6);
    }
}

static void test_a_moved_camera_writes_its_frame(void **state)
{
    (void)state;
    for (int c = 0; c < 3; ++c) {
        view_camera cam;
        view_camera_init(&cam, &cameras[c], 2);
        view_camera_look(&cam, 0, 0); /* no motion: still unmoved */
        assert_false(cam.moved);
        view_camera_move(&cam, 0, 0, 0, 1);
        assert_false(cam.moved);
        cam.moved = true; /* written from the yaw/pitch form, unchanged */
        vkrt_config_camera out;
        view_camera_to_config(&cam, &out);
        float d_out[3], d_scene[3];
        view_direction(&out, d_out);
        view_direction(&cameras[c], d_scene);
        assert_true(angle_degrees(d_out, d_scene) < 1e-3);
        for (int i = 0; i < 3; ++i)
            assert_true(out.eye[i] == cameras[c].eye[i]);
        assert_true(angle_degrees(out.up, cameras[c].up) < 1e-4);
        assert_true(out.fov_deg == cameras[c].fov_deg);
    }
}

static void test_drag_right_turns_right_and_down_looks_down(void **state)
{
    (void)state;
    for (int c = 0; c < 3; ++c) {
        view_camera cam;
        view_camera_init(&cam, &cameras[c], 1);
        float before[3], after[3], right[3];
        view_camera_forward(&cam, before);
        cross(before, cam.up, right); /* the renderer's right */
        view_camera_look(&cam, 100, 0);
        view_camera_forward(&cam, after);
        assert_true(dot(after, right) > 0);
        /* A pure yaw keeps the height of the view direction. */
        assert_true(fabs(dot(after, cam.up) - dot(before, cam.up)) < 1e-5);
        if (c == 0) /* level: the turn is exactly 100 pixels' worth */
            assert_true(fabs(angle_degrees(before, after) - 100 * VIEW_LOOK_DEGREES_PER_PIXEL) <
                        1e-3);
        float height = (float)dot(after, cam.up);
        view_camera_look(&cam, 0, 20);
        view_camera_forward(&cam, after);
        assert_true(dot(after, cam.up) < height);
        assert_true(cam.moved);
    }
}

static void test_pitch_stops_short_of_straight_up(void **state)
{
    (void)state;
    view_camera cam;
    view_camera_init(&cam, &cameras[0], 1);
    view_camera_look(&cam, 0, -1e6f);
    float forward[3];
    view_camera_forward(&cam, forward);
    assert_true(fabs(angle_degrees(forward, cam.up) - (90 - VIEW_PITCH_LIMIT_DEGREES)) < 1e-3);
    view_camera_look(&cam, 0, 2e6f);
    view_camera_forward(&cam, forward);
    assert_true(fabs(angle_degrees(forward, cam.up) - (90 + VIEW_PITCH_LIMIT_DEGREES)) < 1e-3);
    /* Whatever the pitch, the written camera is valid: up is not parallel to the view. */
    vkrt_config_camera out;
    view_camera_to_config(&cam, &out);
    float d[3];
    view_direction(&out, d);
    assert_true(angle_degrees(d, out.up) < 179.5);
}

static void test_full_turn_comes_back(void **state)
{
    (void)state;
    view_camera cam;
    view_camera_init(&cam, &cameras[1], 1);
    float before[3], after[3];
    view_camera_forward(&cam, before);
    view_camera_look(&cam, 360 / VIEW_LOOK_DEGREES_PER_PIXEL, 0);
    view_camera_forward(&cam, after);
    assert_true(angle_degrees(before, after) < 1e-2);
}

static void test_moves(void **state)
{
    (void)state;
    for (int c = 0; c < 3; ++c) {
        view_camera cam;
        view_camera_init(&cam, &cameras[c], 3);
        float forward[3], start[3], step[3];
        view_camera_forward(&cam, forward);
        memcpy(start, cam.position, sizeof start);
        /* W for half a second: speed * seconds along the view. */
        view_camera_move(&cam, 1, 0, 0, 0.5f);
        for (int i = 0; i < 3; ++i)
            step[i] = cam.position[i] - start[i];
        assert_true(fabs(sqrt(dot(step, step)) - 1.5) < 1e-4);
        assert_true(angle_degrees(step, forward) < 1e-2);
        /* D: to the picture's right, level with the horizon. */
        float right[3];
        cross(forward, cam.up, right);
        memcpy(start, cam.position, sizeof start);
        view_camera_move(&cam, 0, 1, 0, 1);
        for (int i = 0; i < 3; ++i)
            step[i] = cam.position[i] - start[i];
        assert_true(angle_degrees(step, right) < 1e-2);
        assert_true(fabs(dot(step, cam.up)) < 1e-4);
        /* E: along the world up, whatever the pitch. */
        memcpy(start, cam.position, sizeof start);
        view_camera_move(&cam, 0, 0, 1, 1);
        for (int i = 0; i < 3; ++i)
            step[i] = cam.position[i] - start[i];
        assert_true(angle_degrees(step, cam.up) < 1e-2);
        /* W and D together are no faster than one of them. */
        memcpy(start, cam.position, sizeof start);
        view_camera_move(&cam, 1, 1, 0, 1);
        for (int i = 0; i < 3; ++i)
            step[i] = cam.position[i] - start[i];
        assert_true(fabs(sqrt(dot(step, step)) - 3) < 1e-3);
        /* The view direction never changes by moving. */
        float after[3];
        view_camera_forward(&cam, after);
        assert_true(angle_degrees(after, forward) < 1e-4);
    }
}

static void test_speed_steps(void **state)
{
    (void)state;
    view_camera cam;
    view_camera_init(&cam, &cameras[0], 8);
    view_camera_scale_speed(&cam, 4);
    assert_true(fabsf(cam.speed - 16) < 1e-4f);
    view_camera_scale_speed(&cam, -8);
    assert_true(fabsf(cam.speed - 4) < 1e-4f);
    float lo[3] = {0, 0, 0}, hi[3] = {3, 4, 0}, point[3] = {1, 1, 1};
    assert_true(fabsf(view_camera_default_speed(lo, hi) - 0.5f) < 1e-6f);
    assert_true(view_camera_default_speed(point, point) == 1.0f);
}

/* Every corner of the box projects inside the picture, and the bounding sphere touches the
 * tighter edge: the whole scene and not much more. */
static void check_framed(const view_camera *cam, const float lo[3], const float hi[3], float aspect)
{
    vkrt_config_camera c;
    view_camera_to_config(cam, &c);
    float forward[3], right[3], up[3];
    view_direction(&c, forward);
    cross(forward, c.up, right);
    normalize(right);
    cross(right, forward, up);
    double tan_v = tan(c.fov_deg * M_PI / 360), tan_h = tan_v * aspect;
    for (int corner = 0; corner < 8; ++corner) {
        float p[3], to[3];
        for (int i = 0; i < 3; ++i) {
            p[i] = (corner >> i & 1) ? hi[i] : lo[i];
            to[i] = p[i] - c.eye[i];
        }
        double z = dot(to, forward);
        assert_true(z > 0);
        assert_true(fabs(dot(to, right)) / z <= tan_h * (1 + 1e-5));
        assert_true(fabs(dot(to, up)) / z <= tan_v * (1 + 1e-5));
    }
    /* The camera looks at the centre, from where the sphere fits the tighter angle exactly. */
    float centre[3], diagonal[3], to_centre[3];
    for (int i = 0; i < 3; ++i) {
        centre[i] = 0.5f * (lo[i] + hi[i]);
        diagonal[i] = hi[i] - lo[i];
        to_centre[i] = centre[i] - c.eye[i];
    }
    double radius = 0.5 * sqrt(dot(diagonal, diagonal));
    if (radius == 0)
        radius = 1;
    double half = fmin(atan(tan_v), atan(tan_h));
    assert_true(angle_degrees(to_centre, forward) < 1e-3);
    assert_true(fabs(sqrt(dot(to_centre, to_centre)) - radius / sin(half)) <
                1e-5 * radius / sin(half));
}

static void test_frame_the_scene(void **state)
{
    (void)state;
    const float lo[3] = {-20, -1, -9}, hi[3] = {18, 15, 9};
    for (int c = 0; c < 3; ++c) {
        float aspects[] = {1, 16.0f / 9, 0.5f};
        for (int a = 0; a < 3; ++a) {
            view_camera cam;
            view_camera_init(&cam, &cameras[c], 1);
            view_camera_look(&cam, 37, 11);
            float before[3], after[3];
            view_camera_forward(&cam, before);
            view_camera_frame(&cam, lo, hi, aspects[a]);
            view_camera_forward(&cam, after);
            assert_true(angle_degrees(before, after) < 1e-4); /* F keeps the direction */
            check_framed(&cam, lo, hi, aspects[a]);
        }
    }
    /* A flat box and an empty one (a scene of one point). */
    const float flat_lo[3] = {0, 0, 0}, flat_hi[3] = {10, 0, 10}, point[3] = {5, 5, 5};
    view_camera cam;
    view_camera_init(&cam, &cameras[1], 1);
    view_camera_frame(&cam, flat_lo, flat_hi, 1.5f);
    check_framed(&cam, flat_lo, flat_hi, 1.5f);
    view_camera_frame(&cam, point, point, 1.5f);
    check_framed(&cam, point, point, 1.5f);
}

/* The printed line, read by the scene.cfg parser, is the traced camera bit for bit: the
 * flythrough a user records renders exactly what the viewer showed. */
static void test_camera_line_reads_back_exactly(void **state)
{
    (void)state;
    for (int c = 0; c < 4; ++c) {
        view_camera cam;
        view_camera_init(&cam, c < 3 ? &cameras[c] : &ortho_camera, 1.37f);
        for (int step = 0; step < 4; ++step) {
            view_camera_look(&cam, 13.3f * step - 7, 3.1f - step);
            view_camera_move(&cam, 1, step & 1 ? 1.0f : -1.0f, step == 2, 0.731f);
            char line[512], text[700];
            vkrt_error err = {{0}};
            assert_true(view_camera_format(&cam, line, sizeof line, &err));
            snprintf(text, sizeof text, "geometry x.obj\n%s\n", line);
            vkrt_config cfg;
            assert_true(vkrt_config_parse(text, strlen(text), "t.cfg", "", &cfg, &err));
            vkrt_config_camera traced;
            view_camera_to_config(&cam, &traced);
            traced.line = cfg.cameras[0].line;
            assert_memory_equal(&cfg.cameras[0], &traced, sizeof traced);
            vkrt_config_free(&cfg);
        }
    }
    view_camera cam;
    view_camera_init(&cam, &cameras[0], 1);
    char tiny[16];
    vkrt_error err = {{0}};
    assert_false(view_camera_format(&cam, tiny, sizeof tiny, &err));
    assert_non_null(strstr(err.msg, "bytes"));
}

/* F with an orthographic camera: the direction kept, every corner of the box in front of the
 * image plane and inside the view, whose width fits the bounding sphere on the tighter side. */
static void test_frame_the_scene_orthographic(void **state)
{
    (void)state;
    const float lo[3] = {-20, -1, -9}, hi[3] = {18, 15, 9};
    double radius = 0.5 * sqrt(38.0 * 38 + 16 * 16 + 18 * 18);
    float aspects[] = {1, 16.0f / 9, 0.5f};
    for (int a = 0; a < 3; ++a) {
        view_camera cam;
        view_camera_init(&cam, &ortho_camera, 1);
        view_camera_look(&cam, 37, 11);
        float before[3], forward[3], right[3], up[3];
        view_camera_forward(&cam, before);
        view_camera_frame(&cam, lo, hi, aspects[a]);
        vkrt_config_camera c;
        view_camera_to_config(&cam, &c);
        view_direction(&c, forward);
        assert_true(angle_degrees(before, forward) < 1e-4);
        double width = 2 * radius * fmax(1, aspects[a]);
        assert_true(fabs(c.ortho_width - width) < 1e-5 * width);
        cross(forward, c.up, right);
        normalize(right);
        cross(right, forward, up);
        for (int corner = 0; corner < 8; ++corner) {
            float to[3];
            for (int i = 0; i < 3; ++i)
                to[i] = ((corner >> i & 1) ? hi[i] : lo[i]) - c.eye[i];
            assert_true(dot(to, forward) > 0);
            assert_true(fabs(dot(to, right)) <= 0.5 * c.ortho_width * (1 + 1e-5));
            assert_true(fabs(dot(to, up)) <= 0.5 * c.ortho_width / aspects[a] * (1 + 1e-5));
        }
    }
}

static void test_reset_by_init(void **state)
{
    (void)state;
    view_camera cam;
    view_camera_init(&cam, &cameras[2], 5);
    view_camera_look(&cam, 50, 50);
    view_camera_move(&cam, 1, 1, 1, 2);
    view_camera_init(&cam, &cameras[2], cam.speed);
    vkrt_config_camera out;
    view_camera_to_config(&cam, &out);
    assert_memory_equal(&out, &cameras[2], sizeof out);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_init_keeps_the_scene_camera),
        cmocka_unit_test(test_a_moved_camera_writes_its_frame),
        cmocka_unit_test(test_drag_right_turns_right_and_down_looks_down),
        cmocka_unit_test(test_pitch_stops_short_of_straight_up),
        cmocka_unit_test(test_full_turn_comes_back),
        cmocka_unit_test(test_moves),
        cmocka_unit_test(test_speed_steps),
        cmocka_unit_test(test_frame_the_scene),
        cmocka_unit_test(test_frame_the_scene_orthographic),
        cmocka_unit_test(test_camera_line_reads_back_exactly),
        cmocka_unit_test(test_reset_by_init),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
