/*
 * test_path.c: the path integrator against what physics fixes exactly, each on a scene where an
 * error shows: energy (a white furnace), containment (a closed box lit from inside), robustness
 * (a tiny, very bright emitter) and consistency (three estimators of one image); and that the
 * sampler stratifies what a path draws (the error of a mean of N samples against one sample's).
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "../glsl/shared.h"
#include "gpu_fixture.h"
#include "render/renderer.h"
#include "scene/scene.h"
#include "scene_dir.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* A closed sphere of radius 1 about the origin, faces wound counter-clockwise seen from outside,
 * without vertex normals (flat facets: a convex polyhedron, so no path meets it twice). */
static void write_sphere(const char *name, const char *material, int rings, int segments)
{
    FILE *f = scene_dir_open(name);
    fprintf(f, "mtllib scene.mtl\nusemtl %s\n", material);
    fprintf(f, "v 0 1 0\nv 0 -1 0\n");
    for (int r = 1; r < rings; ++r)
        for (int s = 0; s < segments; ++s) {
            double theta = M_PI * r / rings, phi = 2 * M_PI * s / segments;
            fprintf(f, "v %.9f %.9f %.9f\n", sin(theta) * cos(phi), cos(theta),
                    sin(theta) * sin(phi));
        }
    /* Vertex of ring r (1..rings-1), segment s: 3 + (r - 1) * segments + s (1-based). */
#define RING(r, s) (3 + ((r) - 1) * segments + ((s) % segments))
    for (int s = 0; s < segments; ++s) {
        fprintf(f, "f 1 %d %d\n", RING(1, s + 1), RING(1, s));
        fprintf(f, "f 2 %d %d\n", RING(rings - 1, s), RING(rings - 1, s + 1));
        for (int r = 1; r + 1 < rings; ++r)
            fprintf(f, "f %d %d %d %d\n", RING(r, s), RING(r, s + 1), RING(r + 1, s + 1),
                    RING(r + 1, s));
    }
#undef RING
    fclose(f);
}

static void render_ok(uint32_t w, uint32_t h, const vkrt_render_desc *desc, float *rgb,
                      vkrt_frame_stats *stats)
{
    vkrt_error err = {{0}};
    if (!scene_dir_render(w, h, desc, rgb, stats, &err))
        fail_msg("render: %s", err.msg);
}

static double mean_of(const float *rgb, size_t pixels)
{
    double sum = 0;
    for (size_t i = 0; i < 3 * pixels; ++i)
        sum += rgb[i];
    return sum / (3.0 * pixels);
}

/* White furnace: a diffuse sphere of albedo 1 under a uniform environment of radiance 1 reflects
 * all it receives, so every pixel, sphere or sky, is 1 in expectation, at any depth cap large
 * enough for the light to come out (the sphere is convex: one bounce suffices, the rest is what
 * Russian roulette and MIS must not bias). Each pixel is held within its noise; the image mean,
 * which averages 1024 pixels' noise away, within 0.5%. */
static void white_furnace(void **state)
{
    (void)state;
    write_sphere("sphere.obj", "white", 12, 24);
    scene_dir_write("scene.mtl", "newmtl white\nKd 1 1 1\n");
    scene_dir_write("scene.cfg", "geometry sphere.obj\nresolution 32 32\nmax-depth 64\n"
                                 "integrator path\nenvironment 1 1 1\n"
                                 "camera eye 0 0 3 look 0 0 0 up 0 1 0 fov 50\n");
    enum { N = 32, SPP = 64 };
    float *rgb = malloc(N * N * 3 * sizeof *rgb);
    vkrt_frame_stats stats;
    render_ok(N, N, &(vkrt_render_desc){.samples = SPP}, rgb, &stats);
    double mean = mean_of(rgb, N * N);
    print_message("white furnace: image mean %.5f (expected 1), %llu shadow rays\n", mean,
                  (unsigned long long)stats.shadow_rays);
    assert_true(fabs(mean - 1.0) < 0.005);
    int sphere_pixels = 0;
    for (int i = 0; i < N * N; ++i) {
        for (int k = 0; k < 3; ++k)
            if (!(fabsf(rgb[3 * i + k] - 1.0f) < 0.25f))
                fail_msg("pixel %d channel %d is %g, not 1", i, k, rgb[3 * i + k]);
        sphere_pixels += rgb[3 * i] != 1.0f; /* the sky is exactly 1 */
    }
    /* A picture of the sky alone would pass the checks above: the sphere must be in it. */
    assert_true(sphere_pixels > N * N / 4);
    assert_int_equal(stats.nonfinite, 0);
    free(rgb);
}

/* An axis-aligned box [lo, hi] as 12 triangles wound counter-clockwise seen from outside
 * (inward: seen from inside), under material. */
