/*
 * test_orthographic.c: the orthographic camera (`camera ... ortho W`) on the GPU, against closed
 * forms. A unit square facing the camera, lit by ambient light only (radiance Kd x ambient = 1
 * where it is seen, 0 elsewhere), seen through a view 4 units wide on 64 pixels: 16 pixels a scene
 * unit whatever the distance, so the square covers exactly 16 x 16 pixels, its edges on pixel
 * edges, at any distance (a perspective camera's square shrinks as 1 / distance^2). With a thin
 * lens the picture is the sharp one convolved with a disc of radius A |1 - d / D| (scene units;
 * d the square's distance, D the focus distance): light is moved, not made or lost.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>

#include <cmocka.h>

#include "scene_dir.h"

enum { W = 64, H = 32 };
/* Pixels per scene unit of a view 4 units wide on W pixels. */
static const double per_unit = W / 4.0;

static int setup(void **state)
{
    if (scene_dir_make(state) != 0)
        return -1;
    scene_dir_write("square.obj", "mtllib square.mtl\nusemtl white\n"
                                  "v -0.5 -0.5 0\nv 0.5 -0.5 0\nv 0.5 0.5 0\nv -0.5 0.5 0\n"
                                  "f 1 2 3 4\n");
    scene_dir_write("square.mtl", "newmtl white\nKd 1 1 1\n");
    return 0;
}

/* Renders the square from (eye_x, 0, distance) looking down -z, through `projection` ("ortho 4"
 * or "fov 40", with a lens if wanted), at spp samples per pixel. */
static void render_square(double eye_x, double distance, const char *projection, uint32_t spp,
                          float *rgb)
{
    char cfg[512];
    snprintf(cfg, sizeof cfg,
             "geometry square.obj\nenvironment 0 0 0\nlight ambient 1 1 1\n"
             "camera eye %.9g 0 %.9g look %.9g 0 0 up 0 1 0 %s\n",
             eye_x, distance, eye_x, projection);
    scene_dir_write("scene.cfg", cfg);
    vkrt_error err = {{0}};
    vkrt_render_desc desc = {.samples = spp, .integrator = VKRT_INTEGRATOR_WHITTED};
    if (!scene_dir_render(W, H, &desc, rgb, NULL, &err))
        fail_msg("%s", err.msg);
}

/* The lit pixels (red above one half) and the box around them. */
static int count_lit(const float *rgb, int box[4])
{
    int count = 0;
    box[0] = box[1] = 1 << 20;
    box[2] = box[3] = -1;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            if (!(rgb[3 * (y * W + x)] > 0.5f))
                continue;
            ++count;
            box[0] = x < box[0] ? x : box[0];
            box[1] = y < box[1] ? y : box[1];
            box[2] = x > box[2] ? x : box[2];
            box[3] = y > box[3] ? y : box[3];
        }
    return count;
}

/* 16 x 16 lit pixels at every distance, in the middle of the picture (and one unit, 16 pixels,
 * to the right of it when the camera moves one unit left); the radiance there is Kd x ambient. A
 * perspective camera's square is 4 times smaller at twice the distance. */
