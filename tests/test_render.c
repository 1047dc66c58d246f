/*
 * test_render.c: a whole frame on the GPU against a CPU reference written independently here.
 *
 * The reference shares nothing with the kernels: it intersects with Moller-Trumbore in double
 * precision, offsets shadow rays by a fixed relative epsilon, and evaluates the lights from their
 * closed-form definitions (docs/scene-format.md). The GPU renders the same scene through the real
 * renderer (vkrt_renderer) at one sample per pixel, the pixel centre.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#include "../glsl/shared.h"
#include "gpu_fixture.h"
#include "render/camera_frame.h"
#include "render/renderer.h"
#include "scene/scene.h"

typedef struct d3 {
    double x, y, z;
} d3;

static d3 make(double x, double y, double z) { return (d3){x, y, z}; }
static d3 add(d3 a, d3 b) { return make(a.x + b.x, a.y + b.y, a.z + b.z); }
static d3 sub(d3 a, d3 b) { return make(a.x - b.x, a.y - b.y, a.z - b.z); }
static d3 scale(d3 a, double s) { return make(a.x * s, a.y * s, a.z * s); }
static double dot(d3 a, d3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static d3 cross(d3 a, d3 b)
{
    return make(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static d3 normalize(d3 a) { return scale(a, 1.0 / sqrt(dot(a, a))); }
static d3 from_floats(const float *f) { return make(f[0], f[1], f[2]); }

/* Moller and Trumbore 1997, in double precision. */
static bool intersect(d3 o, d3 d, const float *tri, double tmin, double tmax, double *t)
{
    d3 v0 = from_floats(tri), e1 = sub(from_floats(tri + 3), v0), e2 = sub(from_floats(tri + 6), v0);
    d3 p = cross(d, e2);
    double det = dot(e1, p);
    if (det == 0)
        return false;
    double inv = 1.0 / det;
    d3 s = sub(o, v0);
    double u = dot(s, p) * inv;
    if (u < 0 || u > 1)
        return false;
    d3 q = cross(s, e1);
    double v = dot(d, q) * inv;
    if (v < 0 || u + v > 1)
        return false;
    double hit = dot(e2, q) * inv;
    if (!(hit > tmin && hit < tmax))
        return false;
    *t = hit;
    return true;
}

static int64_t closest(const vkrt_mesh *mesh, d3 o, d3 d, double *t_out)
{
    int64_t best = -1;
    double best_t = INFINITY;
    for (uint32_t i = 0; i < mesh->triangle_count; ++i) {
        double t;
        if (intersect(o, d, mesh->positions + 9 * (size_t)i, 0, best_t, &t)) {
            best_t = t;
            best = i;
        }
    }
    *t_out = best_t;
    return best;
}

static bool occluded(const vkrt_mesh *mesh, d3 o, d3 d, double tmax)
{
    for (uint32_t i = 0; i < mesh->triangle_count; ++i) {
        double t;
        if (intersect(o, d, mesh->positions + 9 * (size_t)i, 0, tmax, &t))
            return true;
    }
    return false;
}

/* Fresnel reflectance of unpolarised light from index n1 into n2 at cos_i; 1 past the critical
 * angle. */
static double fresnel(double cos_i, double n1, double n2)
{
    double sin_t = n1 / n2 * sqrt(fmax(0, 1 - cos_i * cos_i));
    if (sin_t >= 1)
        return 1;
    double cos_t = sqrt(1 - sin_t * sin_t);
    double rs = (n1 * cos_i - n2 * cos_t) / (n1 * cos_i + n2 * cos_t);
    double rp = (n1 * cos_t - n2 * cos_i) / (n1 * cos_t + n2 * cos_i);
    return 0.5 * (rs * rs + rp * rp);
}

static d3 mul(d3 a, d3 b) { return make(a.x * b.x, a.y * b.y, a.z * b.z); }
static double largest(d3 a) { return fmax(a.x, fmax(a.y, a.z)); }

/* The importance under which the renderer drops a cast ray (tuning.c, default_min_importance). */
static const double min_importance = 1e-3;