static void write_box(FILE *f, const char *material, const double lo[3], const double hi[3],
                      bool inward, int *next_vertex)
{
    int v = *next_vertex;
    fprintf(f, "usemtl %s\n", material);
    for (int i = 0; i < 8; ++i)
        fprintf(f, "v %g %g %g\n", i & 1 ? hi[0] : lo[0], i & 2 ? hi[1] : lo[1],
                i & 4 ? hi[2] : lo[2]);
    /* Each face's corners counter-clockwise seen from outside. */
    static const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                    {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (int q = 0; q < 6; ++q) {
        const int *c = faces[q];
        if (inward)
            fprintf(f, "f %d %d %d %d\n", v + c[3], v + c[2], v + c[1], v + c[0]);
        else
            fprintf(f, "f %d %d %d %d\n", v + c[0], v + c[1], v + c[2], v + c[3]);
    }
    *next_vertex = v + 8;
}

/* A closed box lit from inside leaks nothing: seen from outside under a black sky, every pixel is
 * exactly 0 (a shadow ray or a bounce that slipped through an edge or a face would light the
 * outside). The lamp inside is a small emissive box facing out, the room's walls white. */
static void closed_box_leaks_nothing(void **state)
{
    (void)state;
    FILE *f = scene_dir_open("box.obj");
    fprintf(f, "mtllib scene.mtl\n");
    int v = 1;
    write_box(f, "wall", (double[]){-1, -1, -1}, (double[]){1, 1, 1}, true, &v);
    write_box(f, "wall", (double[]){-1.01, -1.01, -1.01}, (double[]){1.01, 1.01, 1.01}, false,
              &v);
    write_box(f, "lamp", (double[]){-0.1, 0.8, -0.1}, (double[]){0.1, 0.9, 0.1}, false, &v);
    fclose(f);
    scene_dir_write("scene.mtl", "newmtl wall\nKd 0.8 0.8 0.8\nnewmtl lamp\nKd 0 0 0\n"
                                 "Ke 50 50 50\n");
    scene_dir_write("scene.cfg", "geometry box.obj\nresolution 48 48\nmax-depth 8\n"
                                 "integrator path\n"
                                 "camera eye 2.5 1.5 3 look 0 0 0 up 0 1 0 fov 60\n");
    enum { N = 48 };
    float rgb[N * N * 3];
    vkrt_frame_stats stats;
    render_ok(N, N, &(vkrt_render_desc){.samples = 16}, rgb, &stats);
    for (int i = 0; i < N * N * 3; ++i)
        if (rgb[i] != 0.0f)
            fail_msg("value %d is %g: light leaked out of the box", i, rgb[i]);
    /* Not black because nothing was lit: the same box seen from inside is bright. */
    scene_dir_write("scene.cfg", "geometry box.obj\nresolution 48 48\nmax-depth 8\n"
                                 "integrator path\n"
                                 "camera eye 0.5 -0.5 0.9 look 0 0 0 up 0 1 0 fov 80\n");
    render_ok(N, N, &(vkrt_render_desc){.samples = 4}, rgb, &stats);
    double inside = mean_of(rgb, N * N);
    print_message("closed box: outside all 0, inside mean %.4f, %llu shadow rays\n", inside,
                  (unsigned long long)stats.shadow_rays);
    assert_true(inside > 0.05);
}

/* A tiny, very bright emitter (area 1e-8, Ke 1e7) over a floor: next-event estimation divides by
 * its area's pdf and by squared distances that may be tiny; no pixel may become NaN or infinite,
 * and none may be dropped as such. */
static void tiny_bright_emitter_stays_finite(void **state)
{
    (void)state;
    scene_dir_write("scene.obj", "mtllib scene.mtl\nusemtl floor\nv -1 0 -1\nv 1 0 -1\n"
                                 "v 1 0 1\nv -1 0 1\nf 1 4 3 2\nusemtl lamp\n"
                                 "v 0 0.5 0\nv 0.0001 0.5 0\nv 0 0.5 0.0002\nf 5 6 7\n");
    scene_dir_write("scene.mtl", "newmtl floor\nKd 0.5 0.5 0.5\nnewmtl lamp\nKd 0 0 0\n"
                                 "Ke 1e7 1e7 1e7\n");
    scene_dir_write("scene.cfg", "geometry scene.obj\nresolution 32 32\nmax-depth 4\n"
                                 "integrator path\n"
                                 "camera eye 0 2 2 look 0 0 0 up 0 1 0 fov 60\n");
    enum { N = 32 };
    float rgb[N * N * 3];
    vkrt_frame_stats stats;
    render_ok(N, N, &(vkrt_render_desc){.samples = 4}, rgb, &stats);
    for (int i = 0; i < N * N * 3; ++i)
        if (!isfinite(rgb[i]))
            fail_msg("value %d is %g", i, rgb[i]);
    assert_int_equal(stats.nonfinite, 0);
    /* The lamp's light reached the floor: E = I cos / d^2 with I = Ke * area (one-sided, facing
     * down: the winding 5 6 7 faces -y), so under it the floor shows about 0.5 / pi * 1e7 * 1e-8
     * / 0.25 = 0.064; held within a factor of two of that (the pixel is not quite under it). */
    double under = rgb[3 * (N / 2 * N + N / 2)];
    print_message("tiny emitter: floor under it %.4g\n", under);
    assert_true(under > 0.032 && under < 0.128);
}

/* Luminance of pixel i of an image. */
static double pixel_luminance(const float *rgb, int i)
{
    return 0.2126 * rgb[3 * i] + 0.7152 * rgb[3 * i + 1] + 0.0722 * rgb[3 * i + 2];
}

/* Whether images a and b of n pixels agree within 5 standard errors over pixels [first, end)
 * (row-major, width w, a square block of side `side` at (x0, y0)): the test is on the pixels'
 * paired differences, whose spread estimates the noise of their mean (the image's own content
 * cancels in the difference). Prints and returns false when they do not. */
static bool block_agrees(const float *a, const float *b, int w, int x0, int y0, int side,
                         const char *what)
{
    double sum = 0, sum2 = 0;
    int n = side * side;
    for (int y = y0; y < y0 + side; ++y)
        for (int x = x0; x < x0 + side; ++x) {
            double d = pixel_luminance(a, y * w + x) - pixel_luminance(b, y * w + x);
            sum += d;
            sum2 += d * d;
        }
    double mean = sum / n, se = sqrt(fmax(sum2 / n - mean * mean, 0) / (n - 1));
    if (fabs(mean) <= 5 * se + 1e-6)
        return true;
    print_message("%s, block (%d, %d) of side %d: mean difference %.5f, 5 se %.5f\n", what, x0, y0,
                  side, mean, 5 * se);
    return false;
}

/* Renders the folder's scene with MIS, light sampling alone and BSDF sampling alone at n x n
 * and spp, and asserts that the three agree on the whole image and on every 8x8 block. */
static void estimators_agree(int n, uint32_t spp)
{
    enum { B = 8 };
    static const uint32_t modes[] = {VKRT_SAMPLING_MIS, VKRT_SAMPLING_LIGHTS, VKRT_SAMPLING_BSDF};
    static const char *const names[] = {"MIS", "lights alone", "BSDF alone"};
    float *rgb[3];
    for (int m = 0; m < 3; ++m) {
        rgb[m] = malloc((size_t)n * n * 3 * sizeof *rgb[m]);
        render_ok(n, n, &(vkrt_render_desc){.samples = spp, .light_sampling = modes[m]}, rgb[m],
                  NULL);
        print_message("%s: image mean %.5f\n", names[m], mean_of(rgb[m], (size_t)n * n));
    }
    assert_true(mean_of(rgb[0], (size_t)n * n) > 0.05);
    bool all = true;
    for (int m = 1; m < 3; ++m) {
        all &= block_agrees(rgb[m], rgb[0], n, 0, 0, n, names[m]);
        for (int by = 0; by + B <= n; by += B)
            for (int bx = 0; bx + B <= n; bx += B)
                all &= block_agrees(rgb[m], rgb[0], n, bx, by, B, names[m]);
    }
    for (int m = 0; m < 3; ++m)
        free(rgb[m]);
    assert_true(all);
}

/* The lit room of the estimator tests: diffuse walls (material "wall"), an emissive ceiling
 * panel ("lamp"), and the boxes of `boxes` (material name, low and high corners), whose
 * materials `mtl` adds to the .mtl's wall and lamp; then the three estimators must agree. */
typedef struct {
    const char *material;
    double lo[3], hi[3];
} room_box;

static void room_estimators_agree(const room_box *boxes, int box_count, const char *mtl)
{
    FILE *f = scene_dir_open("room.obj");
    fprintf(f, "mtllib scene.mtl\n");
    int v = 1;
    write_box(f, "wall", (double[]){-1, 0, -1}, (double[]){1, 2, 1}, true, &v);
    fprintf(f, "usemtl lamp\nv -0.5 1.99 -0.5\nv 0.5 1.99 -0.5\nv 0.5 1.99 0.5\n"
               "v -0.5 1.99 0.5\nf %d %d %d %d\n", v, v + 1, v + 2, v + 3);
    v += 4;
    for (int i = 0; i < box_count; ++i)
        write_box(f, boxes[i].material, boxes[i].lo, boxes[i].hi, false, &v);
    fclose(f);
    char text[1024];
    snprintf(text, sizeof text, "newmtl wall\nKd 0.6 0.5 0.4\nnewmtl lamp\nKd 0 0 0\nKe 4 4 4\n%s",
             mtl);
    scene_dir_write("scene.mtl", text);
    scene_dir_write("scene.cfg", "geometry room.obj\nresolution 32 32\nmax-depth 5\n"
                                 "integrator path\n"
                                 "camera eye 0 1 0.95 look 0 0.7 0 up 0 1 0 fov 90\n");
    estimators_agree(32, 64);
}

/* Three estimators, one answer: MIS, light sampling alone and BSDF sampling alone converge to the
 * same image of a lit room (an emissive ceiling panel, a glossy box, diffuse walls): the whole
 * image and each 8x8 block agree within 5 standard errors of their paired difference. A wrong
 * weight (double counting, or a strategy left out) moves the means by tens of percent. */
static void three_estimators_agree(void **state)
{
    (void)state;
    static const room_box shiny = {"shiny", {-0.5, 0, -0.3}, {0, 0.8, 0.2}};
    room_estimators_agree(&shiny, 1,
                          "newmtl shiny\nillum 2\nKd 0.3 0.3 0.3\n"
                          "Ks 0.5 0.5 0.5\nNs 20\n");
}

/* The three estimators again, in the room with a rough metal box and a rough plastic one, as the
 * .mtl's PBR extension gives them (the pbr built-in, glsl/lib/microfacet.glsl): light samples
 * find the glossy lobes through bsdf_eval and its pdf, BSDF samples through bsdf_sample, so a
 * pdf that is not the sampler's density, or a value that is not the sampled one, splits them. */
static void rough_estimators_agree(void **state)
{
    (void)state;
    static const room_box boxes[] = {{"metal", {-0.6, 0, -0.3}, {-0.1, 0.8, 0.2}},
                                     {"coated", {0.1, 0, -0.4}, {0.6, 0.5, 0.1}}};
    room_estimators_agree(boxes, 2,
                          "newmtl metal\nKd 0.9 0.6 0.3\nPr 0.3\nPm 1\n"
                          "newmtl coated\nKd 0.2 0.4 0.7\nNi 1.5\nPr 0.2\nPm 0\n");
}

/* Writes a w x h Radiance HDR (flat RGBE scanlines, the top row first) whose pixel (x, y) has
 * the radiance pixel(x, y, rgb) gives. */
static void write_hdr(const char *name, int w, int h, void (*pixel)(int, int, float *))
{
    FILE *f = scene_dir_open(name);
    fprintf(f, "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n", h, w);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float c[3];
            pixel(x, y, c);
            float m = fmaxf(c[0], fmaxf(c[1], c[2]));
            unsigned char rgbe[4] = {0, 0, 0, 0};
            if (m > 1e-32f) {
                int e;
                float scale = frexpf(m, &e) * 256.0f / m;
                for (int k = 0; k < 3; ++k)
                    rgbe[k] = (unsigned char)(c[k] * scale);
                rgbe[3] = (unsigned char)(e + 128);
            }
            fwrite(rgbe, 1, 4, f);
        }
    fclose(f);
}

