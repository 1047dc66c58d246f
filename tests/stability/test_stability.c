/*
 * test_stability.c: the stability suite. Each case sets up what is known to break naive ray
 * tracers, says how they fail, and asserts what vkrt does instead. Cases covered elsewhere are
 * listed in docs/speed-vs-accuracy.md with the test that holds them (the teapot in a stadium,
 * shared edges and vertices, scale and offset, NaN in the input).
 *
 * Every case renders through the real renderer with every acceleration structure, so a fault of
 * one traversal shows as a difference between them.
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

#include "../scene_dir.h"
#include "render/renderer.h"
#include "scene/scene.h"

/* A structure to render with: a kind and, for the BVH, whether it splits triangles. */
typedef struct structure {
    vkrt_accel_kind kind;
    vkrt_bvh_splits splits;
    const char *name;
    uint32_t max_leaf;    /* the BVH's largest leaf; 0: the device's default */
    float spatial_budget; /* the BVH's share of duplicate references; 0: the default */
} structure;

/* The spatial splits' tree of these little scenes is built with leaves of one triangle and the
 * largest budget (BVH_MAX_SPATIAL_BUDGET, +100%): at the defaults (leaves of 8, +30%) the
 * 14 triangles of a cube on a floor split none, and what the suite holds here is the split tree,
 * clipped boxes that meet at split planes included. */
#define SPLIT_TREE_MAX_LEAF 1
#define SPLIT_TREE_BUDGET 1.0f

static const structure all_kinds[] = {
    {VKRT_ACCEL_BRUTE, VKRT_BVH_SPLITS_AUTO, "brute"},
    {VKRT_ACCEL_GRID, VKRT_BVH_SPLITS_AUTO, "grid"},
    {VKRT_ACCEL_BVH, VKRT_BVH_SPLITS_OFF, "bvh"},
    {VKRT_ACCEL_BVH, VKRT_BVH_SPLITS_ON, "bvh with spatial splits", SPLIT_TREE_MAX_LEAF,
     SPLIT_TREE_BUDGET},
    {VKRT_ACCEL_KDTREE, VKRT_BVH_SPLITS_AUTO, "kdtree"},
};
enum { KINDS = sizeof all_kinds / sizeof *all_kinds };

/* Renders the folder's scene.cfg at w x h with the given structure; fails the test on error,
 * and when a tree with spatial splits holds no triangle twice (it would be the plain tree). */
static void render_as(const structure *s, uint32_t w, uint32_t h, float *rgb,
                      vkrt_frame_stats *stats)
{
    vkrt_error err = {{0}};
    vkrt_render_desc desc = {.accel = s->kind, .bvh_splits = s->splits,
                             .tuning = {.bvh_max_leaf = s->max_leaf,
                                        .bvh_spatial_budget = s->spatial_budget}};
    vkrt_accel_stats accel;
    if (!scene_dir_render_accel(w, h, &desc, rgb, stats, &accel, &err))
        fail_msg("%s: %s", s->name, err.msg);
    if (s->splits != VKRT_BVH_SPLITS_ON)
        return;
    print_message("%s: %u triangles, %u references\n", s->name, accel.triangles, accel.references);
    if (accel.references <= accel.triangles)
        fail_msg("%s: no triangle in two leaves (%s)", s->name, accel.reason);
}

/* Renders with the structure of that kind (the BVH with its default splits). */
static void render(vkrt_accel_kind kind, uint32_t w, uint32_t h, float *rgb, vkrt_frame_stats *stats)
{
    render_as(&(structure){kind, VKRT_BVH_SPLITS_AUTO, vkrt_accel_name(kind)}, w, h, rgb, stats);
}

static void assert_all_finite(const float *rgb, size_t n, const char *what)
{
    for (size_t i = 0; i < n; ++i)
        if (!isfinite(rgb[i]))
            fail_msg("%s: value %zu is %g", what, i, rgb[i]);
}

/* A floor y = 0, [-10, 10]^2, seen from above: camera at height 10, fov 60, up +z. */
static const char floor_obj[] = "v -10 0 -10\nv 10 0 -10\nv 10 0 10\nv -10 0 10\nf 1 4 3 2\n";
static const char floor_camera[] = "camera eye 0 10 0 look 0 0 0 up 0 0 1 fov 60\n";

/* Where the ray of pixel (x, y) of an N x N picture of floor_camera meets the floor. */
static void floor_point(int x, int y, int n, double *px, double *pz)
{
    double t = tan(M_PI / 6) * 10;
    *px = -(2 * (x + 0.5) / n - 1) * t;
    *pz = (1 - 2 * (y + 0.5) / n) * t;
}

