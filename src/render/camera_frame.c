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

/* The thin lens (raygen.comp): its radius in right.w, the distance in focus in up.w. */
static void set_lens(const vkrt_config_camera *camera, FrameParams *params)
{
    if (camera->aperture > 0.0f) {
        float d[3] = {camera->look[0] - camera->eye[0], camera->look[1] - camera->eye[1],
                      camera->look[2] - camera->eye[2]};
        params->right.w = camera->aperture;
        params->up.w = camera->focus > 0.0f ? camera->focus
                                            : sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    }
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
    float aspect = (float)width / (float)height;
    params->eye = (vec4){camera->eye[0], camera->eye[1], camera->eye[2], 0};
    params->forward = (vec4){forward[0], forward[1], forward[2], 0};
    if (camera->ortho_width > 0.0f) {
        /* Orthographic: right and up span half the view in scene units, and forward.w says so
         * (raygen.comp). Square pixels: the height is the width over the aspect. */
        float half_width = 0.5f * camera->ortho_width, half_height = half_width / aspect;
        params->forward.w = 1.0f;
        params->right = (vec4){right[0] * half_width, right[1] * half_width,
                               right[2] * half_width, 0};
        params->up = (vec4){up[0] * half_height, up[1] * half_height, up[2] * half_height, 0};
        set_lens(camera, params);
        return;
    }
    float tan_half = tanf(radians(camera->fov_deg) * 0.5f);
    params->right = (vec4){right[0] * tan_half * aspect, right[1] * tan_half * aspect,
                           right[2] * tan_half * aspect, 0};
    params->up = (vec4){up[0] * tan_half, up[1] * tan_half, up[2] * tan_half, 0};
    set_lens(camera, params);
}

/* The rotation of a camera's frame as a unit quaternion (w, x, y, z): the matrix whose columns
 * are right, up and -forward (Shepperd's method, from the largest of the four candidates). */
static void frame_quaternion(const float right[3], const float up[3], const float back[3],
                             double q[4])
{
    double m[3][3] = {{right[0], up[0], back[0]}, {right[1], up[1], back[1]},
                      {right[2], up[2], back[2]}};
    double trace = m[0][0] + m[1][1] + m[2][2];
    if (trace > 0) {
        double s = 2 * sqrt(1 + trace);
        q[0] = s / 4;
        q[1] = (m[2][1] - m[1][2]) / s;
        q[2] = (m[0][2] - m[2][0]) / s;
        q[3] = (m[1][0] - m[0][1]) / s;
    } else if (m[0][0] > m[1][1] && m[0][0] > m[2][2]) {
        double s = 2 * sqrt(1 + m[0][0] - m[1][1] - m[2][2]);
        q[0] = (m[2][1] - m[1][2]) / s;
        q[1] = s / 4;
        q[2] = (m[0][1] + m[1][0]) / s;
        q[3] = (m[0][2] + m[2][0]) / s;
    } else if (m[1][1] > m[2][2]) {
        double s = 2 * sqrt(1 + m[1][1] - m[0][0] - m[2][2]);
        q[0] = (m[0][2] - m[2][0]) / s;
        q[1] = (m[0][1] + m[1][0]) / s;
        q[2] = s / 4;
        q[3] = (m[1][2] + m[2][1]) / s;
    } else {
        double s = 2 * sqrt(1 + m[2][2] - m[0][0] - m[1][1]);
        q[0] = (m[1][0] - m[0][1]) / s;
        q[1] = (m[0][2] + m[2][0]) / s;
        q[2] = (m[1][2] + m[2][1]) / s;
        q[3] = s / 4;
    }
}

/* A camera's right, up and forward, unit and orthogonal, as vkrt_camera_params builds them. */
static void camera_basis(const vkrt_config_camera *c, float right[3], float up[3],
                         float forward[3])
{
    for (int i = 0; i < 3; ++i)
        forward[i] = c->look[i] - c->eye[i];
    normalize3(forward);
    float given_up[3] = {c->up[0], c->up[1], c->up[2]};
    normalize3(given_up);
    cross3(forward, given_up, right);
    normalize3(right);
    cross3(right, forward, up);
}

void vkrt_camera_between(const vkrt_config_camera *a, const vkrt_config_camera *b, float t,
                         vkrt_config_camera *out)
{
    *out = *a;
    float ra[3], ua[3], fa[3], rb[3], ub[3], fb[3];
    camera_basis(a, ra, ua, fa);
    camera_basis(b, rb, ub, fb);
    float ba[3] = {-fa[0], -fa[1], -fa[2]}, bb[3] = {-fb[0], -fb[1], -fb[2]};
    double qa[4], qb[4], q[4];
    frame_quaternion(ra, ua, ba, qa);
    frame_quaternion(rb, ub, bb, qb);
    /* Slerp along the shorter arc (q and -q are one rotation); nlerp where they nearly agree,
     * where slerp's sin(angle) would divide by almost 0. */
    double dot = qa[0] * qb[0] + qa[1] * qb[1] + qa[2] * qb[2] + qa[3] * qb[3];
    double sign = dot < 0 ? -1 : 1;
    dot *= sign;
    double wa = 1 - t, wb = t;
    if (dot < 0.9995) {
        double angle = acos(dot);
        wa = sin((1 - t) * angle) / sin(angle);
        wb = sin(t * angle) / sin(angle);
    }
    double len = 0;
    for (int i = 0; i < 4; ++i) {
        q[i] = wa * qa[i] + wb * sign * qb[i];
        len += q[i] * q[i];
    }
    len = sqrt(len);
    double w = q[0] / len, x = q[1] / len, y = q[2] / len, z = q[3] / len;
    /* The rotated frame's up (column 1) and -forward (column 2). */
    double up[3] = {2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x)};
    double back[3] = {2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)};
    for (int i = 0; i < 3; ++i) {
        out->eye[i] = (1 - t) * a->eye[i] + t * b->eye[i];
        out->look[i] = out->eye[i] - (float)back[i];
        out->up[i] = (float)up[i];
    }
    /* The projection is a's; its size moves towards b's where b has the same projection (a
     * perspective camera's fov, an orthographic one's width), and stays a's where it has not. */
    bool a_ortho = a->ortho_width > 0, b_ortho = b->ortho_width > 0;
    if (!a_ortho && !b_ortho)
        out->fov_deg = (1 - t) * a->fov_deg + t * b->fov_deg;
    else if (a_ortho && b_ortho)
        out->ortho_width = (1 - t) * a->ortho_width + t * b->ortho_width;
    /* look is now one unit ahead: the focus distance that defaulted to |look - eye| is kept. */
    if (a->aperture > 0 && !(a->focus > 0)) {
        float da = 0, db = 0;
        for (int i = 0; i < 3; ++i) {
            da += (a->look[i] - a->eye[i]) * (a->look[i] - a->eye[i]);
            db += (b->look[i] - b->eye[i]) * (b->look[i] - b->eye[i]);
        }
        out->focus = (1 - t) * sqrtf(da) + t * sqrtf(db);
    }
}