static void constant_sky(int x, int y, float *c)
{
    (void)x, (void)y;
    c[0] = c[1] = c[2] = 1.0f;
}

/* A sky that varies: dim blue, brighter to the horizon, and a small sun 64 times brighter. */
static void sunny_sky(int x, int y, float *c)
{
    bool sun = x >= 10 && x < 12 && y >= 4 && y < 6;
    c[0] = sun ? 64.0f : 0.2f + 0.05f * y;
    c[1] = sun ? 60.0f : 0.3f + 0.05f * y;
    c[2] = sun ? 50.0f : 0.6f;
}

/* The white furnace again, lit by an environment map of radiance 1 everywhere: the map's
 * importance sampling and its radiance lookup must agree for every pixel to come out 1. */
static void environment_map_furnace(void **state)
{
    (void)state;
    write_sphere("sphere.obj", "white", 12, 24);
    scene_dir_write("scene.mtl", "newmtl white\nKd 1 1 1\n");
    write_hdr("sky.hdr", 32, 16, constant_sky);
    scene_dir_write("scene.cfg", "geometry sphere.obj\nresolution 32 32\nmax-depth 64\n"
                                 "environment-map sky.hdr\n"
                                 "camera eye 0 0 3 look 0 0 0 up 0 1 0 fov 50\n");
    enum { N = 32 };
    float rgb[N * N * 3];
    vkrt_frame_stats stats;
    render_ok(N, N, &(vkrt_render_desc){.samples = 64}, rgb, &stats);
    double mean = mean_of(rgb, N * N);
    print_message("environment-map furnace: image mean %.5f (expected 1)\n", mean);
    assert_true(fabs(mean - 1.0) < 0.01);
    for (int i = 0; i < N * N * 3; ++i)
        if (!(fabsf(rgb[i] - 1.0f) < 0.25f))
            fail_msg("value %d is %g, not 1", i, rgb[i]);
}