/* 100 point lights. Naive: a fixed-size light loop or a single 32-bit visibility mask silently
 * drops lights past the 32nd; per-light shadow storage grows with the light count. vkrt keeps one
 * bit per light in as many words as needed: the floor's radiance is the closed-form sum of all
 * 100 (albedo / pi * I * h / d^3 each). */
static void test_hundred_lights_sum_in_closed_form(void **state)
{
    (void)state;
    FILE *f = scene_dir_open("scene.cfg");
    fprintf(f, "geometry floor.obj\n%s", floor_camera);
    double lights[100][3];
    for (int i = 0; i < 100; ++i) {
        lights[i][0] = -6 + 12.0 * (i % 10) / 9;
        lights[i][1] = 1 + 0.05 * i;
        lights[i][2] = -6 + 12.0 * (i / 10) / 9;
        fprintf(f, "light point %.9g %.9g %.9g  %g %g %g\n", lights[i][0], lights[i][1],
                lights[i][2], 1.0 + i % 7, 1.0 + i % 5, 1.0 + i % 3);
    }
    fclose(f);
    scene_dir_write("floor.obj", floor_obj);
    enum { N = 16 };
    float rgb[N * N * 3];
    render(VKRT_ACCEL_BVH, N, N, rgb, NULL);
    for (int y = 0; y < N; ++y)
        for (int x = 0; x < N; ++x) {
            double px, pz, want[3] = {0, 0, 0};
            floor_point(x, y, N, &px, &pz);
            for (int i = 0; i < 100; ++i) {
                double dx = lights[i][0] - px, dy = lights[i][1], dz = lights[i][2] - pz;
                double d = sqrt(dx * dx + dy * dy + dz * dz);
                double g = 0.8 / M_PI * dy / (d * d * d); /* default albedo 0.8 */
                want[0] += g * (1.0 + i % 7);
                want[1] += g * (1.0 + i % 5);
                want[2] += g * (1.0 + i % 3);
            }
            for (int k = 0; k < 3; ++k) {
                double got = rgb[3 * (y * N + x) + k];
                if (fabs(got - want[k]) > 1e-4 * want[k])
                    fail_msg("pixel %d %d channel %d: %.7g, the 100 lights give %.7g", x, y, k,
                             got, want[k]);
            }
        }
}

/* A light inside a closed box. Naive: shadow rays that start on the far side of a wall (a fixed
 * epsilon too large) or skip the triangle they start on let the light leak out. vkrt: the outside
 * of the box gets exactly nothing, the floor under the box's light inside cannot be seen. Seen
 * from above, the ground around the box is dark and the lid is dark: every pixel is 0. */
static void test_light_inside_a_closed_box_does_not_leak(void **state)
{
    (void)state;
    scene_dir_write("box.obj",
               /* ground */
               "v -10 0 -10\nv 10 0 -10\nv 10 0 10\nv -10 0 10\n"
               /* a closed cube [-1, 1] x [0.5, 2.5] x [-1, 1] */
               "v -1 0.5 -1\nv 1 0.5 -1\nv 1 2.5 -1\nv -1 2.5 -1\n"
               "v -1 0.5 1\nv 1 0.5 1\nv 1 2.5 1\nv -1 2.5 1\n"
               "f 1 4 3 2\n"
               "f 5 8 7 6\nf 9 10 11 12\nf 5 6 10 9\nf 8 12 11 7\nf 5 9 12 8\nf 6 7 11 10\n");
    scene_dir_write("scene.cfg", "geometry box.obj\nlight point 0 1.5 0  1000 1000 1000\n"
                            "camera eye 3 8 2 look 0 0 0 up 0 1 0 fov 70\n");
    enum { N = 32 };
    static float rgb[N * N * 3];
    for (size_t k = 0; k < sizeof all_kinds / sizeof *all_kinds; ++k) {
        render_as(&all_kinds[k], N, N, rgb, NULL);
        for (int i = 0; i < N * N * 3; ++i)
            if (rgb[i] != 0.0f)
                fail_msg("%s: value %d is %g: light leaked out of the box",
                         all_kinds[k].name, i, rgb[i]);
    }
    /* The control: without its lid the same box lets light out, so the black above was the
     * box's doing, not a black renderer. */
    scene_dir_write("box.obj", "v -10 0 -10\nv 10 0 -10\nv 10 0 10\nv -10 0 10\n"
                          "v -1 0.5 -1\nv 1 0.5 -1\nv 1 2.5 -1\nv -1 2.5 -1\n"
                          "v -1 0.5 1\nv 1 0.5 1\nv 1 2.5 1\nv -1 2.5 1\n"
                          "f 1 4 3 2\nf 5 8 7 6\nf 9 10 11 12\nf 5 6 10 9\nf 5 9 12 8\nf 6 7 11 10\n");
    render(VKRT_ACCEL_BVH, N, N, rgb, NULL);
    int lit = 0;
    for (int i = 0; i < N * N * 3; ++i)
        lit += rgb[i] > 0.0f;
    assert_true(lit > 20); /* the inside walls, seen through the open top */
}

