/*
 * test_materials.c: the wavefront of materials against closed forms.
 *
 * Each test writes a tiny scene (OBJ, .mtl, material file, user shaders) into a temporary folder
 * and renders a few pixels through the real renderer. Probes are user shaders: a surface whose
 * shade adds its hit position as radiance, or an environment that returns the ray's direction, turn
 * a pixel into a measurement of where a ray went, which the test predicts from geometry (mirror
 * law, Snell's law, Fresnel equations) and the lights' definitions (docs/scene-format.md).
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

#include <stb_image_write.h>

#include "gpu_fixture.h"
#include "scene_dir.h"
#include "render/renderer.h"
#include "scene/scene.h"
#include "scene/texture.h"

/* A probe surface: adds its hit position as radiance. */
static const char position_probe[] = "uint count_rays(Surface s) { return 0u; }\n"
                                     "void shade(Surface s) { add_radiance(s.position); }\n";

/* Renders the folder's scene.cfg at w x h, one sample per pixel centre. */
static bool render(uint32_t w, uint32_t h, const vkrt_render_desc *extra, float *rgb,
                   vkrt_frame_stats *stats, vkrt_error *err)
{
    return scene_dir_render(w, h, extra, rgb, stats, err);
}

static void render_ok(uint32_t w, uint32_t h, const vkrt_render_desc *extra, float *rgb,
                      vkrt_frame_stats *stats)
{
    vkrt_error err = {{0}};
    if (!render(w, h, extra, rgb, stats, &err))
        fail_msg("render: %s", err.msg);
}

static void assert_close3(const float *got, const double *want, double tolerance, const char *what)
{
    for (int k = 0; k < 3; ++k)
        if (!(fabs(got[k] - want[k]) <= tolerance)) {
            fail_msg("%s: got (%.6g %.6g %.6g), want (%.6g %.6g %.6g), tolerance %g", what,
                     got[0], got[1], got[2], want[0], want[1], want[2], tolerance);
        }
}

/* A one-pixel camera looking from eye along dir, as a scene.cfg line. fov 1 degree: the pixel
 * centre ray is exactly dir. */
static void camera_line(char *out, size_t size, const double eye[3], const double d[3])
{
    snprintf(out, size, "camera eye %.9g %.9g %.9g look %.9g %.9g %.9g up 0 1 0.001 fov 1\n",
             eye[0], eye[1], eye[2], eye[0] + d[0], eye[1] + d[1], eye[2] + d[2]);
}

/* Mirror: a camera ray meets a mirror plane y = 0 (reflectance 0.5) at 30 degrees from the
 * normal and reflects onto a probe wall x = 10; the pixel is 0.5 times the point where the mirror
 * law says the reflected ray lands. */
static void test_mirror_reflects_where_geometry_says(void **state)
{
    (void)state;
    scene_dir_write("m.obj", "mtllib m.mtl\n"
                        "v -20 0 -20\nv 20 0 -20\nv 20 0 20\nv -20 0 20\n"
                        "v 10 -20 -20\nv 10 20 -20\nv 10 20 20\nv 10 -20 20\n"
                        "usemtl mirror\nf 1 4 3 2\nusemtl probe\nf 5 6 7 8\n");
    scene_dir_write("m.mtl", "newmtl mirror\nKd 0 0 0\nKs 0.5 0.5 0.5\nillum 3\nnewmtl probe\nKd 1 1 1\n");
    scene_dir_write("probe.glsl", position_probe);
    scene_dir_write("m.mat", "probe 0 probe.glsl\n");
    double eye[3] = {0, 5, 0.25}, d[3] = {sin(M_PI / 6), -cos(M_PI / 6), 0};
    char cam[256], cfg[1024];
    camera_line(cam, sizeof cam, eye, d);
    snprintf(cfg, sizeof cfg, "geometry m.obj\nmaterials m.mat\nmax-depth 2\n%s", cam);
    scene_dir_write("scene.cfg", cfg);
    float rgb[3];
    render_ok(1, 1, NULL, rgb, NULL);
    /* Down to y = 0: t = 5 / cos 30; reflected (sin 30, cos 30, 0) on to x = 10. */
    double hit_x = 5 * tan(M_PI / 6);
    double t = (10 - hit_x) / sin(M_PI / 6);
    double want[3] = {0.5 * 10, 0.5 * (t * cos(M_PI / 6)), 0.5 * 0.25};
    /* The reflected ray starts 256 float ULPs of 20 (6e-4) off the mirror (docs/architecture.md),
     * which moves where it lands by about as much. */
    assert_close3(rgb, want, 1e-3, "mirror");
}