/* A diffuse sphere on a floor under a sky with a sun: the three estimators agree, so the map's
 * pdf is the density its sampler draws from, and MIS weighs the map against the BSDF right. */
static void environment_map_estimators_agree(void **state)
{
    (void)state;
    FILE *f = scene_dir_open("scene.obj");
    fprintf(f, "mtllib scene.mtl\nusemtl floor\nv -3 -1 -3\nv 3 -1 -3\nv 3 -1 3\nv -3 -1 3\n"
               "f 1 4 3 2\n");
    fclose(f);
    write_sphere("sphere.obj", "white", 8, 16);
    scene_dir_write("scene.mtl", "newmtl floor\nKd 0.5 0.5 0.5\nnewmtl white\nKd 0.8 0.7 0.6\n");
    write_hdr("sky.hdr", 32, 16, sunny_sky);
    scene_dir_write("scene.cfg", "geometry scene.obj\nresolution 32 32\nmax-depth 3\n"
                                 "environment-map sky.hdr scale 0.5 rotate 30\n"
                                 "camera eye 0 2 4 look 0 -0.5 0 up 0 1 0 fov 60\n");
    estimators_agree(32, 64);
}

/* A sky lit in its upper half: 1 in the top rows, 0 in the bottom ones. */
static void upper_half_sky(int x, int y, float *c)
{
    (void)x;
    c[0] = c[1] = c[2] = y < 4 ? 1.0f : 0.0f;
}

/* Looking straight up at a map whose top rows are 1 and bottom rows 0, every pixel is 1, and
 * straight down 0: the lookup clamps at the poles instead of wrapping from one to the other (the
 * top row's upper half used to blend with the bottom row, 0.5 at the zenith). */