/* Writes bumpy.obj and scene.cfg: a sphere of radius 100 with bumps 6% high, of 96 x 192 quads
 * (triangles about 3 units across), centre (o, o, o), lit by a directional light that grazes the
 * bumps (they shadow each other over the half of the lit side nearest the terminator), seen from
 * 300 units away. The camera moves with the sphere; the light, directional, needs no moving. */
static void write_bumpy_sphere(double o)
{
    enum { LAT = 96, LON = 192 };
    FILE *f = scene_dir_open("bumpy.obj");
    fprintf(f, "v %.17g %.17g %.17g\n", o, o + 100, o);
    for (int i = 1; i < LAT; ++i)
        for (int j = 0; j < LON; ++j) {
            double th = M_PI * i / LAT, ph = 2 * M_PI * j / LON;
            double r = 100 * (1 + 0.06 * sin(9 * th) * sin(11 * ph));
            fprintf(f, "v %.17g %.17g %.17g\n", o + r * sin(th) * cos(ph), o + r * cos(th),
                    o + r * sin(th) * sin(ph));
        }
    fprintf(f, "v %.17g %.17g %.17g\n", o, o - 100, o);
    int bottom = 2 + (LAT - 1) * LON;
    for (int j = 0; j < LON; ++j) {
        int k = (j + 1) % LON;
        fprintf(f, "f 1 %d %d\n", 2 + k, 2 + j);
        fprintf(f, "f %d %d %d\n", bottom, 2 + (LAT - 2) * LON + j, 2 + (LAT - 2) * LON + k);
        for (int i = 1; i < LAT - 1; ++i) {
            int a = 2 + (i - 1) * LON, b = a + LON;
            fprintf(f, "f %d %d %d %d\n", a + j, a + k, b + k, b + j);
        }
    }
    fclose(f);
    char cfg[512];
    snprintf(cfg, sizeof cfg,
             "geometry bumpy.obj\nlight directional -1 -0.35 -0.25  3 3 3\n"
             "camera eye %.17g %.17g %.17g look %.17g %.17g %.17g up 0 1 0 fov 45\n",
             o + 150, o + 40, o + 250, o, o, o);
    scene_dir_write("scene.cfg", cfg);
}

/* A self-shadowing mesh moved far from the origin. Naive: a fixed epsilon makes acne far away;
 * an offset that grows with the distance from the origin faster than the rounding of the
 * coordinates there (vkrt's was 256 ULPs of the largest coordinate) soon reaches past the
 * neighbouring bumps that shadow a grazing point, and the shadows' edges brighten as the scene
 * moves. vkrt: the bumpy sphere at offsets 1e2, 1e4 and 1e5 against the same at offset 1, with the
 * BVH (the offset is the same code for every structure, and brute force, the grid and the BVH
 * gave the same numbers to the last digit when measured; one structure keeps CI's time: brute
 * force over its 37,000 triangles takes minutes on a CPU device). Two measures: the change of the
 * image's mean, and the share of lit pixels that change by more than 5%.
 * What moving must change: at 1e5 the float spacing is 2^-7 = 0.008, so vertices and the camera
 * move by up to 0.004 (4e-5 of the radius), which tilts facets and shifts shadow edges and the
 * silhouette by a fraction of a pixel. With the smallest offset that still has no acne (2 ULPs
 * of the coordinates, against 8 in vkrt; 0 shadows half the lit points) the sphere at 1e5 moves
 * by +0.010% in the mean and 0.50% of its pixels by more than 5%: that is the floor. The
 * tolerances are 10 and 2 times that floor; 256 ULPs of the coordinates gave +0.21% at 1e4 and
 * +1.14% (3.4% of pixels) at 1e5, 16 ULPs +0.14% at 1e5, and both fail. */
