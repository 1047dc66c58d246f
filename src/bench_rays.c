/*
 * bench_rays.c: the rays of `vkrt bench` (see bench_rays.h), apart from the command so that
 * another tracer timed against vkrt traces the very same rays.
 */
#include "bench_rays.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "../glsl/shared.h"
#include "../glsl/lib/ray_offset.glsl"
#include "render/camera_frame.h"

/* As raygen.comp's normalize, in float. */
static void normalize3(float v[3])
{
    float len = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int i = 0; i < 3; ++i)
        v[i] /= len;
}

void bench_primary_rays(const vkrt_config_camera *camera, uint32_t width, uint32_t height,
                        Ray *rays)
{
    const uint32_t tile = 8; /* TILE of raygen.comp */
    /* The renderer's camera frame: these are the rays raygen.comp makes, bit for bit. */
    FrameParams p;
    vkrt_camera_params(camera, width, height, &p);
    const float forward[3] = {p.forward.x, p.forward.y, p.forward.z};
    const float right[3] = {p.right.x, p.right.y, p.right.z};
    const float up[3] = {p.up.x, p.up.y, p.up.z};
    for (uint32_t i = 0; i < width * height; ++i) {
        /* Ray i goes through the pixel raygen.comp gives invocation i (tile_pixel there: 8x8
         * tiles in bands of 8 rows, the last ones narrower), and through its centre, as raygen
         * does for one sample per pixel; info.x is the pixel. */
        uint32_t band = i / (tile * width), in_band = i - band * tile * width;
        uint32_t rows = height - band * tile < tile ? height - band * tile : tile;
        uint32_t t = in_band / (tile * rows), in_tile = in_band - t * tile * rows;
        uint32_t cols = width - t * tile < tile ? width - t * tile : tile;
        uint32_t x = t * tile + in_tile % cols, y = band * tile + in_tile / cols;
        float sx = 2.0f * (x + 0.5f) / width - 1.0f;
        float sy = 1.0f - 2.0f * (y + 0.5f) / height;
        float d[3] = {forward[0] + sx * right[0] + sy * up[0],
                      forward[1] + sx * right[1] + sy * up[1],
                      forward[2] + sx * right[2] + sy * up[2]};
        float o[3] = {camera->eye[0], camera->eye[1], camera->eye[2]};
        if (p.forward.w != 0) { /* orthographic: parallel rays from the image plane */
            for (int k = 0; k < 3; ++k) {
                o[k] = camera->eye[k] + sx * right[k] + sy * up[k];
                d[k] = forward[k];
            }
        } else {
            normalize3(d);
        }
        rays[i] = (Ray){
            .origin = {o[0], o[1], o[2], 0},
            .direction = {d[0], d[1], d[2], 3.4e38f},
            .importance = {1, 1, 1, 0},
            .info = {y * width + x, 0, 0, 0},
        };
    }
}

/* Shadow and bounce rays leave the surface as the kernels' do (lib/ray_offset.glsl). */
static void offset_origin(const float p[3], const float n[3], float magnitude, float out[3])
{
    float step = ray_offset_distance(magnitude);
    for (int i = 0; i < 3; ++i)
        out[i] = p[i] + step * n[i];
}

/* Where shadow rays go: a point (is_point) or a direction the light travels. */
typedef struct shadow_target {
    bool is_point;
    float v[3];
} shadow_target;

static shadow_target choose_target(const vkrt_scene *scene)
{
    for (uint32_t i = 0; i < scene->light_count; ++i) {
        const vkrt_config_light *l = &scene->lights[i];
        if (l->kind == VKRT_LIGHT_POINT || l->kind == VKRT_LIGHT_SPOT)
            return (shadow_target){true, {l->position[0], l->position[1], l->position[2]}};
        if (l->kind == VKRT_LIGHT_DIRECTIONAL)
            return (shadow_target){false, {l->direction[0], l->direction[1], l->direction[2]}};
    }
    const float *lo = scene->model.bounds_min, *hi = scene->model.bounds_max;
    return (shadow_target){true,
                           {0.5f * (lo[0] + hi[0]), hi[1] + 0.5f * (hi[1] - lo[1]),
                            0.5f * (lo[2] + hi[2])}};
}

/* The hit of primary ray i: a ray origin just off the surface on the camera's side, and the unit
 * normal on that side. */