/* Radiance along the ray o + t d, as docs/materials.md defines the built-ins (no vn in these
 * scenes, so normals are the triangles' own): Lambert lit by the lights for diffuse surfaces
 * (.mtl illum 0-2), plus a reflection weighted Ks for mirrors (illum 3, 5: the mirror family),
 * Fresnel-weighted reflection and refraction for glass (illum 4, 6, 7: the smooth dielectric).
 * depth counts bounces left; importance is the ray's throughput, for the renderer's threshold. */
static d3 shade(const vkrt_scene *scene, d3 o, d3 d, int depth, d3 importance)
{
    const vkrt_config *cfg = &scene->config;
    const vkrt_mesh *mesh = &scene->model.meshes[0]; /* one identity instance */
    double t;
    int64_t tri = closest(mesh, o, d, &t);
    if (tri < 0)
        return from_floats(cfg->environment);
    const float *v = mesh->positions + 9 * tri;
    d3 p = add(o, scale(d, t));
    d3 n = normalize(cross(sub(from_floats(v + 3), from_floats(v)), sub(from_floats(v + 6), from_floats(v))));
    bool front = dot(n, d) < 0;
    if (!front)
        n = scale(n, -1);
    int32_t m = mesh->material[tri];
    const vkrt_material *mtl = m < 0 ? NULL : &scene->model.materials[m];
    vkrt_bsdf bsdf = mtl ? mtl->bsdf : VKRT_BSDF_DIFFUSE;
    /* A fixed relative epsilon: enough for this scene of unit-scale numbers in the hundreds. */
    double extent = fmax(fmax(fabs(p.x), fabs(p.y)), fmax(fabs(p.z), 1.0));
    double eps = 1e-4 * extent;
    d3 sum = make(0, 0, 0);
    if (bsdf == VKRT_BSDF_DIELECTRIC) {
        double ni = mtl->ior > 0 ? mtl->ior : 1.5;
        double n1 = front ? 1 : ni, n2 = front ? ni : 1;
        double cos_i = -dot(d, n);
        double r = fresnel(cos_i, n1, n2);
        if (depth > 0) {
            d3 refl = add(d, scale(n, 2 * cos_i));
            d3 w = scale(importance, r);
            if (largest(w) >= min_importance)
                sum = add(sum, scale(shade(scene, add(p, scale(n, eps)), refl, depth - 1, w), r));
            if (r < 1) {
                double eta = n1 / n2, k = 1 - eta * eta * (1 - cos_i * cos_i);
                d3 refr = normalize(add(scale(d, eta), scale(n, eta * cos_i - sqrt(k))));
                w = scale(importance, 1 - r);
                if (largest(w) >= min_importance)
                    sum = add(sum, scale(shade(scene, sub(p, scale(n, eps)), refr, depth - 1, w), 1 - r));
            }
        }
        return sum;
    }
    d3 kd = mtl ? from_floats(mtl->base_colour) : make(0.8, 0.8, 0.8);
    d3 origin = add(p, scale(n, eps));
    for (uint32_t i = 0; i < cfg->light_count; ++i) {
        const vkrt_config_light *l = &cfg->lights[i];
        d3 colour = from_floats(l->colour);
        if (l->kind == VKRT_LIGHT_AMBIENT) {
            sum = add(sum, mul(kd, colour));
            continue;
        }
        d3 wi;
        double dist = INFINITY;
        d3 e = colour;
        if (l->kind == VKRT_LIGHT_DIRECTIONAL) {
            wi = scale(normalize(from_floats(l->direction)), -1);
        } else {
            d3 to = sub(from_floats(l->position), p);
            dist = sqrt(dot(to, to));
            wi = scale(to, 1 / dist);
            e = scale(colour, 1 / (dist * dist));
            if (l->kind == VKRT_LIGHT_SPOT) {
                double cutoff = l->half_angle_deg * M_PI / 180, beam = 0.75 * cutoff;
                double angle = acos(fmin(1, fmax(-1, -dot(wi, normalize(from_floats(l->direction))))));
                double falloff = angle >= cutoff ? 0 : angle <= beam ? 1 : (cutoff - angle) / (cutoff - beam);
                e = scale(e, falloff);
            }
        }
        double cos_theta = dot(n, wi);
        if (cos_theta <= 0 || (e.x == 0 && e.y == 0 && e.z == 0))
            continue;
        if (occluded(mesh, origin, wi, dist))
            continue;
        sum = add(sum, mul(kd, scale(e, cos_theta / M_PI)));
    }
    if (bsdf == VKRT_BSDF_MIRROR && depth > 0) {
        d3 ks = from_floats(mtl->specular);
        d3 w = mul(importance, ks);
        if (largest(w) >= min_importance) {
            d3 refl = add(d, scale(n, -2 * dot(d, n)));
            sum = add(sum, mul(ks, shade(scene, origin, refl, depth - 1, w)));
        }
    }
    return sum;
}