static void test_self_shadows_hold_far_from_the_origin(void **state)
{
    (void)state;
    const double MEAN_TOLERANCE = 1e-3, MOVED_TOLERANCE = 1e-2;
    enum { N = 128 };
    static const double offsets[] = {1e2, 1e4, 1e5};
    /* the BVH, and the BVH with spatial splits (whose clipped boxes are rounded outwards) */
    static const structure *const kinds[] = {&all_kinds[2], &all_kinds[3]};
    static float base[N * N * 3], moved[N * N * 3];
    for (size_t k = 0; k < sizeof kinds / sizeof *kinds; ++k) {
        write_bumpy_sphere(1);
        render_as(kinds[k], N, N, base, NULL);
        for (size_t c = 0; c < sizeof offsets / sizeof *offsets; ++c) {
            write_bumpy_sphere(offsets[c]);
            render_as(kinds[k], N, N, moved, NULL);
            assert_all_finite(moved, N * N * 3, kinds[k]->name);
            double sum_base = 0, sum_moved = 0;
            int lit = 0, moved_pixels = 0;
            for (int i = 0; i < N * N; ++i) {
                const float *b = base + 3 * i, *m = moved + 3 * i;
                double lb = b[0] + b[1] + b[2], lm = m[0] + m[1] + m[2];
                sum_base += lb;
                sum_moved += lm;
                lit += lb > 0 || lm > 0;
                moved_pixels += fabs(lm - lb) > 0.05 * lb;
            }
            double mean = sum_moved / sum_base - 1, share = (double)moved_pixels / lit;
            print_message("%s, offset %g: mean %+.4f%%, %.2f%% of %d lit pixels moved by more "
                          "than 5%%\n",
                          kinds[k]->name, offsets[c], 100 * mean, 100 * share, lit);
            if (fabs(mean) > MEAN_TOLERANCE || share > MOVED_TOLERANCE)
                fail_msg("%s, offset %g: mean %+.4f%% (tolerance %g%%), %.2f%% of pixels moved "
                         "(tolerance %g%%)",
                         kinds[k]->name, offsets[c], 100 * mean, 100 * MEAN_TOLERANCE,
                         100 * share, 100 * MOVED_TOLERANCE);
        }
    }
}

/* Axis-parallel rays on grid-cell and box boundaries. Naive: 1/0 in a slab test gives NaN when the
 * origin lies on a slab plane (0 * inf), and a 3D-DDA stepping on t = 0 boundaries skips cells or
 * loops. vkrt: a camera looking straight down -y on a floor at y = 0 with a cube whose faces lie
 * on integer coordinates, rays through pixel centres parallel to the y axis at x, z = 0 exactly
 * (orthographic-like rays down the middle, fov tiny), give the same picture with every structure,
 * finite everywhere, and the cube's top and the floor where they belong. */
static const char cube_on_floor_obj[] =
    "v -4 0 -4\nv 4 0 -4\nv 4 0 4\nv -4 0 4\n"
    "v -1 0 -1\nv 1 0 -1\nv 1 2 -1\nv -1 2 -1\nv -1 0 1\nv 1 0 1\nv 1 2 1\nv -1 2 1\n"
    "f 1 4 3 2\nf 5 8 7 6\nf 9 10 11 12\nf 5 6 10 9\nf 8 12 11 7\nf 5 9 12 8\nf 6 7 11 10\n";

/* Renders the scene.cfg written last with every structure: finite, and the same as brute force
 * value for value. */
static void render_all_alike(float rgb[][5 * 5 * 3])
{
    enum { N = 5 };
    for (size_t k = 0; k < KINDS; ++k) {
        render_as(&all_kinds[k], N, N, rgb[k], NULL);
        assert_all_finite(rgb[k], N * N * 3, all_kinds[k].name);
    }
    for (int i = 0; i < N * N * 3; ++i)
        for (size_t k = 1; k < KINDS; ++k)
            if (rgb[k][i] != rgb[0][i])
                fail_msg("value %d: brute %g, %s %g", i, rgb[0][i], all_kinds[k].name,
                         rgb[k][i]);
}