static void environment_map_poles_do_not_wrap(void **state)
{
    (void)state;
    /* One small triangle behind the camera: a scene needs geometry. */
    scene_dir_write("scene.obj", "v 0 -10 0\nv 0.1 -10 0\nv 0 -10 0.1\nf 1 2 3\n");
    write_hdr("sky.hdr", 16, 8, upper_half_sky);
    enum { N = 16 };
    const char *views[2] = {"look 0 1 0", "look 0 -1 0"};
    for (int down = 0; down < 2; ++down) {
        char cfg[256];
        snprintf(cfg, sizeof cfg,
                 "geometry scene.obj\nresolution 16 16\nenvironment-map sky.hdr\n"
                 "camera eye 0 0 0 %s up 0 0 -1 fov 20\n",
                 views[down]);
        scene_dir_write("scene.cfg", cfg);
        float rgb[N * N * 3];
        vkrt_frame_stats stats;
        render_ok(N, N, &(vkrt_render_desc){.samples = 1}, rgb, &stats);
        for (int i = 0; i < N * N * 3; ++i)
            if (!(fabsf(rgb[i] - (down ? 0.0f : 1.0f)) < 1e-3f))
                fail_msg("looking %s, value %d is %g", down ? "down" : "up", i, rgb[i]);
    }
}

/* A thin emissive stripe, 0.02 wide and 10 tall, 10 down -z, facing +z. */
static void write_stripe(void)
{
    scene_dir_write("stripe.obj", "mtllib stripe.mtl\nusemtl lamp\n"
                                  "v -0.01 -5 -10\nv 0.01 -5 -10\nv 0.01 5 -10\nv -0.01 5 -10\n"
                                  "f 1 2 3 4\n");
    scene_dir_write("stripe.mtl", "newmtl lamp\nKd 0 0 0\nKe 1 1 1\n");
}

/* The spread (standard deviation, in pixels) of an image's light across its columns: the
 * second moment of the column sums about their centroid. */
static double column_spread(const float *rgb, int w, int h)
{
    double sum = 0, first = 0, second = 0;
    for (int x = 0; x < w; ++x) {
        double column = 0;
        for (int y = 0; y < h; ++y)
            column += rgb[3 * (y * w + x)];
        sum += column;
        first += column * (x + 0.5);
        second += column * (x + 0.5) * (x + 0.5);
    }
    double mean = first / sum;
    return sqrt(second / sum - mean * mean);
}

/* Depth of field, against its closed form: a thin emissive stripe (0.02 wide, 10 away) seen
 * through a lens of radius A focused at distance f. Its every point spreads on the plane in focus
 * into a disc of radius A |10 - f| / 10 (similar triangles through the lens), R pixels across
 * the image; a vertical line's light then spreads sideways as the projection of that disc, whose
 * variance is R^2 / 4, on top of the stripe's own width and the pixels' binning (1/12 each, in
 * squared pixels). In focus (f = 10), the stripe is as sharp as through a pinhole. Both integrators:
 * path draws the lens from the sampler, whitted from a stream of its own. */
static void thin_lens_blurs_by_its_circle_of_confusion(void **state)
{
    (void)state;
    write_stripe();
    enum { N = 64 };
    const double fov = 20.0, aperture = 0.2, width_px = 0.02 / (2 * 10 * tan(fov * M_PI / 360) / N);
    const char *integrators[2] = {"path", "whitted"};
    static float rgb[N * N * 3];
    for (int i = 0; i < 2; ++i) {
        for (int focused = 0; focused < 2; ++focused) {
            double f = focused ? 10.0 : 5.0;
            char cfg[512];
            snprintf(cfg, sizeof cfg,
                     "geometry stripe.obj\nresolution %d %d\nintegrator %s\n"
                     "camera eye 0 0 0 look 0 0 -1 up 0 1 0 fov %g aperture %g focus %g\n",
                     N, N, integrators[i], fov, aperture, f);
            scene_dir_write("scene.cfg", cfg);
            vkrt_frame_stats stats;
            render_ok(N, N, &(vkrt_render_desc){.samples = 256}, rgb, &stats);
            double pixel_at_focus = 2 * f * tan(fov * M_PI / 360) / N;
            double radius_px = aperture * fabs(10 - f) / 10 / pixel_at_focus;
            double want = sqrt(radius_px * radius_px / 4 + width_px * width_px / 12 + 1.0 / 12);
            double got = column_spread(rgb, N, N);
            if (focused) { /* binning a line into pixels is not smooth: compare with a pinhole */
                snprintf(cfg, sizeof cfg,
                         "geometry stripe.obj\nresolution %d %d\nintegrator %s\n"
                         "camera eye 0 0 0 look 0 0 -1 up 0 1 0 fov %g\n",
                         N, N, integrators[i], fov);
                scene_dir_write("scene.cfg", cfg);
                render_ok(N, N, &(vkrt_render_desc){.samples = 256}, rgb, &stats);
                want = column_spread(rgb, N, N);
            }
            print_message("thin lens, %s, focus %g: spread %.3f pixels, expected %.3f\n",
                          integrators[i], f, got, want);
            assert_true(fabs(got - want) < 0.05 * want + 0.05);
        }
    }
}

/* The light-weighted mean column of an image (its centroid across), in pixels from the left. */
static double column_centroid(const float *rgb, int w, int h)
{
    double sum = 0, first = 0;
    for (int x = 0; x < w; ++x)
        for (int y = 0; y < h; ++y) {
            sum += rgb[3 * (y * w + x)];
            first += rgb[3 * (y * w + x)] * (x + 0.5);
        }
    return first / sum;
}