/* Pixel centres through the camera of scene.cfg's definition: vertical fov, row 0 on top; or,
 * orthographic, parallel rays along the view from the plane through the eye, ortho_width wide
 * with square pixels. */
static void reference_render(const vkrt_scene *scene, uint32_t w, uint32_t h, float *rgb)
{
    const vkrt_config_camera *cam = &scene->cameras[0];
    d3 eye = from_floats(cam->eye);
    d3 forward = normalize(sub(from_floats(cam->look), eye));
    d3 right = normalize(cross(forward, from_floats(cam->up)));
    d3 up = cross(right, forward);
    bool ortho = cam->ortho_width > 0;
    double aspect = (double)w / h;
    double half_height = ortho ? cam->ortho_width / (2 * aspect) : tan(cam->fov_deg * M_PI / 360);
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
            double sx = (2 * (x + 0.5) / w - 1) * half_height * aspect;
            double sy = (1 - 2 * (y + 0.5) / h) * half_height;
            d3 across = add(scale(right, sx), scale(up, sy));
            d3 o = ortho ? add(eye, across) : eye;
            d3 d = ortho ? forward : normalize(add(forward, across));
            d3 c = shade(scene, o, d, (int)scene->config.max_depth, make(1, 1, 1));
            float *out = rgb + 3 * ((size_t)y * w + x);
            out[0] = (float)c.x;
            out[1] = (float)c.y;
            out[2] = (float)c.z;
        }
}

static void gpu_render(const vkrt_scene *scene, uint32_t w, uint32_t h, float *rgb)
{
    fixture_render(scene, &(vkrt_render_desc){.width = w, .height = h, .samples = 1}, rgb, NULL);
}

/* Renders the scene both ways at 64x64 and compares every pixel. */
static void compare_with_reference(const char *cfg_path)
{
    enum { W = 64, H = 64 };
    vkrt_scene scene;
    vkrt_error err = {{0}};
    if (!vkrt_scene_load(cfg_path, &scene, &err))
        fail_msg("%s", err.msg);
    float *gpu = calloc(W * H * 3, sizeof *gpu), *cpu = calloc(W * H * 3, sizeof *cpu);
    assert_non_null(gpu);
    assert_non_null(cpu);
    gpu_render(&scene, W, H, gpu);
    reference_render(&scene, W, H, cpu);

    /* Tolerance: the GPU computes in float what the reference computes in double, so a pixel may
     * differ by a few float ULPs of its value (1e-5 relative); 1e-3 relative + 1e-4 absolute is
     * far above that and far below any visible error. Pixels whose shadow or primary ray grazes
     * an edge can legitimately flip between the two methods (different intersection tests and
     * shadow offsets), so up to 1% of pixels may differ; more is a bug. */
    int mismatches = 0;
    double max_error = 0, sum = 0;
    for (int i = 0; i < W * H * 3; ++i) {
        double diff = fabs((double)gpu[i] - cpu[i]);
        sum += cpu[i];
        if (diff > 1e-4 + 1e-3 * fabs(cpu[i])) {
            if (mismatches < 5)
                print_message("pixel %d channel %d: gpu %g cpu %g\n", i / 3, i % 3, gpu[i], cpu[i]);
            ++mismatches;
        }
        if (diff > max_error)
            max_error = diff;
        assert_true(isfinite(gpu[i]));
    }
    print_message("%s: %d of %d values differ, max difference %g, mean radiance %g\n", cfg_path,
                  mismatches, W * H * 3, max_error, sum / (W * H * 3));
    /* A black or blank image would agree trivially: the reference must see light. */
    assert_true(sum / (W * H * 3) > 0.01);
    assert_true(mismatches <= W * H * 3 / 100);
    free(gpu);
    free(cpu);
    vkrt_scene_free(&scene);
}