/* Fresnel reflectance for unpolarised light, n1 -> n2 at cos_i; 1 past the critical angle. */
static double fresnel(double cos_i, double n1, double n2)
{
    double sin_t = n1 / n2 * sqrt(1 - cos_i * cos_i);
    if (sin_t >= 1)
        return 1;
    double cos_t = sqrt(1 - sin_t * sin_t);
    double rs = (n1 * cos_i - n2 * cos_t) / (n1 * cos_i + n2 * cos_t);
    double rp = (n1 * cos_t - n2 * cos_i) / (n1 * cos_t + n2 * cos_i);
    return 0.5 * (rs * rs + rp * rp);
}

/* Glass slab: a ray at 40 degrees through a slab 0 <= y <= 2 of index 1.5 leaves parallel to
 * itself, shifted sideways by t sin(a - b) / cos b (Snell: sin a = 1.5 sin b), and lands on a
 * probe floor y = -3. The pixel is the landing point times the two Fresnel transmittances; the
 * weaker rays reflected inside the slab fall under the importance threshold. */
static void test_glass_slab_shifts_as_snell_says(void **state)
{
    (void)state;
    scene_dir_write("g.obj", "mtllib g.mtl\n"
                        /* the slab: top y = 2 facing up, bottom y = 0 facing down */
                        "v -20 2 -20\nv 20 2 -20\nv 20 2 20\nv -20 2 20\n"
                        "v -20 0 -20\nv 20 0 -20\nv 20 0 20\nv -20 0 20\n"
                        "v -20 -3 -20\nv 20 -3 -20\nv 20 -3 20\nv -20 -3 20\n"
                        "usemtl glass\nf 1 4 3 2\nf 5 6 7 8\nusemtl probe\nf 9 12 11 10\n");
    scene_dir_write("g.mtl", "newmtl glass\nKd 0 0 0\nNi 1.5\nillum 7\nnewmtl probe\nKd 1 1 1\n");
    scene_dir_write("probe.glsl", position_probe);
    scene_dir_write("g.mat", "probe 0 probe.glsl\n");
    double a = 40 * M_PI / 180;
    double eye[3] = {0, 5, 0.5}, d[3] = {sin(a), -cos(a), 0};
    char cam[256], cfg[1024];
    camera_line(cam, sizeof cam, eye, d);
    snprintf(cfg, sizeof cfg, "geometry g.obj\nmaterials g.mat\nmax-depth 4\n%s", cam);
    scene_dir_write("scene.cfg", cfg);
    float rgb[3];
    vkrt_render_desc desc = {.min_importance = 0.01f};
    render_ok(1, 1, &desc, rgb, NULL);
    double b = asin(sin(a) / 1.5);
    double x_top = 3 * tan(a);                 /* entering at y = 2 */
    double x_bottom = x_top + 2 * tan(b);      /* leaving at y = 0 */
    double x_floor = x_bottom + 3 * tan(a);    /* parallel to the incoming ray again */
    double transmit = (1 - fresnel(cos(a), 1, 1.5)) * (1 - fresnel(cos(b), 1.5, 1));
    double want[3] = {transmit * x_floor, transmit * -3, transmit * 0.5};
    print_message("glass slab: shift %.6g (straight line would land at x %.6g, refracted %.6g)\n",
                  2 * (tan(a) - tan(b)) * cos(a), 8 * tan(a), x_floor);
    /* Two origin offsets of 6e-4 (256 ULPs of 20), each moving the path by about as much; a
     * wrong index or no refraction would miss by 0.7. */
    assert_close3(rgb, want, 2e-3, "glass slab");
}

/* The payload example: @absorbing_glass carries the entry point of a ray in its payload, so a
 * ray crossing a slab of thickness 2 straight down leaves it attenuated by exp(-2 sigma) per
 * channel (Beer-Lambert), besides the two Fresnel transmittances at normal incidence. The
 * environment is 1 below the slab and 0 above, so only the transmitted light counts; rays bounced
 * twice inside fall under the importance threshold. */