/* Motion blur along a flythrough, against its closed form: the camera moves 0.5 sideways between
 * two frames, past the emissive stripe of the thin-lens test 10 away; with the shutter open for a
 * share S of the interval, the stripe sweeps D = S * 0.5 / (pixel size at 10) pixels, uniformly
 * in time: a box of width D, whose variance D^2 / 12 adds to the stripe's and the binning's, and
 * whose centroid is D / 2 from where the still camera sees the stripe (the image's middle). With
 * the shutter at 0 the stripe stays sharp. (The orientation's slerp: tests/test_camera_motion.c.) */
static void motion_blur_smears_by_the_distance_travelled(void **state)
{
    (void)state;
    write_stripe();
    enum { N = 64 };
    const double fov = 20.0, pixel = 2 * 10 * tan(fov * M_PI / 360) / N, width_px = 0.02 / pixel;
    static float rgb[N * N * 3];
    const struct {
        const char *integrator;
        double shutter;
    } cases[] = {{"path", 1.0}, {"whitted", 1.0}, {"path", 0.5}, {"path", 0.0}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        char cfg[512];
        snprintf(cfg, sizeof cfg,
                 "geometry stripe.obj\nresolution %d %d\nintegrator %s\nshutter %g\n"
                 "camera eye 0 0 0 look 0 0 -1 up 0 1 0 fov %g\n"
                 "camera eye 0.5 0 0 look 0.5 0 -1 up 0 1 0 fov %g\n",
                 N, N, cases[i].integrator, cases[i].shutter, fov, fov);
        scene_dir_write("scene.cfg", cfg);
        vkrt_frame_stats stats;
        render_ok(N, N, &(vkrt_render_desc){.samples = 256}, rgb, &stats);
        double d = cases[i].shutter * 0.5 / pixel;
        double want = sqrt(d * d / 12 + width_px * width_px / 12 + 1.0 / 12);
        double got = column_spread(rgb, N, N), centre = column_centroid(rgb, N, N);
        print_message("motion blur, %s, shutter %g: spread %.3f pixels (closed form %.3f), "
                      "centroid %.3f (closed form %.3f)\n",
                      cases[i].integrator, cases[i].shutter, got, want, centre, N / 2 - d / 2);
        if (cases[i].shutter > 0)
            assert_true(fabs(got - want) < 0.05 * want + 0.05);
        else
            assert_true(got < 0.6); /* the stripe within a column or two */
        assert_true(fabs(centre - (N / 2 - d / 2)) < 0.1);
    }
}

/* --seed: a render's noise is a function of its seed. The same seed twice gives the same image
 * (up to the order of the float atomic adds: 1e-4 relative), another seed an image whose
 * difference is noise, the size of the noise itself (the images' difference has twice the
 * variance of either: about the spread of a pixel over seeds). */
static void seeds_give_independent_noise(void **state)
{
    (void)state;
    write_sphere("sphere.obj", "white", 8, 16);
    scene_dir_write("scene.mtl", "newmtl white\nKd 0.8 0.8 0.8\n");
    scene_dir_write("scene.cfg", "geometry sphere.obj\nresolution 16 16\nmax-depth 4\n"
                                 "environment 1 1 1\n"
                                 "camera eye 0 0 3 look 0 0 0 up 0 1 0 fov 50\n");
    enum { N = 16 };
    float a[N * N * 3], b[N * N * 3], c[N * N * 3];
    vkrt_frame_stats stats;
    render_ok(N, N, &(vkrt_render_desc){.samples = 4, .seed = 5}, a, &stats);
    render_ok(N, N, &(vkrt_render_desc){.samples = 4, .seed = 5}, b, &stats);
    render_ok(N, N, &(vkrt_render_desc){.samples = 4, .seed = 6}, c, &stats);
    double same = 0, other = 0;
    for (int i = 0; i < N * N * 3; ++i) {
        same = fmax(same, fabs(a[i] - b[i]) / fmax(fabs(a[i]), 1e-3));
        other += (a[i] - c[i]) * (a[i] - c[i]);
    }
    other = sqrt(other / (N * N * 3));
    print_message("seeds: same seed differs by %.2g (relative), another by %.3g (rms)\n", same,
                  other);
    assert_true(same < 1e-4);
    assert_true(other > 1e-2);
}

/* A w x h 32-bit TGA (uncompressed, the top row first) whose left half has alpha 0 and right half
 * alpha 255, colour white: foliage's kind of texture, alpha carrying coverage. */
static void write_half_cut_tga(const char *name, int w, int h)
{
    FILE *f = scene_dir_open(name);
    unsigned char header[18] = {0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, (unsigned char)w,
                                (unsigned char)(w >> 8), (unsigned char)h,
                                (unsigned char)(h >> 8), 32, 8 | 0x20};
    fwrite(header, 1, sizeof header, f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            unsigned char bgra[4] = {255, 255, 255, x < w / 2 ? 0 : 255};
            fwrite(bgra, 1, 4, f);
        }
    fclose(f);
}

/* A card with an RGBA map_Kd (no map_d) whose left half is transparent, above a floor, under a
 * directional light from straight above, seen from above at a slant: through the left half the
 * camera sees the floor, and the floor under the left half is lit while under the right half it
 * lies in the card's shadow. In both integrators, with each structure. */