static char cornell_obj[4096];

static int find_cornell(void **state)
{
    (void)state;
    const char *source = getenv("VKRT_SOURCE_DIR");
    snprintf(cornell_obj, sizeof cornell_obj, "%s/scenes/cornell/cornell.obj", source ? source : ".");
    return access(cornell_obj, R_OK) == 0 ? 0 : -1;
}

static void test_cornell_point_light(void **state)
{
    (void)state;
    char cfg[4096];
    snprintf(cfg, sizeof cfg, "%.*s/scene.cfg", (int)(strrchr(cornell_obj, '/') - cornell_obj),
             cornell_obj);
    compare_with_reference(cfg);
}

/* The Cornell box's geometry under the scene.cfg lines given (lights, environment, camera),
 * against the reference. */
static void compare_cornell_with_reference(const char *lines)
{
    char dir[] = "/tmp/vkrt-render-XXXXXX";
    assert_non_null(mkdtemp(dir));
    char path[4200];
    snprintf(path, sizeof path, "%s/variant.cfg", dir);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fprintf(f, "geometry %s\n%s", cornell_obj, lines);
    fclose(f);
    compare_with_reference(path);
    unlink(path);
    rmdir(dir);
}

/* Every light kind at once, and an environment seen past the box's edges. */
static void test_cornell_all_lights(void **state)
{
    (void)state;
    compare_cornell_with_reference("environment 0.1 0.2 0.3\n"
                                   "light ambient 0.02 0.02 0.02\n"
                                   "light directional 0.2 -0.3 1  0.5 0.4 0.3\n"
                                   "light spot 278 540 278  0 -1 0  30  300000 250000 200000\n"
                                   "light point 100 400 100  50000 60000 70000\n"
                                   "camera eye 278 273 -800 look 278 273 0 up 0 1 0 fov 39.3077\n");
}

/* An orthographic view of the box from above and to the side (its walls, blocks, shadows and
 * the environment past its edges), against the reference's parallel rays. */
static void test_cornell_orthographic(void **state)
{
    (void)state;
    compare_cornell_with_reference(
        "environment 0.1 0.2 0.3\n"
        "light ambient 0.05 0.05 0.05\n"
        "light point 278 500 279.5  250000 250000 250000\n"
        "camera eye 900 800 -600 look 278 273 279 up 0 1 0 ortho 900\n");
}

/* The Cornell box with its short block made of glass and its tall block a mirror (the OBJ's faces
 * 5-9 and 10-14): one mirror and one glass bounce, and more, against the reference. */
static void test_cornell_mirror_and_glass(void **state)
{
    (void)state;
    char dir[] = "/tmp/vkrt-render-XXXXXX", path[4200], line[512];
    assert_non_null(mkdtemp(dir));
    snprintf(path, sizeof path, "%s/box.obj", dir);
    FILE *in = fopen(cornell_obj, "r"), *out = fopen(path, "w");
    assert_true(in && out);
    int face = 0;
    while (fgets(line, sizeof line, in)) {
        if (strncmp(line, "mtllib", 6) == 0) {
            fputs("mtllib box.mtl\n", out);
            continue;
        }
        if (strncmp(line, "f ", 2) == 0) {
            if (face == 5)
                fputs("usemtl glass\n", out);
            else if (face == 10)
                fputs("usemtl mirror\n", out);
            ++face;
        }
        fputs(line, out);
    }
    fclose(in);
    fclose(out);
    assert_int_equal(face, 15);
    snprintf(path, sizeof path, "%s/box.mtl", dir);
    out = fopen(path, "w");
    assert_non_null(out);
    fputs("newmtl white\nKd 0.73 0.73 0.73\nnewmtl red\nKd 0.63 0.065 0.05\n"
          "newmtl green\nKd 0.14 0.45 0.091\n"
          "newmtl mirror\nKd 0.1 0.1 0.1\nKs 0.8 0.8 0.8\nillum 3\n"
          "newmtl glass\nKd 0 0 0\nNi 1.5\nillum 7\n",
          out);
    fclose(out);
    snprintf(path, sizeof path, "%s/scene.cfg", dir);
    out = fopen(path, "w");
    assert_non_null(out);
    fputs("geometry box.obj\nmax-depth 4\nenvironment 0.1 0.2 0.3\n"
          "light ambient 0.03 0.03 0.03\nlight point 278 500 279.5  250000 250000 250000\n"
          "camera eye 278 273 -800 look 278 273 0 up 0 1 0 fov 39.3077\n",
          out);
    fclose(out);
    compare_with_reference(path);
    static const char *const files[] = {"box.obj", "box.mtl", "scene.cfg"};
    for (int i = 0; i < 3; ++i) {
        snprintf(path, sizeof path, "%s/%s", dir, files[i]);
        unlink(path);
    }
    rmdir(dir);
}