static void test_absorbing_glass_uses_the_payload(void **state)
{
    (void)state;
    scene_dir_write("a.obj", "mtllib a.mtl\n"
                        "v -20 2 -20\nv 20 2 -20\nv 20 2 20\nv -20 2 20\n"
                        "v -20 0 -20\nv 20 0 -20\nv 20 0 20\nv -20 0 20\n"
                        "usemtl slab\nf 1 4 3 2\nf 5 6 7 8\n");
    scene_dir_write("a.mtl", "newmtl slab\nKd 1 1 1\n");
    scene_dir_write("below.glsl", "vec3 environment(vec3 d, vec4 payload) { return d.y < 0.0 ? vec3(1.0) : vec3(0.0); }\n");
    scene_dir_write("a.mat", "slab 0 @absorbing_glass 0.5 0.1 0  0 0 0 0  0 0 0  1.5\n"
                        "environment 0 below.glsl\n");
    scene_dir_write("scene.cfg", "geometry a.obj\nmaterials a.mat\nmax-depth 4\n"
                            "camera eye 0 5 0 look 0 0 0 up 0 0 1 fov 1\n");
    float rgb[3];
    vkrt_render_desc desc = {.min_importance = 0.01f};
    render_ok(1, 1, &desc, rgb, NULL);
    double r = (0.5 / 2.5) * (0.5 / 2.5); /* Fresnel at normal incidence, ((n - 1) / (n + 1))^2 */
    const double sigma[3] = {0.5, 0.1, 0};
    double want[3];
    for (int k = 0; k < 3; ++k)
        want[k] = (1 - r) * (1 - r) * exp(-2 * sigma[k]);
    assert_close3(rgb, want, 1e-4, "absorbing glass");
}

/* An environment that shows directions: d + 1 for rays towards +z (or -z), zero otherwise. */
static void write_direction_environment(bool towards_plus_z)
{
    char text[256];
    snprintf(text, sizeof text,
             "vec3 environment(vec3 d, vec4 payload) { return d.z %s 0.0 ? d + 1.0 : vec3(0.0); }\n",
             towards_plus_z ? ">" : "<");
    scene_dir_write("env.glsl", text);
}

/* Inside glass (the back of a glass plane z = 0 whose front faces +z), a ray meets the surface:
 * at 30 degrees it refracts out by Snell's law with weight 1 - R (Fresnel); at 60 degrees, past
 * the critical angle asin(1/1.5) = 41.8 degrees, it reflects totally, weight 1. */
static void test_glass_refraction_and_total_internal_reflection(void **state)
{
    (void)state;
    scene_dir_write("p.obj", "mtllib p.mtl\nv -100 -100 0\nv 100 -100 0\nv 100 100 0\nv -100 100 0\n"
                        "usemtl glass\nf 1 2 3 4\n");
    scene_dir_write("p.mtl", "newmtl glass\nKd 0 0 0\nNi 1.5\nillum 7\n");
    scene_dir_write("p.mat", "environment 0 env.glsl\n");
    const double angles[] = {30, 60};
    for (int i = 0; i < 2; ++i) {
        double a = angles[i] * M_PI / 180;
        double eye[3] = {0, 0, -3}, d[3] = {sin(a), 0, cos(a)};
        char cam[256], cfg[1024];
        camera_line(cam, sizeof cam, eye, d);
        snprintf(cfg, sizeof cfg, "geometry p.obj\nmaterials p.mat\nmax-depth 2\n%s", cam);
        scene_dir_write("scene.cfg", cfg);
        bool refracts = angles[i] < 41.8;
        write_direction_environment(refracts);
        float rgb[3];
        render_ok(1, 1, NULL, rgb, NULL);
        double want[3];
        if (refracts) {
            double sin_t = 1.5 * sin(a), cos_t = sqrt(1 - sin_t * sin_t);
            double weight = 1 - fresnel(cos(a), 1.5, 1);
            double out[3] = {sin_t, 0, cos_t};
            for (int k = 0; k < 3; ++k)
                want[k] = weight * (out[k] + 1);
        } else {
            double out[3] = {sin(a), 0, -cos(a)};
            for (int k = 0; k < 3; ++k)
                want[k] = out[k] + 1;
        }
        assert_close3(rgb, want, 1e-4, refracts ? "refraction at 30 degrees" : "TIR at 60 degrees");
    }
}