static void test_axis_parallel_rays_on_cell_boundaries(void **state)
{
    (void)state;
    scene_dir_write("grid.obj", cube_on_floor_obj);
    /* fov 90 and 4 x 4 pixels from height 4: pixel centres at x, z = +-1, +-3 on the floor's plane,
     * exactly the cube's edges and the floor's quarter lines (the grid's cell boundaries). The
     * centre column (x = 0) of a 5-wide picture looks straight down the y axis. */
    scene_dir_write("scene.cfg", "geometry grid.obj\nlight directional 0 -1 0  1 1 1\n"
                                 "camera eye 0 4 0 look 0 0 0 up 0 0 1 fov 90\n");
    enum { N = 5 };
    float rgb[KINDS][N * N * 3];
    render_all_alike(rgb);
    /* The centre pixel sees the cube's top, lit head-on: 0.8 / pi. */
    const float *centre = rgb[0] + 3 * (2 * N + 2);
    assert_float_equal(centre[0], 0.8 / M_PI, 1e-6);
}

/* Axis-parallel rays in split planes. Naive kd-tree walk: a ray whose direction has a 0 component
 * and whose origin lies on a node's split plane runs in that plane, and a walk that sends it to
 * one side only (the side the origin is "below", say) misses the triangles that touch the plane
 * from the other: the SAH with perfect splits puts planes exactly at the cube's faces. vkrt: the
 * eye above the cube's edge x = z = -1, looking straight down: the middle row and column of a
 * 5 x 5 picture run in the planes x = -1 and z = -1, the centre ray along the cube's vertical
 * edge; those meeting the cube's top (its corner and the points 0.6 along its edges) see it lit
 * head-on, the same with every structure. The kd-tree's walk first failed this: in the plane it
 * visited both sides but ended in the first, on the shadowed floor beneath the top. */
static void test_axis_parallel_rays_in_split_planes(void **state)
{
    (void)state;
    scene_dir_write("grid.obj", cube_on_floor_obj);
    scene_dir_write("scene.cfg", "geometry grid.obj\nlight directional 0 -1 0  1 1 1\n"
                                 "camera eye -1 4 -1 look -1 0 -1 up 0 0 1 fov 90\n");
    enum { N = 5 };
    float rgb[KINDS][N * N * 3];
    render_all_alike(rgb);
    /* The rays that meet the top on its edges: the centre (its corner), and 0.6 along each edge
     * (row 1 of the middle column, column 1 of the middle row). Beneath the top the floor lies in
     * its shadow, so a walk that loses the edge shows black there. */
    static const int on_top[3][2] = {{2, 2}, {1, 2}, {2, 1}};
    for (int i = 0; i < 3; ++i)
        assert_float_equal(rgb[0][3 * (on_top[i][0] * N + on_top[i][1])], 0.8 / M_PI, 1e-6);
}

/* Degenerate triangles: zero-area (a repeated vertex), collinear vertices and slivers 1e-7 wide.
 * Naive: a determinant of 0 divides to inf or NaN and reports hits at NaN distances; slivers make
 * SAH and grid builds produce empty or inverted boxes. vkrt: mixed into a scene they change
 * nothing (they cover no area: the sliver covers less than a pixel's ray spacing), and the picture
 * equals the one without them, with every structure. */
static void test_degenerate_triangles_change_nothing(void **state)
{
    (void)state;
    const char *clean = "v -10 0 -10\nv 10 0 -10\nv 10 0 10\nv -10 0 10\nf 1 4 3 2\n";
    scene_dir_write("floor.obj", clean);
    scene_dir_write("scene.cfg", "geometry floor.obj\nlight point 1 4 2  100 100 100\n"
                            "camera eye 0 10 0 look 0 0 0 up 0 0 1 fov 60\n");
    enum { N = 16 };
    float want[N * N * 3], got[N * N * 3];
    render(VKRT_ACCEL_BRUTE, N, N, want, NULL);
    FILE *f = scene_dir_open("floor.obj");
    fputs(clean, f);
    /* Above the floor, so a wrong hit on them would shadow it or show up. */
    fputs("v 0 1 0\nv 1 1 0\nv 2 1 0\n"             /* 5-7: collinear */
          "v 0 2 0\nv 0 2 0\nv 0 2 0\n"             /* 8-10: a point */
          "v -3 1.5 -3\nv 3 1.5 3\nv 3 1.5000001 3.0000001\n" /* 11-13: a sliver */
          "v 5 3 5\n"                               /* 14 */
          "f 5 6 7\nf 8 9 10\nf 11 12 13\nf 14 14 5\nf 6 6 6\n",
          f);
    fclose(f);
    for (size_t k = 0; k < KINDS; ++k) {
        render_as(&all_kinds[k], N, N, got, NULL);
        assert_all_finite(got, N * N * 3, all_kinds[k].name);
        int differ = 0;
        for (int i = 0; i < N * N * 3; ++i)
            differ += fabs(got[i] - want[i]) > 1e-6 * want[i] + 1e-9;
        if (differ)
            fail_msg("%s: %d values changed by degenerate triangles", all_kinds[k].name,
                     differ);
    }
}