static void square_covers_its_area_at_any_distance(void **state)
{
    (void)state;
    float *rgb = calloc(W * H * 3, sizeof *rgb);
    assert_non_null(rgb);
    const double distances[] = {0.25, 3, 1000};
    for (int i = 0; i < 3; ++i)
        for (int shifted = 0; shifted < 1 + (i == 1); ++shifted) {
            render_square(shifted ? -1 : 0, distances[i], "ortho 4", 1, rgb);
            int box[4];
            int lit = count_lit(rgb, box);
            int left = W / 2 - (int)(0.5 * per_unit) + (shifted ? (int)per_unit : 0);
            int top = H / 2 - (int)(0.5 * per_unit);
            print_message("distance %g%s: %d pixels lit, columns %d-%d, rows %d-%d\n",
                          distances[i], shifted ? ", camera 1 unit left" : "", lit, box[0],
                          box[2], box[1], box[3]);
            assert_int_equal(lit, (int)(per_unit * per_unit));
            assert_int_equal(box[0], left);
            assert_int_equal(box[2], left + (int)per_unit - 1);
            assert_int_equal(box[1], top);
            assert_int_equal(box[3], top + (int)per_unit - 1);
            float centre = rgb[3 * ((top + 8) * W + left + 8)];
            assert_true(fabsf(centre - 1.0f) < 1e-5f);
        }
    int box[4];
    render_square(0, 2, "fov 40", 1, rgb);
    int near = count_lit(rgb, box);
    render_square(0, 4, "fov 40", 1, rgb);
    int far = count_lit(rgb, box);
    print_message("perspective: %d pixels lit at distance 2, %d at 4\n", near, far);
    assert_true(near > 3 * far && near < 5 * far);
    free(rgb);
}

/* Distance in pixels from the centre of pixel (x, y) to the square (0 inside), and how deep
 * inside it the centre is (0 outside). */
static void square_distance(int x, int y, double *outside, double *inside)
{
    double px = (x + 0.5) - W / 2.0, py = (y + 0.5) - H / 2.0, half = 0.5 * per_unit;
    double dx = fabs(px) - half, dy = fabs(py) - half;
    *outside = sqrt(fmax(dx, 0) * fmax(dx, 0) + fmax(dy, 0) * fmax(dy, 0));
    *inside = fmax(-fmax(dx, dy), 0);
}

/* A thin lens of radius 0.25 focused at half the square's distance of 4: a blur disc of 0.25 |1 -
 * 4 / 2| = 0.25 units, 4 pixels. Pixels farther than that (plus half a pixel's diagonal, the
 * jitter) from the square see none of it, pixels deeper inside see only it, the total stays the
 * square's 256 pixels (to the noise of 64 lens samples along the edges), and pixels in between are
 * grey. Focused on the square, the lens changes nothing. */
static void lens_blurs_by_the_closed_form_radius(void **state)
{
    (void)state;
    float *rgb = calloc(W * H * 3, sizeof *rgb);
    assert_non_null(rgb);
    render_square(0, 4, "ortho 4 aperture 0.25 focus 2", 64, rgb);
    const double radius = 0.25 * fabs(1 - 4.0 / 2) * per_unit, jitter = sqrt(0.5);
    double total = 0;
    int grey = 0, wrong = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            float v = rgb[3 * (y * W + x)];
            double outside, inside;
            square_distance(x, y, &outside, &inside);
            total += v;
            grey += v > 0.05f && v < 0.95f;
            if ((outside > radius + jitter && v != 0) ||
                (inside > radius + jitter && fabsf(v - 1) > 1e-5f)) {
                if (wrong++ < 5)
                    print_message("pixel %d %d: %g, %g outside, %g inside\n", x, y, v, outside,
                                  inside);
            }
        }
    print_message("blurred: total %.2f (square: %g), %d grey pixels\n", total,
                  per_unit * per_unit, grey);
    assert_int_equal(wrong, 0);
    assert_true(fabs(total - per_unit * per_unit) < 0.02 * per_unit * per_unit);
    assert_true(grey > 100);

    render_square(0, 4, "ortho 4 aperture 0.25 focus 4", 16, rgb);
    int box[4];
    assert_int_equal(count_lit(rgb, box), (int)(per_unit * per_unit));
    total = 0;
    for (int i = 0; i < W * H; ++i)
        total += rgb[3 * i];
    assert_true(fabs(total - per_unit * per_unit) < 1e-3);
    free(rgb);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(square_covers_its_area_at_any_distance),
        cmocka_unit_test(lens_blurs_by_the_closed_form_radius),
    };
    return cmocka_run_group_tests(tests, setup, scene_dir_remove);
}