/* Writes the Cornell box scaled by `scale` and moved by `offset` into dir (scene.cfg, OBJ, MTL):
 * camera and light move with it, and the point light's intensity grows with scale^2 so that the
 * picture stays the same. The environment is a colour no surface has, to tell holes apart. */
static void write_transformed_cornell(const char *dir, double scale, double offset)
{
    char path[4200], line[512];
    FILE *in = fopen(cornell_obj, "r");
    snprintf(path, sizeof path, "%s/box.obj", dir);
    FILE *out = fopen(path, "w");
    assert_true(in && out);
    while (fgets(line, sizeof line, in)) {
        double x, y, z;
        if (sscanf(line, "v %lf %lf %lf", &x, &y, &z) == 3)
            fprintf(out, "v %.9g %.9g %.9g\n", x * scale + offset, y * scale + offset,
                    z * scale + offset);
        else
            fputs(line, out);
    }
    fclose(in);
    fclose(out);
    char mtl_in[4200];
    snprintf(mtl_in, sizeof mtl_in, "%.*s/cornell.mtl", (int)(strrchr(cornell_obj, '/') - cornell_obj),
             cornell_obj);
    snprintf(path, sizeof path, "%s/cornell.mtl", dir);
    in = fopen(mtl_in, "r");
    out = fopen(path, "w");
    assert_true(in && out);
    while (fgets(line, sizeof line, in))
        fputs(line, out);
    fclose(in);
    fclose(out);
    snprintf(path, sizeof path, "%s/scene.cfg", dir);
    out = fopen(path, "w");
    assert_non_null(out);
    double s = scale, o = offset;
    fprintf(out,
            "geometry box.obj\nenvironment 0 0 5\nlight ambient 0.03 0.03 0.03\n"
            "light point %.9g %.9g %.9g  %.9g %.9g %.9g\n"
            "camera eye %.9g %.9g %.9g look %.9g %.9g %.9g up 0 1 0 fov 39.3077\n",
            278 * s + o, 500 * s + o, 279.5 * s + o, 250000 * s * s, 250000 * s * s,
            250000 * s * s, 278 * s + o, 273 * s + o, -800 * s + o, 278 * s + o, 273 * s + o, o);
    fclose(out);
}

static void render_transformed(double scale, double offset, vkrt_accel_kind kind, uint32_t w,
                               uint32_t h, float *rgb)
{
    char dir[] = "/tmp/vkrt-scale-XXXXXX", path[4200];
    assert_non_null(mkdtemp(dir));
    write_transformed_cornell(dir, scale, offset);
    snprintf(path, sizeof path, "%s/scene.cfg", dir);
    vkrt_scene scene;
    vkrt_error err = {{0}};
    if (!vkrt_scene_load(path, &scene, &err))
        fail_msg("%s", err.msg);
    gpu_context ctx;
    fixture_context_create(&ctx);
    vkrt_renderer *r = NULL;
    vkrt_render_desc desc = {.width = w, .height = h, .samples = 1, .accel = kind};
    if (!vkrt_renderer_create(&r, &ctx, &scene, &desc, &err) ||
        !vkrt_renderer_render(r, &scene.cameras[0], 0, rgb, NULL, &err))
        fail_msg("%s", err.msg);
    vkrt_renderer_destroy(r);
    fixture_context_destroy(&ctx);
    vkrt_scene_free(&scene);
    static const char *const files[] = {"box.obj", "cornell.mtl", "scene.cfg"};
    for (int i = 0; i < 3; ++i) {
        snprintf(path, sizeof path, "%s/%s", dir, files[i]);
        unlink(path);
    }
    rmdir(dir);
}