/* Grazing glass and total internal reflection chains. Naive: every glass hit doubles the rays,
 * so depth d needs 2^d rays per pixel (a fixed buffer overflows and corrupts memory, or the
 * renderer runs out of memory), and grazing angles give refract() a negative root (NaN).
 * vkrt: a stack of 6 glass slabs seen at 85 degrees from the normal, max-depth 16: the counting
 * kernel grows the buffers (at least doubling) to what a frame needs and no further, the
 * importance threshold ends the chains, no pixel is NaN or infinite and no NaN was dropped. */
static void test_glass_chains_stay_bounded_and_finite(void **state)
{
    (void)state;
    FILE *f = scene_dir_open("slabs.obj");
    fputs("mtllib slabs.mtl\nusemtl glass\n", f);
    for (int s = 0; s < 6; ++s) {
        double y0 = s * 1.0, y1 = y0 + 0.5;
        fprintf(f, "v -50 %g -50\nv 50 %g -50\nv 50 %g 50\nv -50 %g 50\n", y1, y1, y1, y1);
        fprintf(f, "v -50 %g -50\nv 50 %g -50\nv 50 %g 50\nv -50 %g 50\n", y0, y0, y0, y0);
        int b = 8 * s;
        fprintf(f, "f %d %d %d %d\nf %d %d %d %d\n", b + 1, b + 4, b + 3, b + 2, b + 5, b + 6,
                b + 7, b + 8);
    }
    fputs("usemtl floor\nv -50 -2 -50\nv 50 -2 -50\nv 50 -2 50\nv -50 -2 50\nf 49 52 51 50\n", f);
    fclose(f);
    scene_dir_write("slabs.mtl", "newmtl glass\nKd 0 0 0\nNi 1.5\nillum 7\n"
                            "newmtl floor\nKd 0.5 0.5 0.5\n");
    /* Grazing: the centre ray meets the slabs 85 degrees from their normal. */
    double a = 85 * M_PI / 180;
    char cfg[512];
    snprintf(cfg, sizeof cfg,
             "geometry slabs.obj\nmax-depth 16\nenvironment 0.3 0.4 0.5\n"
             "light directional 0.3 -1 0.2  2 2 2\n"
             "camera eye 0 8 0 look %.9g %.9g 0 up 0 1 0 fov 30\n",
             sin(a), 8 - cos(a));
    scene_dir_write("scene.cfg", cfg);
    enum { N = 32 };
    static float rgb[N * N * 3];
    vkrt_frame_stats stats;
    render(VKRT_ACCEL_BVH, N, N, rgb, &stats);
    print_message("glass chains: %llu secondary rays, buffers grew to %u rays in %u attempts, "
                  "%u non-finite results\n",
                  (unsigned long long)stats.secondary_rays, stats.ray_capacity, stats.attempts,
                  stats.nonfinite);
    assert_all_finite(rgb, N * N * 3, "glass chains");
    assert_int_equal(stats.nonfinite, 0);
    assert_int_equal(stats.dropped_rays, 0);
    /* The chains did branch (more rays than pixels), and the buffers hold no more than the
     * largest generation rounded up to a doubling of the pixel count. */
    assert_true(stats.secondary_rays > 4 * N * N);
    assert_true(stats.attempts >= 2);
    assert_true(stats.ray_capacity <= 2 * stats.secondary_rays);
    double sum = 0;
    for (int i = 0; i < N * N * 3; ++i)
        sum += rgb[i];
    assert_true(sum / (N * N * 3) > 0.01);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_hundred_lights_sum_in_closed_form),
        cmocka_unit_test(test_light_inside_a_closed_box_does_not_leak),
        cmocka_unit_test(test_self_shadows_hold_far_from_the_origin),
        cmocka_unit_test(test_axis_parallel_rays_on_cell_boundaries),
        cmocka_unit_test(test_axis_parallel_rays_in_split_planes),
        cmocka_unit_test(test_degenerate_triangles_change_nothing),
        cmocka_unit_test(test_glass_chains_stay_bounded_and_finite),
    };
    return cmocka_run_group_tests(tests, scene_dir_make, scene_dir_remove);
}
