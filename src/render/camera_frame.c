/*
 * camera_frame.c: a camera's frame for raygen.comp (see camera_frame.h).
 */
#include "camera_frame.h"

#include <math.h>

#include "../../glsl/shared.h"

static float radians(float degrees)
{
    return degrees * 3.14159265358979f / 180.0f;
}

/* In double: the square of a finite float's component may not be a finite float (an up of
 * 0 1e30 0 gave a zero length's inverse and a picture of NaNs). */
static void normalize3(float v[3])
{
    double len = sqrt((double)v[0] * v[0] + (double)v[1] * v[1] + (double)v[2] * v[2]);
    for (int i = 0; i < 3; ++i)
        v[i] = (float)(v[i] / len);
}

static void cross3(const float a[3], const float b[3], float out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

/* Camera basis of a right-handed camera looking down -z in its own space: right = forward x up. */
void vkrt_camera_params(const vkrt_config_camera *camera, uint32_t width, uint32_t height,
                        FrameParams *params)
{
    float forward[3] = {camera->look[0] - camera->eye[0], camera->look[1] - camera->eye[1],
                        camera->look[2] - camera->eye[2]};
    normalize3(forward);
    float given_up[3] = {camera->up[0], camera->up[1], camera->up[2]};
    normalize3(given_up); /* so that the cross product below stays finite too */
    float right[3], up[3];
    cross3(forward, given_up, right);
    normalize3(right);
    cross3(right, forward, up);
    float tan_half = tanf(radians(camera->fov_deg) * 0.5f);
    float aspect = (float)width / (float)height;
    params->eye = (vec4){camera->eye[0], camera->eye[1], camera->eye[2], 0};
    params->forward = (vec4){forward[0], forward[1], forward[2], 0};
    params->right = (vec4){right[0] * tan_half * aspect, right[1] * tan_half * aspect,
                           right[2] * tan_half * aspect, 0};
    params->up = (vec4){up[0] * tan_half, up[1] * tan_half, up[2] * tan_half, 0};
    /* The thin lens (raygen.comp): its radius in right.w, the distance in focus in up.w. */
    if (camera->aperture > 0.0f) {
        float d[3] = {camera->look[0] - camera->eye[0], camera->look[1] - camera->eye[1],
                      camera->look[2] - camera->eye[2]};
        params->right.w = camera->aperture;
        params->up.w = camera->focus > 0.0f ? camera->focus
                                            : sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    }
}