static void cutouts_cut_every_ray(void **state)
{
    (void)state;
    write_half_cut_tga("leaf.tga", 16, 16);
    /* The card: x in [-1, 1] at height 1, uv u = (x + 1) / 2; the floor: a large quad at 0. */
    scene_dir_write("scene.obj", "mtllib scene.mtl\nusemtl floor\nv -4 0 -4\nv 4 0 -4\nv 4 0 4\n"
                                 "v -4 0 4\nf 1 4 3 2\nusemtl leaf\nv -1 1 -1\nv 1 1 -1\n"
                                 "v 1 1 1\nv -1 1 1\nvt 0 1\nvt 1 1\nvt 1 0\nvt 0 0\n"
                                 "f 5/1 8/4 7/3 6/2\n");
    scene_dir_write("scene.mtl", "newmtl floor\nKd 0.5 0.5 0.5\nnewmtl leaf\nKd 0.2 0.8 0.2\n"
                                 "map_Kd leaf.tga\n");
    enum { N = 32 };
    static const char *const integrators[] = {"whitted", "path"};
    for (int k = 0; k < 2; ++k) {
        char cfg[512];
        snprintf(cfg, sizeof cfg,
                 "geometry scene.obj\nresolution 32 32\nmax-depth 2\nintegrator %s\n"
                 "light directional 0 -1 0  1 1 1\n"
                 "camera eye 0 3 0.01 look 0 0 0 up 0 0 -1 fov 90\n",
                 integrators[k]);
        scene_dir_write("scene.cfg", cfg);
        for (int a = 0; a < 3; ++a) {
            static const vkrt_accel_kind kinds[] = {VKRT_ACCEL_BRUTE, VKRT_ACCEL_GRID,
                                                    VKRT_ACCEL_BVH};
            float rgb[N * N * 3];
            render_ok(N, N, &(vkrt_render_desc){.samples = 4, .accel = kinds[a]}, rgb, NULL);
            /* Straight down: x in [-3, 3] across the picture; the card spans the middle third.
             * Row 16 (z near 0): pixel 12 looks at x = -0.56 (through the cut half, onto lit
             * floor), pixel 20 at x = +0.56 (the card itself, green), pixel 4 at x = -2.2
             * (open floor, lit), and pixel 28 at x = +2.2 (open floor, lit). The floor seen
             * through the hole is lit: the light passed the same hole. */
            const float *hole = &rgb[3 * (16 * N + 12)], *card = &rgb[3 * (16 * N + 20)];
            const float *open = &rgb[3 * (16 * N + 4)];
            print_message("%s, %s: open floor %.3f, through the hole %.3f, card %.3f %.3f\n",
                          integrators[k], vkrt_accel_name(kinds[a]), open[1], hole[1], card[0],
                          card[1]);
            double lit = 0.5 / M_PI; /* Kd / pi times the irradiance 1 */
            assert_true(fabs(open[1] - lit) < 0.2 * lit);
            assert_true(fabs(hole[1] - open[1]) < 0.2 * lit); /* seen, and lit, through it */
            assert_true(card[1] > 2 * card[0]);              /* the card is green */
        }
    }
    /* The floor under the card, seen from the side below it: lit under the cut half (x < 0),
     * in shadow under the opaque half (x > 0). Pixel 11 of the middle row looks at x = -0.5,
     * pixel 21 at x = +0.5 (the half-width there is tan(20 deg) * 4.03 = 1.47). */
    for (int k = 0; k < 2; ++k) {
        char cfg[512];
        snprintf(cfg, sizeof cfg,
                 "geometry scene.obj\nresolution 32 32\nmax-depth 2\nintegrator %s\n"
                 "light directional 0 -1 0  1 1 1\n"
                 "camera eye 0 0.5 4 look 0 0 0 up 0 1 0 fov 40\n",
                 integrators[k]);
        scene_dir_write("scene.cfg", cfg);
        float rgb[N * N * 3];
        render_ok(N, N, &(vkrt_render_desc){.samples = 4}, rgb, NULL);
        double lit = 0.5 / M_PI, under_hole = rgb[3 * (16 * N + 11) + 1],
               under_card = rgb[3 * (16 * N + 21) + 1];
        print_message("%s: floor under the hole %.3f, under the card %.3f\n", integrators[k],
                      under_hole, under_card);
        assert_true(fabs(under_hole - lit) < 0.3 * lit);
        assert_true(under_card < 0.5 * under_hole);
    }
}

/* Renders the folder's scene (sampling by mode, w x w pixels) with one renderer, reading its
 * image after each of the sample counts `ends` (increasing; the last is the renderer's samples):
 * rgb[k] is the mean of samples 0 .. ends[k] - 1, as a render at ends[k] samples would be. */
static void render_prefixes(int w, uint32_t mode, const uint32_t *ends, int n, float **rgb)
{
    char path[256];
    snprintf(path, sizeof path, "%s/scene.cfg", scene_dir);
    vkrt_error err = {{0}};
    vkrt_scene scene;
    if (!vkrt_scene_load(path, &scene, &err))
        fail_msg("scene: %s", err.msg);
    gpu_context ctx;
    fixture_context_create(&ctx);
    vkrt_renderer *r = NULL;
    bool ok = vkrt_renderer_create(&r, &ctx, &scene,
                                   &(vkrt_render_desc){.width = w, .height = w,
                                                       .samples = ends[n - 1],
                                                       .light_sampling = mode},
                                   &err);
    for (int k = 0; ok && k < n; ++k)
        ok = vkrt_renderer_add_samples(r, &scene.cameras[0], 0, k ? ends[k - 1] : 0,
                                       ends[k] - (k ? ends[k - 1] : 0), NULL, &err) &&
             vkrt_renderer_read_image(r, ends[k], rgb[k], &err);
    vkrt_renderer_destroy(r);
    fixture_context_destroy(&ctx);
    vkrt_scene_free(&scene);
    if (!ok)
        fail_msg("render: %s", err.msg);
}