/* Energy: a Lambertian floor of albedo 0.5 under a directional light of irradiance E at 60 degrees
 * from the normal returns radiance albedo * E * cos(60) / pi in every pixel; under a point light
 * of intensity I at height h, albedo / pi * I * h / d^3 at distance d. */
static void test_diffuse_radiance_closed_form(void **state)
{
    (void)state;
    scene_dir_write("f.obj", "mtllib f.mtl\nv -50 0 -50\nv 50 0 -50\nv 50 0 50\nv -50 0 50\n"
                        "usemtl floor\nf 1 4 3 2\n");
    scene_dir_write("f.mtl", "newmtl floor\nKd 0.5 0.5 0.5\n");
    /* Looking straight down from y = 10 with a 60 degree fov: the floor fills the picture. */
    const char *camera = "camera eye 0 10 0 look 0 0 0 up 0 0 1 fov 60\n";
    char cfg[1024];
    snprintf(cfg, sizeof cfg, "geometry f.obj\nlight directional 0 -1 1.7320508  2 2 2\n%s",
             camera);
    /* direction (0, -1, sqrt 3) normalised: 60 degrees from the downward axis */
    scene_dir_write("scene.cfg", cfg);
    enum { N = 8 };
    float rgb[N * N * 3];
    render_ok(N, N, NULL, rgb, NULL);
    double want = 0.5 * 2 * cos(M_PI / 3) / M_PI;
    for (int i = 0; i < N * N * 3; ++i)
        if (fabs(rgb[i] - want) > 1e-5)
            fail_msg("directional: value %d is %.7g, want %.7g", i, rgb[i], want);

    snprintf(cfg, sizeof cfg, "geometry f.obj\nlight point 0 4 0  100 100 100\n%s", camera);
    scene_dir_write("scene.cfg", cfg);
    render_ok(N, N, NULL, rgb, NULL);
    double tan_half = tan(M_PI / 6);
    for (int y = 0; y < N; ++y)
        for (int x = 0; x < N; ++x) {
            /* The pixel centre's ray meets the floor at (px, 0, pz) (up is +z, right is -x). */
            double sx = 2 * (x + 0.5) / N - 1, sy = 1 - 2 * (y + 0.5) / N;
            double px = -sx * tan_half * 10, pz = sy * tan_half * 10;
            double d = sqrt(px * px + pz * pz + 16);
            double radiance = 0.5 / M_PI * 100 * 4 / (d * d * d);
            const float *got = rgb + 3 * (y * N + x);
            if (fabs(got[0] - radiance) > 1e-5 * radiance + 1e-7)
                fail_msg("point: pixel %d %d is %.7g, want %.7g", x, y, got[0], radiance);
        }
}

/* Spot falloff: a spot light of cutoff 40 degrees (full beam to 30, linear in angle to zero at
 * 40) above the floor; each pixel's radiance is albedo / pi * I * falloff(angle) * h / d^3. */
static void test_spot_falloff_closed_form(void **state)
{
    (void)state;
    scene_dir_write("f.obj", "mtllib f.mtl\nv -50 0 -50\nv 50 0 -50\nv 50 0 50\nv -50 0 50\n"
                        "usemtl floor\nf 1 4 3 2\n");
    scene_dir_write("f.mtl", "newmtl floor\nKd 0.5 0.5 0.5\n");
    scene_dir_write("scene.cfg", "geometry f.obj\nlight spot 0 4 0  0 -1 0  40  100 100 100\n"
                            "camera eye 0 10 0 look 0 0 0 up 0 0 1 fov 60\n");
    enum { N = 32 };
    static float rgb[N * N * 3];
    render_ok(N, N, NULL, rgb, NULL);
    double tan_half = tan(M_PI / 6), cutoff = 40 * M_PI / 180, beam = 0.75 * cutoff;
    int lit = 0, dark = 0, ramp = 0;
    for (int y = 0; y < N; ++y)
        for (int x = 0; x < N; ++x) {
            double sx = 2 * (x + 0.5) / N - 1, sy = 1 - 2 * (y + 0.5) / N;
            double px = -sx * tan_half * 10, pz = sy * tan_half * 10;
            double r = sqrt(px * px + pz * pz), d = sqrt(r * r + 16);
            double angle = atan2(r, 4);
            double falloff = angle >= cutoff ? 0 : angle <= beam ? 1 : (cutoff - angle) / (cutoff - beam);
            double radiance = 0.5 / M_PI * 100 * falloff * 4 / (d * d * d);
            lit += falloff == 1;
            dark += falloff == 0;
            ramp += falloff > 0 && falloff < 1;
            const float *got = rgb + 3 * (y * N + x);
            /* GLSL leaves acos's precision to the implementation (llvmpipe's is good to about
             * 1e-4 radians): allow that much angle error on the ramp, 1e-3 of the unfaded value. */
            double unfaded = 0.5 / M_PI * 100 * 4 / (d * d * d);
            if (fabs(got[0] - radiance) > 1e-4 * radiance + 1e-3 * unfaded)
                fail_msg("spot: pixel %d %d (angle %.3f deg) is %.7g, want %.7g", x, y,
                         angle * 180 / M_PI, got[0], radiance);
        }
    /* The picture must cover the beam, the ramp and the dark outside. */
    assert_true(lit > 10 && dark > 10 && ramp > 10);
}

