/*
 * camera.h: the viewer's fly camera, as plain math: no window, no Vulkan, so tests can drive it.
 *
 * The camera keeps a position, a yaw and a pitch around the scene camera's `up` (the world up),
 * a field of view and a speed. Yaw 0 and pitch 0 look along the scene camera's view direction
 * flattened onto the horizon, so the camera a scene.cfg names comes back unchanged (to float
 * rounding) from view_camera_init and view_camera_to_config.
 */
#ifndef VKRT_VIEW_CAMERA_H
#define VKRT_VIEW_CAMERA_H

#include <stdbool.h>
#include <stddef.h>

#include "../error.h"
#include "../scene/config.h"

typedef struct view_camera {
    float position[3];
    float yaw, pitch;          /* radians: yaw turns right around up, pitch looks up */
    float up[3];               /* the world up, unit length */
    float ahead[3], right[3];  /* the horizon's frame at yaw 0: unit, perpendicular to up */
    float fov_deg;             /* vertical field of view (perspective) */
    float ortho_width;         /* > 0: orthographic, the view's width in scene units; 0: perspective */
    float look_distance;       /* how far ahead `look` is put when the camera is written out */
    float speed;               /* scene units per second */
    float pitch_limit;         /* radians; VIEW_PITCH_LIMIT_DEGREES or the scene camera's pitch */
    vkrt_config_camera scene;  /* the scene camera it started from */
    bool moved;                /* false: view_camera_to_config gives `scene` itself, bit for bit */
} view_camera;

/* Degrees of turn per pixel of mouse drag. */
#define VIEW_LOOK_DEGREES_PER_PIXEL 0.15f
/* The pitch stops this close to straight up or down, where yaw would lose its meaning. */
#define VIEW_PITCH_LIMIT_DEGREES 89.0f

/* Sets the camera to a scene camera (a valid one: eye != look, up not parallel to the view) and
 * the speed to speed (scene units per second). Also what R (reset) does. */
void view_camera_init(view_camera *cam, const vkrt_config_camera *scene_camera, float speed);

/* The unit view direction. */
void view_camera_forward(const view_camera *cam, float forward[3]);

/* The camera as a scene.cfg camera: eye = position, look = eye + look_distance * forward, up the
 * world up; until the camera moves or turns, the scene camera itself. What the renderer traces,
 * and what view_camera_format writes. */
void view_camera_to_config(const view_camera *cam, vkrt_config_camera *out);

/* Turns the camera by a mouse drag of dx, dy pixels (right and down positive, as windows count):
 * dragging right turns right, dragging down looks down. The pitch stays within the limit (or
 * within the scene camera's own pitch, when that was steeper). */
void view_camera_look(view_camera *cam, float dx_pixels, float dy_pixels);

/* Moves the camera by seconds * speed along its view direction (forward, negative is back), its
 * right (right) and the world up (up); each of forward, right, up is -1, 0 or 1 (a key held), and
 * a diagonal is not faster than a straight move. */
void view_camera_move(view_camera *cam, float forward, float right, float up, float seconds);

/* Multiplies the speed by 2^(steps / 4): four scroll clicks or +/- presses double it. */
void view_camera_scale_speed(view_camera *cam, float steps);

/* Keeps the view direction and moves the camera back from the centre of the box [lo, hi] until
 * the box's bounding sphere (radius half its diagonal, or 1 when that is 0) fits the view, both
 * the vertical fov and the horizontal one of aspect = width / height; look_distance becomes the
 * distance to the centre. An orthographic camera instead steps back by the radius (the sphere
 * wholly in front of its image plane) and takes the width at which the sphere fits: 2 radius
 * times the larger of 1 and aspect. */
void view_camera_frame(view_camera *cam, const float lo[3], const float hi[3], float aspect);

/* A default speed for a scene whose geometry spans [lo, hi]: a tenth of its diagonal per second. */
float view_camera_default_speed(const float lo[3], const float hi[3]);

/* Writes the camera as a scene.cfg line, "camera eye X Y Z look X Y Z up X Y Z fov F" (or
 * "ortho W" in place of "fov F" for an orthographic camera; no newline), with every number
 * printed so that it reads back as the same float. Returns false with err set when size is too
 * small. */
bool view_camera_format(const view_camera *cam, char *out, size_t size, vkrt_error *err);

#endif