/* N times the mean squared error of the folder's scene at N samples per pixel over that at one
 * sample, both against its first 512 samples (sampling by mode, w x w pixels): about 1 where a
 * pixel's samples are independent (the variance of a mean of N falls as 1/N), well under 1 where
 * the sampler stratifies the dimensions the estimate depends on. */
static double stratification_gain(int w, uint32_t mode, const char *what)
{
    enum { N = 64, CONVERGED = 512 };
    static const uint32_t ends[] = {1, N, CONVERGED};
    float *rgb[3];
    for (int k = 0; k < 3; ++k)
        rgb[k] = malloc((size_t)w * w * 3 * sizeof *rgb[k]);
    render_prefixes(w, mode, ends, 3, rgb);
    double mse[2] = {0, 0};
    for (int k = 0; k < 2; ++k)
        for (int i = 0; i < w * w; ++i) {
            double d = pixel_luminance(rgb[k], i) - pixel_luminance(rgb[2], i);
            mse[k] += d * d / (w * w);
        }
    double gain = N * mse[1] / mse[0], mean = mean_of(rgb[2], (size_t)w * w);
    print_message("%s: image mean %.4f, mean squared error %.3g at 1 spp, %.3g at %d spp: "
                  "%d x %.3g / %.3g = %.3f\n", what, mean, mse[0], mse[1], N, N, mse[1], mse[0],
                  gain);
    for (int k = 0; k < 3; ++k)
        free(rgb[k]);
    assert_true(mean > 0.02); /* lit: the errors are of something */
    return gain;
}

/* Every dimension of a path is stratified over a pixel's samples (glsl/lib/sampler.glsl), not
 * only its position in the pixel: a diffuse floor lit by a square lamp, direct light only
 * (max-depth 0), seen at 64 samples per pixel, has well under 1/64 of the squared error of one
 * sample when its numbers are: with light sampling alone (the lamp's triangle and the point on
 * it), with BSDF sampling alone (the cosine-weighted direction), and with light sampling of a
 * uniform sky. Independent numbers, as the hash streams drew, give a gain of about 0.9 (the
 * reference shares the first 64 samples: (7/8)^2 (1 + 1/7) = 7/8); the sampler gave 0.31, 0.16 and
 * 0.14, and hash streams in its place for those numbers 0.85, 0.92 and 0.99. The camera sees a
 * small patch of floor under the lamp, so that the light across a pixel, which the jitter
 * averages, is close to constant and the error is the light sample's. */
static void samples_are_stratified(void **state)
{
    (void)state;
    scene_dir_write("scene.obj", "mtllib scene.mtl\nusemtl floor\nv -1 0 -1\nv 1 0 -1\n"
                                 "v 1 0 1\nv -1 0 1\nf 1 4 3 2\nusemtl lamp\n"
                                 "v -0.4 1 -0.4\nv 0.4 1 -0.4\nv 0.4 1 0.4\nv -0.4 1 0.4\n"
                                 "f 5 6 7 8\n");
    scene_dir_write("scene.mtl", "newmtl floor\nKd 0.7 0.7 0.7\nnewmtl lamp\nKd 0 0 0\n"
                                 "Ke 3 3 3\n");
    const char *camera = "camera eye 0 0.6 0.8 look 0 0 0 up 0 1 0 fov 15\n";
    char cfg[512];
    snprintf(cfg, sizeof cfg, "geometry scene.obj\nresolution 16 16\nmax-depth 0\n"
                              "integrator path\n%s", camera);
    scene_dir_write("scene.cfg", cfg);
    assert_true(stratification_gain(16, VKRT_SAMPLING_LIGHTS, "lamp, light samples") < 0.5);
    assert_true(stratification_gain(16, VKRT_SAMPLING_BSDF, "lamp, BSDF samples") < 0.5);
    snprintf(cfg, sizeof cfg, "geometry scene.obj\nresolution 16 16\nmax-depth 0\n"
                              "integrator path\nenvironment 0.5 0.5 0.5\n%s", camera);
    scene_dir_write("scene.cfg", cfg);
    assert_true(stratification_gain(16, VKRT_SAMPLING_LIGHTS, "sky, light samples") < 0.5);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(white_furnace),
        cmocka_unit_test(closed_box_leaks_nothing),
        cmocka_unit_test(tiny_bright_emitter_stays_finite),
        cmocka_unit_test(three_estimators_agree),
        cmocka_unit_test(rough_estimators_agree),
        cmocka_unit_test(environment_map_furnace),
        cmocka_unit_test(environment_map_estimators_agree),
        cmocka_unit_test(environment_map_poles_do_not_wrap),
        cmocka_unit_test(thin_lens_blurs_by_its_circle_of_confusion),
        cmocka_unit_test(seeds_give_independent_noise),
        cmocka_unit_test(motion_blur_smears_by_the_distance_travelled),
        cmocka_unit_test(cutouts_cut_every_ray),
        cmocka_unit_test(samples_are_stratified),
    };
    return cmocka_run_group_tests(tests, scene_dir_make, scene_dir_remove);
}