/* Growth: a glass slab in front of the whole view doubles the rays at every hit, so buffers that
 * start at one ray per pixel must grow (at least doubling), and the picture must be the one that
 * large buffers give. The floor under the slab is lit, so the picture is not black. */
static void test_ray_buffers_grow_to_the_same_image(void **state)
{
    (void)state;
    scene_dir_write("s.obj", "mtllib s.mtl\n"
                        "v -20 2 -20\nv 20 2 -20\nv 20 2 20\nv -20 2 20\n"
                        "v -20 0 -20\nv 20 0 -20\nv 20 0 20\nv -20 0 20\n"
                        "v -20 -3 -20\nv 20 -3 -20\nv 20 -3 20\nv -20 -3 20\n"
                        "usemtl glass\nf 1 4 3 2\nf 5 6 7 8\nusemtl floor\nf 9 12 11 10\n");
    scene_dir_write("s.mtl", "newmtl glass\nKd 0 0 0\nNi 1.5\nillum 7\nnewmtl floor\nKd 0.6 0.5 0.4\n");
    scene_dir_write("scene.cfg", "geometry s.obj\nmax-depth 5\nenvironment 0.2 0.3 0.4\n"
                            "light point 3 6 1  200 200 200\n"
                            "camera eye 0 8 -4 look 0 0 1 up 0 1 0 fov 40\n");
    enum { W = 32, H = 32 };
    static float small[W * H * 3], large[W * H * 3];
    vkrt_frame_stats stats[2];
    vkrt_render_desc big = {.ray_capacity = 1u << 20};
    render_ok(W, H, NULL, small, &stats[0]);
    render_ok(W, H, &big, large, &stats[1]);
    print_message("small buffers: %u attempts, capacity %u; large: %u attempts, capacity %u; "
                  "secondary rays %llu\n",
                  stats[0].attempts, stats[0].ray_capacity, stats[1].attempts,
                  stats[1].ray_capacity, (unsigned long long)stats[0].secondary_rays);
    assert_true(stats[0].attempts > 1);
    assert_true(stats[0].ray_capacity >= 2 * W * H);
    assert_int_equal(stats[1].attempts, 1);
    assert_int_equal(stats[0].secondary_rays, stats[1].secondary_rays);
    assert_true(stats[0].secondary_rays > 2 * W * H);
    double sum = 0;
    for (int i = 0; i < W * H * 3; ++i) {
        /* Float atomics add a pixel's contributions in any order: a few ULPs apart. */
        if (fabs(small[i] - large[i]) > 1e-5 * fabs(large[i]) + 1e-7)
            fail_msg("value %d: %.9g with growth, %.9g without", i, small[i], large[i]);
        assert_true(isfinite(small[i]));
        sum += large[i];
    }
    assert_true(sum / (W * H * 3) > 0.01);
}

/* Textures through the whole path: a quad with uvs 0..1, a 4x4 sRGB texture (map_Kd) and Kd 0.5,
 * lit only by an ambient light of radiance 1, shows 0.5 * texture(uv) in each pixel: the CPU
 * reference sampler (src/scene/texture.c) at the uv the pixel centre's ray meets, interpolated
 * from the corners as the kernels do. The texture repeats twice across the quad, to see the wrap. */