static void hit_frame(const vkrt_model *model, const uint32_t *firsts, const Ray *primary,
                      const Hit *hits, uint32_t i, float origin[3], float nrm[3])
{
    float v[9];
    vkrt_model_world_triangle(model, firsts, hits[i].triangle, v);
    float w = 1 - hits[i].u - hits[i].v, p[3], e1[3], e2[3], largest = 0, size = 0;
    for (int k = 0; k < 3; ++k) {
        p[k] = w * v[k] + hits[i].u * v[3 + k] + hits[i].v * v[6 + k];
        e1[k] = v[3 + k] - v[k];
        e2[k] = v[6 + k] - v[k];
        largest = fmaxf(largest, fmaxf(fabsf(v[k]), fmaxf(fabsf(v[3 + k]), fabsf(v[6 + k]))));
        size = fmaxf(size, fmaxf(v[k], fmaxf(v[3 + k], v[6 + k])) -
                               fminf(v[k], fminf(v[3 + k], v[6 + k])));
    }
    nrm[0] = e1[1] * e2[2] - e1[2] * e2[1];
    nrm[1] = e1[2] * e2[0] - e1[0] * e2[2];
    nrm[2] = e1[0] * e2[1] - e1[1] * e2[0];
    float len = sqrtf(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
    const float *d = &primary[i].direction.x;
    float facing = nrm[0] * d[0] + nrm[1] * d[1] + nrm[2] * d[2] > 0 ? -1.0f : 1.0f;
    for (int k = 0; k < 3; ++k)
        nrm[k] *= facing / len;
    offset_origin(p, nrm, ray_offset_magnitude(largest, size), origin);
}

/* A secondary ray's direction and length from a hit's origin and normal: towards the light
 * (shadow_direction) or a diffuse bounce (diffuse_direction); i numbers the primary ray. */
typedef void (*secondary_direction)(const shadow_target *target, uint32_t i, const float nrm[3],
                                    const float origin[3], float dir[3], float *tmax);

/* One secondary ray per primary ray that hit, in the order of the primary rays, each carrying
 * its primary ray's index; 0 when memory runs out. The hit triangles are taken into world space
 * one by one: an instanced scene is never flattened. */
static uint32_t secondary_rays(const vkrt_scene *scene, const Ray *primary, const Hit *hits,
                               uint32_t count, secondary_direction direction, Ray *out)
{
    shadow_target target = choose_target(scene);
    uint32_t *firsts = vkrt_model_instance_firsts(&scene->model);
    if (!firsts)
        return 0;
    uint32_t n = 0;
    for (uint32_t i = 0; i < count; ++i) {
        if (hits[i].triangle == VKRT_NO_HIT)
            continue;
        float origin[3], nrm[3], dir[3], tmax = 3.4e38f;
        hit_frame(&scene->model, firsts, primary, hits, i, origin, nrm);
        direction(&target, i, nrm, origin, dir, &tmax);
        out[n++] = (Ray){
            .origin = {origin[0], origin[1], origin[2], 0},
            .direction = {dir[0], dir[1], dir[2], tmax},
            .importance = {1, 1, 1, 0},
            .info = {i, 0, 0, 0},
        };
    }
    free(firsts);
    return n;
}

static void shadow_direction(const shadow_target *target, uint32_t i, const float nrm[3],
                             const float origin[3], float dir[3], float *tmax)
{
    (void)i;
    (void)nrm;
    if (target->is_point) {
        for (int k = 0; k < 3; ++k)
            dir[k] = target->v[k] - origin[k];
        *tmax = sqrtf(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
        for (int k = 0; k < 3; ++k)
            dir[k] /= *tmax;
    } else {
        for (int k = 0; k < 3; ++k)
            dir[k] = -target->v[k];
    }
}

uint32_t bench_shadow_rays(const vkrt_scene *scene, const Ray *primary, const Hit *hits,
                           uint32_t count, Ray *shadow)
{
    return secondary_rays(scene, primary, hits, count, shadow_direction, shadow);
}

/* A 32-bit hash (the low-bias finaliser of glsl/lib/rng.glsl) to a float in [0, 1). */
static float hash_float(uint32_t x)
{
    x = (x ^ (x >> 16)) * 0x7FEB352Du;
    x = (x ^ (x >> 15)) * 0x846CA68Bu;
    return (float)((x ^ (x >> 16)) >> 8) * (1.0f / 16777216.0f);
}

/* Cosine-distributed about nrm: a disc sample lifted onto the hemisphere. */
static void diffuse_direction(const shadow_target *target, uint32_t i, const float nrm[3],
                              const float origin[3], float dir[3], float *tmax)
{
    (void)target;
    (void)origin;
    (void)tmax;
    float u1 = hash_float(2 * i + 1), u2 = hash_float(2 * i + 2);
    float r = sqrtf(u1), phi = 6.28318531f * u2;
    float t[3], b[3];
    float a[3] = {fabsf(nrm[0]) > 0.5f ? 0.0f : 1.0f, fabsf(nrm[0]) > 0.5f ? 1.0f : 0.0f, 0};
    t[0] = nrm[1] * a[2] - nrm[2] * a[1];
    t[1] = nrm[2] * a[0] - nrm[0] * a[2];
    t[2] = nrm[0] * a[1] - nrm[1] * a[0];
    float tl = sqrtf(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
    for (int k = 0; k < 3; ++k)
        t[k] /= tl;
    b[0] = nrm[1] * t[2] - nrm[2] * t[1];
    b[1] = nrm[2] * t[0] - nrm[0] * t[2];
    b[2] = nrm[0] * t[1] - nrm[1] * t[0];
    float z = sqrtf(fmaxf(0.0f, 1 - u1));
    for (int k = 0; k < 3; ++k)
        dir[k] = r * cosf(phi) * t[k] + r * sinf(phi) * b[k] + z * nrm[k];
    float dl = sqrtf(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
    for (int k = 0; k < 3; ++k)
        dir[k] /= dl;
}

uint32_t bench_diffuse_rays(const vkrt_scene *scene, const Ray *primary, const Hit *hits,
                            uint32_t count, Ray *diffuse)
{
    return secondary_rays(scene, primary, hits, count, diffuse_direction, diffuse);
}
