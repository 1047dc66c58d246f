/*
 * camera.c: the viewer's fly camera (see camera.h).
 *
 * Orientation is yaw and pitch rather than a free rotation: a flythrough keeps the horizon level,
 * and two angles cannot drift into a roll the way accumulated rotations do.
 */
#include "camera.h"

#include <math.h>
#include <stdio.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static float radians(float degrees)
{
    return degrees * (float)(M_PI / 180.0);
}

static float dot3(const float a[3], const float b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross3(const float a[3], const float b[3], float out[3])
{
    float x = a[1] * b[2] - a[2] * b[1];
    float y = a[2] * b[0] - a[0] * b[2];
    float z = a[0] * b[1] - a[1] * b[0];
    out[0] = x;
    out[1] = y;
    out[2] = z;
}

/* Scales v to unit length; returns its length before (0 leaves v as it was). */
static float normalize3(float v[3])
{
    float length = sqrtf(dot3(v, v));
    if (length > 0)
        for (int i = 0; i < 3; ++i)
            v[i] /= length;
    return length;
}

void view_camera_init(view_camera *cam, const vkrt_config_camera *scene_camera, float speed)
{
    *cam = (view_camera){.fov_deg = scene_camera->fov_deg,
                         .ortho_width = scene_camera->ortho_width,
                         .speed = speed,
                         .scene = *scene_camera};
    float view[3];
    for (int i = 0; i < 3; ++i) {
        cam->position[i] = scene_camera->eye[i];
        cam->up[i] = scene_camera->up[i];
        view[i] = scene_camera->look[i] - scene_camera->eye[i];
    }
    normalize3(cam->up);
    cam->look_distance = normalize3(view);
    /* The horizon's frame: the view direction without its up part, and the right of it, as the
     * renderer's camera takes it (right = forward x up). */
    float height = dot3(view, cam->up);
    for (int i = 0; i < 3; ++i)
        cam->ahead[i] = view[i] - height * cam->up[i];
    normalize3(cam->ahead);
    cross3(cam->ahead, cam->up, cam->right);
    normalize3(cam->right);
    cam->pitch = asinf(fmaxf(-1.0f, fminf(1.0f, height)));
    cam->pitch_limit = fmaxf(radians(VIEW_PITCH_LIMIT_DEGREES), fabsf(cam->pitch));
}

/* The horizontal unit directions at the camera's yaw: ahead and to the right. */
static void horizon(const view_camera *cam, float ahead[3], float right[3])
{
    float c = cosf(cam->yaw), s = sinf(cam->yaw);
    for (int i = 0; i < 3; ++i) {
        ahead[i] = c * cam->ahead[i] + s * cam->right[i];
        right[i] = c * cam->right[i] - s * cam->ahead[i];
    }
}

void view_camera_forward(const view_camera *cam, float forward[3])
{
    float ahead[3], right[3];
    horizon(cam, ahead, right);
    float c = cosf(cam->pitch), s = sinf(cam->pitch);
    for (int i = 0; i < 3; ++i)
        forward[i] = c * ahead[i] + s * cam->up[i];
    normalize3(forward);
}

void view_camera_to_config(const view_camera *cam, vkrt_config_camera *out)
{
    if (!cam->moved) {
        *out = cam->scene;
        return;
    }
    float forward[3];
    view_camera_forward(cam, forward);
    /* One projection: an orthographic camera's fov is unused, and written as the parser reads
     * an `ortho` line (0). */
    *out = (vkrt_config_camera){.fov_deg = cam->ortho_width > 0 ? 0 : cam->fov_deg,
                                .ortho_width = cam->ortho_width,
                                .line = cam->scene.line};
    for (int i = 0; i < 3; ++i) {
        out->eye[i] = cam->position[i];
        out->look[i] = cam->position[i] + cam->look_distance * forward[i];
        out->up[i] = cam->up[i];
    }
}

void view_camera_look(view_camera *cam, float dx_pixels, float dy_pixels)
{
    if (dx_pixels == 0 && dy_pixels == 0)
        return;
    float per_pixel = radians(VIEW_LOOK_DEGREES_PER_PIXEL);
    cam->yaw = fmodf(cam->yaw + dx_pixels * per_pixel, (float)(2 * M_PI));
    float pitch = cam->pitch - dy_pixels * per_pixel;
    cam->pitch = fmaxf(-cam->pitch_limit, fminf(cam->pitch_limit, pitch));
    cam->moved = true;
}

void view_camera_move(view_camera *cam, float forward, float right, float up, float seconds)
{
    float f[3], ahead[3], r[3], step[3];
    view_camera_forward(cam, f);
    horizon(cam, ahead, r);
    for (int i = 0; i < 3; ++i)
        step[i] = forward * f[i] + right * r[i] + up * cam->up[i];
    if (normalize3(step) == 0 || !(seconds > 0))
        return;
    for (int i = 0; i < 3; ++i)
        cam->position[i] += step[i] * cam->speed * seconds;
    cam->moved = true;
}

void view_camera_scale_speed(view_camera *cam, float steps)
{
    cam->speed *= exp2f(steps / 4.0f);
}

void view_camera_frame(view_camera *cam, const float lo[3], const float hi[3], float aspect)
{
    float centre[3], diagonal[3], forward[3];
    for (int i = 0; i < 3; ++i) {
        centre[i] = 0.5f * (lo[i] + hi[i]);
        diagonal[i] = hi[i] - lo[i];
    }
    float radius = 0.5f * sqrtf(dot3(diagonal, diagonal));
    if (!(radius > 0))
        radius = 1;
    view_camera_forward(cam, forward);
    if (cam->ortho_width > 0) {
        /* Parallel rays: the distance changes nothing but what is in front of the image plane. */
        cam->ortho_width = 2 * radius * (aspect > 1 ? aspect : 1);
        for (int i = 0; i < 3; ++i)
            cam->position[i] = centre[i] - radius * forward[i];
        cam->look_distance = radius;
        cam->moved = true;
        return;
    }
    /* A sphere of radius r fits a view of half angle a from distance r / sin(a). */
    float half_vertical = 0.5f * radians(cam->fov_deg);
    float half_horizontal = atanf(tanf(half_vertical) * (aspect > 0 ? aspect : 1));
    float distance = radius / sinf(fminf(half_vertical, half_horizontal));
    for (int i = 0; i < 3; ++i)
        cam->position[i] = centre[i] - distance * forward[i];
    cam->look_distance = distance;
    cam->moved = true;
}

float view_camera_default_speed(const float lo[3], const float hi[3])
{
    float diagonal[3] = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
    float length = sqrtf(dot3(diagonal, diagonal));
    return length > 0 ? 0.1f * length : 1.0f;
}

bool view_camera_format(const view_camera *cam, char *out, size_t size, vkrt_error *err)
{
    vkrt_config_camera c;
    view_camera_to_config(cam, &c);
    /* Nine significant digits read back as the same float (IEEE 754 single precision). */
    bool ortho = c.ortho_width > 0;
    int n = snprintf(out, size,
                     "camera eye %.9g %.9g %.9g look %.9g %.9g %.9g up %.9g %.9g %.9g %s %.9g",
                     c.eye[0], c.eye[1], c.eye[2], c.look[0], c.look[1], c.look[2], c.up[0],
                     c.up[1], c.up[2], ortho ? "ortho" : "fov", ortho ? c.ortho_width : c.fov_deg);
    if (n < 0 || (size_t)n >= size)
        return vkrt_error_set(err, "a camera line needs more than %zu bytes", size);
    return true;
}