static void test_textured_quad_matches_the_reference_sampler(void **state)
{
    (void)state;
    unsigned char texels[4 * 4 * 3];
    for (int i = 0; i < 16; ++i) {
        texels[3 * i + 0] = (unsigned char)(17 * i);
        texels[3 * i + 1] = (unsigned char)(255 - 13 * i);
        texels[3 * i + 2] = (unsigned char)(i % 3 == 0 ? 250 : 20);
    }
    char path[256];
    snprintf(path, sizeof path, "%s/t.png", scene_dir);
    assert_true(stbi_write_png(path, 4, 4, 3, texels, 4 * 3) != 0);
    /* The quad z = 0, x and y in [-1, 1], uv = (x + 1, y + 1): two repeats each way. */
    scene_dir_write("q.obj", "mtllib q.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n"
                        "vt 0 0\nvt 2 0\nvt 2 2\nvt 0 2\nusemtl tex\nf 1/1 2/2 3/3 4/4\n");
    scene_dir_write("q.mtl", "newmtl tex\nKd 0.5 0.5 0.5\nmap_Kd t.png\n");
    /* fov chosen so the picture spans x, y in [-0.9, 0.9] at z = 0 from 3 away */
    double fov = 2 * atan(0.9 / 3) * 180 / M_PI;
    char cfg[512];
    snprintf(cfg, sizeof cfg, "geometry q.obj\nlight ambient 1 1 1\n"
                              "camera eye 0 0 3 look 0 0 0 up 0 1 0 fov %.9g\n", fov);
    scene_dir_write("scene.cfg", cfg);
    enum { N = 24 };
    float rgb[N * N * 3];
    render_ok(N, N, NULL, rgb, NULL);
    vkrt_texture_set set = {0};
    uint32_t index;
    vkrt_error err = {{0}};
    if (!vkrt_texture_set_add(&set, path, VKRT_TEXTURE_COLOUR, "test", &index, &err))
        fail_msg("%s", err.msg);
    double max_diff = 0;
    for (int y = 0; y < N; ++y)
        for (int x = 0; x < N; ++x) {
            /* The camera looks down -z with up +y: right is +x. */
            double px = (2 * (x + 0.5) / N - 1) * 0.9, py = (1 - 2 * (y + 0.5) / N) * 0.9;
            float want[4];
            vkrt_texture_sample(&set, index, (float)(px + 1), (float)(py + 1), want);
            for (int k = 0; k < 3; ++k) {
                double diff = fabs(rgb[3 * (y * N + x) + k] - 0.5 * want[k]);
                max_diff = diff > max_diff ? diff : max_diff;
                /* uv interpolated in float from a ray hit: 1e-5 of a texel moves the sample by
                 * at most 1e-5 times the largest step between neighbouring texels (< 1). */
                if (diff > 1e-4)
                    fail_msg("pixel %d %d channel %d: %.6g, the reference sampler says %.6g", x, y,
                             k, rgb[3 * (y * N + x) + k], 0.5 * want[k]);
            }
        }
    print_message("textured quad: largest difference %.3g\n", max_diff);
    vkrt_texture_set_free(&set);
}

/* Progressive rendering (what the viewer does): the passes of a 4-sample frame added one call at a
 * time give the picture one call for all four gives. */
static void test_passes_added_one_by_one_equal_the_whole_frame(void **state)
{
    (void)state;
    const char *source = getenv("VKRT_SOURCE_DIR");
    assert_non_null(source);
    char path[512];
    snprintf(path, sizeof path, "%s/scenes/cornell-spheres/scene.cfg", source);
    vkrt_scene scene;
    vkrt_error err = {{0}};
    if (!vkrt_scene_load(path, &scene, &err))
        fail_msg("%s", err.msg);
    enum { W = 24, H = 24 };
    static float whole[W * H * 3], parts[W * H * 3];
    gpu_context ctx;
    fixture_context_create(&ctx);
    vkrt_render_desc desc = {.width = W, .height = H, .samples = 4};
    vkrt_renderer *r = NULL;
    if (!vkrt_renderer_create(&r, &ctx, &scene, &desc, &err) ||
        !vkrt_renderer_render(r, &scene.cameras[0], 3, whole, NULL, &err))
        fail_msg("%s", err.msg);
    for (uint32_t pass = 0; pass < 4; ++pass)
        if (!vkrt_renderer_add_samples(r, &scene.cameras[0], 3, pass, 1, NULL, &err))
            fail_msg("%s", err.msg);
    if (!vkrt_renderer_read_image(r, 4, parts, &err))
        fail_msg("%s", err.msg);
    assert_false(vkrt_renderer_add_samples(r, &scene.cameras[0], 3, 4, 1, NULL, &err));
    vkrt_renderer_destroy(r);
    fixture_context_destroy(&ctx);
    double sum = 0;
    for (int i = 0; i < W * H * 3; ++i) {
        if (fabs(whole[i] - parts[i]) > 1e-5 * fabs(whole[i]) + 1e-7)
            fail_msg("value %d: %.9g in one call, %.9g pass by pass", i, whole[i], parts[i]);
        sum += whole[i];
    }
    assert_true(sum / (W * H * 3) > 0.01);
    vkrt_scene_free(&scene);
}