/* The Cornell box moved 1e5 from the origin, and scaled by 1e-3, 1e3, 1e5 and 1.2e8, renders as it
 * does at its own size. A fixed epsilon fails here: too small far from the origin (self-shadowing
 * acne, dark speckles on lit walls), too large on a small scene (light leaking through contacts).
 * Holes (rays slipping between triangles) would show the environment's pure blue. Edges may shift
 * by a pixel where the camera's rays round differently, so up to 1% of pixels may differ.
 * Scaled by 1.2e8 the camera is 9.6e10 from the origin, near the 1e11 that scene files may use
 * (src/scene/coordinate_limit.h): there the walls' normals overflowed to zero (every wall dark
 * past a scale of 7.7e6) and the BVH lost the rays of the middle row and column, whose direction
 * has a component of exactly 0 at an odd image size. */
static void test_scale_and_offset(void **state)
{
    (void)state;
    enum { W = 95, H = 95 };
    static const struct { double scale, offset; } cases[] = {
        {1, 1e5}, {1, 1e7}, {1e-3, 0}, {1e3, 0}, {1e5, 0}, {1.2e8, 0}};
    static const vkrt_accel_kind kinds[] = {VKRT_ACCEL_GRID, VKRT_ACCEL_BVH};
    float *base = calloc(W * H * 3, sizeof *base), *moved = calloc(W * H * 3, sizeof *moved);
    assert_true(base && moved);
    for (int k = 0; k < 2; ++k) {
        render_transformed(1, 0, kinds[k], W, H, base);
        for (size_t c = 0; c < sizeof cases / sizeof *cases; ++c) {
            render_transformed(cases[c].scale, cases[c].offset, kinds[k], W, H, moved);
            int holes = 0, darker = 0, lighter = 0;
            for (int i = 0; i < W * H; ++i) {
                const float *b = base + 3 * i, *m = moved + 3 * i;
                bool base_env = b[0] == 0 && b[1] == 0 && b[2] == 5;
                bool moved_env = m[0] == 0 && m[1] == 0 && m[2] == 5;
                holes += moved_env && !base_env;
                if (!base_env && !moved_env) {
                    float lb = b[0] + b[1] + b[2], lm = m[0] + m[1] + m[2];
                    darker += lm < 0.5f * lb;
                    lighter += lm > 2.0f * lb + 1e-3f;
                }
            }
            print_message("%s, scale %g, offset %g: %d holes, %d pixels darker, %d lighter\n",
                          vkrt_accel_name(kinds[k]), cases[c].scale, cases[c].offset, holes,
                          darker, lighter);
            assert_true(holes <= W * H / 100);
            assert_true(darker <= W * H / 100);
            assert_true(lighter <= W * H / 100);
        }
    }
    free(base);
    free(moved);
}

/* up is a direction of any finite length (docs/scene-format.md): 0 1e30 0 gives the frame of
 * 0 1 0. Squared in float, its cross product with the view overflowed, and the camera's right
 * became 0 x inf: a picture of NaNs, with exit 0. */
static void test_camera_up_of_any_length(void **state)
{
    (void)state;
    vkrt_config_camera unit = {.eye = {278, 273, -800}, .look = {278, 273, 0}, .up = {0, 1, 0},
                               .fov_deg = 39.3077f};
    vkrt_config_camera long_up = unit;
    long_up.up[1] = 1e30f;
    FrameParams a = {0}, b = {0};
    vkrt_camera_params(&unit, 95, 95, &a);
    vkrt_camera_params(&long_up, 95, 95, &b);
    assert_true(a.right.x == b.right.x && a.right.y == b.right.y && a.right.z == b.right.z);
    assert_true(a.up.x == b.up.x && a.up.y == b.up.y && a.up.z == b.up.z);
    assert_true(fabsf(a.right.x) > 0.3f); /* tan(fov / 2): a right vector at all */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cornell_point_light),
        cmocka_unit_test(test_cornell_all_lights),
        cmocka_unit_test(test_cornell_mirror_and_glass),
        cmocka_unit_test(test_cornell_orthographic),
        cmocka_unit_test(test_camera_up_of_any_length),
        cmocka_unit_test(test_scale_and_offset),
    };
    return cmocka_run_group_tests(tests, find_cornell, NULL);
}