/* A shader that casts more rays than it counted is caught and named; nothing is corrupted. */
static void test_overcasting_shader_is_reported(void **state)
{
    (void)state;
    scene_dir_write("o.obj", "mtllib o.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nusemtl greedy\nf 1 2 3 4\n");
    scene_dir_write("o.mtl", "newmtl greedy\nKd 1 1 1\n");
    scene_dir_write("greedy.glsl", "uint count_rays(Surface s) { return 1u; }\n"
                              "void shade(Surface s) {\n"
                              "    cast_ray(s, reflect(s.incoming, s.normal), vec3(0.5));\n"
                              "    cast_ray(s, -s.incoming, vec3(0.5));\n"
                              "}\n");
    scene_dir_write("o.mat", "# one too many\ngreedy 0 greedy.glsl\n");
    scene_dir_write("scene.cfg", "geometry o.obj\nmaterials o.mat\nmax-depth 3\n"
                            "camera eye 0 0 3 look 0 0 0 up 0 1 0 fov 30\n");
    float rgb[4 * 4 * 3];
    vkrt_error err = {{0}};
    assert_false(render(4, 4, NULL, rgb, NULL, &err));
    print_message("%s\n", err.msg);
    assert_non_null(strstr(err.msg, "'greedy'"));
    assert_non_null(strstr(err.msg, "o.mat:2"));
    assert_non_null(strstr(err.msg, "more rays than its count_rays"));
}

/* A syntax error in a user shader names the material file's line, the shader file and its line,
 * and nothing renders. */
static void test_shader_syntax_error_names_file_and_line(void **state)
{
    (void)state;
    scene_dir_write("o.obj", "mtllib o.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nusemtl broken\nf 1 2 3\n");
    scene_dir_write("o.mtl", "newmtl broken\nKd 1 1 1\n");
    scene_dir_write("broken.glsl", "uint count_rays(Surface s) { return 0u; }\n"
                              "void shade(Surface s) {\n"
                              "    add_radiance(vec3(1.0)) oops;\n"
                              "}\n");
    scene_dir_write("o.mat", "\n\nbroken 0 broken.glsl 1 2 3\n");
    scene_dir_write("scene.cfg", "geometry o.obj\nmaterials o.mat\n"
                            "camera eye 0 0 3 look 0 0 0 up 0 1 0 fov 30\n");
    float rgb[3];
    vkrt_error err = {{0}};
    assert_false(render(1, 1, NULL, rgb, NULL, &err));
    print_message("%s\n", err.msg);
    assert_non_null(strstr(err.msg, "o.mat:3"));
    assert_non_null(strstr(err.msg, "broken.glsl:3"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mirror_reflects_where_geometry_says),
        cmocka_unit_test(test_glass_slab_shifts_as_snell_says),
        cmocka_unit_test(test_glass_refraction_and_total_internal_reflection),
        cmocka_unit_test(test_absorbing_glass_uses_the_payload),
        cmocka_unit_test(test_diffuse_radiance_closed_form),
        cmocka_unit_test(test_spot_falloff_closed_form),
        cmocka_unit_test(test_ray_buffers_grow_to_the_same_image),
        cmocka_unit_test(test_textured_quad_matches_the_reference_sampler),
        cmocka_unit_test(test_passes_added_one_by_one_equal_the_whole_frame),
        cmocka_unit_test(test_overcasting_shader_is_reported),
        cmocka_unit_test(test_shader_syntax_error_names_file_and_line),
    };
    return cmocka_run_group_tests(tests, scene_dir_make, scene_dir_remove);
}
