/*
 * test_surface_maps.c: the .mtl maps that change a surface (glsl/lib/surface_maps.glsl) against
 * closed forms, in both integrators: a normal map of a constant tilt lights a flat quad as a
 * quad of that normal would be lit (Kd / pi E cos), a height map of a linear ramp tilts it by the
 * ramp's slope, and an emission map black on one half halves the light a floor gets from it.
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

#include "render/renderer.h"
#include "scene_dir.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

enum { SIDE = 16 };

static const char *const integrators[] = {"whitted", "path"};

/* A w x h 24-bit TGA, top row first, texel (x, y) from texel(). */
static void write_tga(const char *name, int w, int h, void (*texel)(int, int, unsigned char *))
{
    FILE *f = scene_dir_open(name);
    unsigned char header[18] = {0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, (unsigned char)w,
                                (unsigned char)(w >> 8), (unsigned char)h,
                                (unsigned char)(h >> 8), 24, 0x20};
    fwrite(header, 1, sizeof header, f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            unsigned char rgb[3], bgr[3];
            texel(x, y, rgb);
            bgr[0] = rgb[2], bgr[1] = rgb[1], bgr[2] = rgb[0];
            fwrite(bgr, 1, 3, f);
        }
    fclose(f);
}

/* The unit quad's corners and texture coordinates: the square x, z in [-1, 1] at y = 0, facing +y,
 * u = u0 + (x + 1) * span / 2 and v = u0 + (1 - z) * span / 2: dp/du along +x and dp/dv along -z,
 * each 2 / span long. */
static void write_quad(const char *material, double u0, double span)
{
    char obj[1024];
    snprintf(obj, sizeof obj,
             "mtllib scene.mtl\nusemtl %s\nv -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\n"
             "vt %g %g\nvt %g %g\nvt %g %g\nvt %g %g\nf 1/1 4/4 3/3 2/2\n",
             material, u0, u0 + span, u0 + span, u0 + span, u0 + span, u0, u0, u0);
    scene_dir_write("scene.obj", obj);
}

/* The mean of channel 1 over the middle 8 x 8 pixels (the quad, seen from straight above). */
static double middle_mean(const float *rgb)
{
    double sum = 0;
    for (int y = SIDE / 2 - 4; y < SIDE / 2 + 4; ++y)
        for (int x = SIDE / 2 - 4; x < SIDE / 2 + 4; ++x)
            sum += rgb[3 * (y * SIDE + x) + 1];
    return sum / 64.0;
}

/* Writes cfg as the folder's scene.cfg and renders it at SIDE x SIDE with spp samples. */
static void render_cfg(const char *cfg, uint32_t spp, float *rgb)
{
    scene_dir_write("scene.cfg", cfg);
    vkrt_error err = {{0}};
    if (!scene_dir_render(SIDE, SIDE, &(vkrt_render_desc){.samples = spp}, rgb, NULL, &err))
        fail_msg("render: %s", err.msg);
}

/* Renders the folder's quad from straight above under a directional light arriving from
 * to_light (irradiance 1), with the integrator k: the mean of the middle pixels. */
static double render_lit_quad(int k, const double to_light[3])
{
    char cfg[512];
    snprintf(cfg, sizeof cfg,
             "geometry scene.obj\nresolution %d %d\nmax-depth 1\nintegrator %s\n"
             "light directional %.9f %.9f %.9f  1 1 1\n"
             "camera eye 0 3 0 look 0 0 0 up 0 0 -1 fov 30\n",
             SIDE, SIDE, integrators[k], -to_light[0], -to_light[1], -to_light[2]);
    float rgb[SIDE * SIDE * 3];
    render_cfg(cfg, 1, rgb);
    return middle_mean(rgb);
}

static void normalize3(double v[3])
{
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int i = 0; i < 3; ++i)
        v[i] /= l;
}

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* A light from up and to the side, so that a tilt along either texture axis, or its sign,
 * changes the cosine. */
static void light_direction(double to_light[3])
{
    to_light[0] = 0.35, to_light[1] = 1.0, to_light[2] = -0.5;
    normalize3(to_light);
}

/* The normal map's texel: a normal tilted towards +u and towards +v (tangent space x, y). */
static const unsigned char tilt_texel[3] = {166, 107, 232};

static void tilted(int x, int y, unsigned char *rgb)
{
    (void)x, (void)y;
    memcpy(rgb, tilt_texel, 3);
}

/* A flat quad with a constant normal map is lit as a quad of the texel's normal: (2 rgb - 1) in
 * the frame (dp/du, dp/dv, n) = (+x, -z, +y), so Kd / pi * E * cos(normal, light), exactly (no
 * noise: a directional light). Swapping the tangent's or the bitangent's sign, or reading the map
 * as sRGB, changes the cosine by more than 10%. */
static void normal_map_lights_as_its_normal(void **state)
{
    (void)state;
    write_tga("tilt.tga", 4, 4, tilted);
    write_quad("bent", 0, 1);
    scene_dir_write("scene.mtl", "newmtl bent\nKd 0.6 0.6 0.6\nnorm tilt.tga\n");
    double local[3], normal[3], to_light[3];
    for (int i = 0; i < 3; ++i)
        local[i] = tilt_texel[i] / 255.0 * 2.0 - 1.0;
    normal[0] = local[0], normal[1] = local[2], normal[2] = -local[1];
    normalize3(normal);
    light_direction(to_light);
    double expected = 0.6 / M_PI * dot3(normal, to_light);
    double flat = 0.6 / M_PI * to_light[1];
    for (int k = 0; k < 2; ++k) {
        double got = render_lit_quad(k, to_light);
        print_message("%s: normal map %.5f, closed form %.5f (flat %.5f)\n", integrators[k], got,
                      expected, flat);
        assert_true(fabs(got - expected) < 0.005 * expected);
    }
    /* The same texel through map_Bump: the image reads as a normal map, not heights. */
    scene_dir_write("scene.mtl", "newmtl bent\nKd 0.6 0.6 0.6\nmap_Bump tilt.tga\n");
    double got = render_lit_quad(0, to_light);
    print_message("map_Bump of a normal map: %.5f\n", got);
    assert_true(fabs(got - expected) < 0.005 * expected);
}

enum { RAMP = 128 };

/* Height rising by 1/255 a texel to the right and a texel upwards (v). */
static void ramp(int x, int y, unsigned char *rgb)
{
    rgb[0] = rgb[1] = rgb[2] = (unsigned char)(x + (RAMP - 1 - y));
}

/* A height map of a linear ramp, h = (i + j) / 255 at texel (i, j up), times -bm in scene units,
 * on a quad whose uv span [0.25, 0.75] (clear of the wrap-around): dh/du = dh/dv = RAMP / 255
 * per unit of uv, dp/du and dp/dv 4 long, so the surface rises by bm RAMP / (4 * 255) per unit
 * along +x and along -z, and its normal is (-s, 1, s) normalised. */
static void bump_ramp_tilts_by_its_slope(void **state)
{
    (void)state;
    write_tga("ramp.tga", RAMP, RAMP, ramp);
    write_quad("bumpy", 0.25, 0.5);
    scene_dir_write("scene.mtl", "newmtl bumpy\nKd 0.6 0.6 0.6\nbump -bm 3 ramp.tga\n");
    double slope = 3.0 * RAMP / (4.0 * 255.0);
    double normal[3] = {-slope, 1.0, slope}, to_light[3];
    normalize3(normal);
    light_direction(to_light);
    double expected = 0.6 / M_PI * dot3(normal, to_light);
    for (int k = 0; k < 2; ++k) {
        double got = render_lit_quad(k, to_light);
        print_message("%s: bump ramp %.5f, closed form %.5f (flat %.5f)\n", integrators[k], got,
                      expected, 0.6 / M_PI * to_light[1]);
        assert_true(fabs(got - expected) < 0.005 * expected);
    }
}

/* Tilted 75 degrees towards -u: a normal the viewer below sees from behind. */
static void steep(int x, int y, unsigned char *rgb)
{
    (void)x, (void)y;
    rgb[0] = 5, rgb[1] = 128, rgb[2] = 161;
}

/* The floor seen at a slant from +x, under light from above: the mean of the bottom rows (the
 * floor), for material `floor` of the .mtl written before. */
static double slanted_floor(int k)
{
    char cfg[512];
    snprintf(cfg, sizeof cfg,
             "geometry scene.obj\nresolution %d %d\nmax-depth 1\nintegrator %s\n"
             "light directional 0.5 -1 0  1 1 1\n"
             "camera eye 3 0.6 0 look 0 0 0 up 0 1 0 fov 40\n",
             SIDE, SIDE, integrators[k]);
    float rgb[SIDE * SIDE * 3];
    render_cfg(cfg, 1, rgb);
    double sum = 0;
    for (int i = 3 * SIDE * (SIDE - 4); i < 3 * SIDE * SIDE; ++i) {
        assert_true(isfinite(rgb[i]));
        sum += rgb[i];
    }
    return sum / (3 * SIDE * 4);
}

/* A normal map that turns the normal away from the viewer (75 degrees towards -x, the floor
 * seen from +x): every BSDF would be black there (exactly 0), a grid of black pixels on real
 * scenes. The mapped normal is bent back just in front of the viewer, so the floor stays lit:
 * dimly, as @pbr's coat reflects nearly everything at that grazing angle and lets little reach
 * the diffuse base (0.0226 against 0.179 without the map in Whitted), so the bound is 5% of the
 * unmapped floor. A glossy material (@pbr), whose lobes need the viewer in front of the normal. */
static void steep_normal_map_is_not_black(void **state)
{
    (void)state;
    write_tga("steep.tga", 4, 4, steep);
    scene_dir_write("scene.obj", "mtllib scene.mtl\nusemtl floor\nv -4 0 -4\nv 4 0 -4\n"
                                 "v 4 0 4\nv -4 0 4\nvt 0 1\nvt 1 1\nvt 1 0\nvt 0 0\n"
                                 "f 1/1 4/4 3/3 2/2\n");
    for (int k = 0; k < 2; ++k) {
        scene_dir_write("scene.mtl", "newmtl floor\nKd 0.6 0.6 0.6\nPr 0.5\n");
        double flat = slanted_floor(k);
        scene_dir_write("scene.mtl", "newmtl floor\nKd 0.6 0.6 0.6\nPr 0.5\nnorm steep.tga\n");
        double mapped = slanted_floor(k);
        print_message("%s: floor seen from behind its mapped normal %.5f, without the map %.5f\n",
                      integrators[k], mapped, flat);
        assert_true(flat > 0.01);
        assert_true(mapped > 0.05 * flat);
    }
}

/* Left half black, right half white. */
static void half_black(int x, int y, unsigned char *rgb)
{
    (void)y;
    rgb[0] = rgb[1] = rgb[2] = x < 8 ? 0 : 255;
}

/* The mean of the whole image: a floor at y = 0 seen from just below an emitter facing down. */
static double floor_light(int k, const char *mtl)
{
    scene_dir_write("scene.mtl", mtl);
    char cfg[512];
    snprintf(cfg, sizeof cfg,
             "geometry scene.obj\nresolution %d %d\nmax-depth 2\nintegrator %s\n"
             "camera eye 0 0.9 0 look 0 0 0 up 0 0 -1 fov 60\n",
             SIDE, SIDE, integrators[k]);
    float rgb[SIDE * SIDE * 3];
    render_cfg(cfg, 256, rgb);
    double sum = 0;
    for (int i = 0; i < SIDE * SIDE * 3; ++i)
        sum += rgb[i];
    return sum / (SIDE * SIDE * 3);
}

/* An emitter over a floor, its map_Ke black on the half x < 0: the floor, seen symmetric about
 * x = 0, gets half the light of the same emitter without the map (each point of the floor gets
 * from the lit half what its mirror image gets from the dark one; bilinear filtering keeps this,
 * the ramps at u = 0.5 and at the wrap being odd about them). In both integrators: the path
 * tracer's light samples weigh the emitter by its mean, which must be the density its hits are
 * weighed with in MIS. */
static void emission_map_halves_the_light(void **state)
{
    (void)state;
    write_tga("half.tga", 16, 16, half_black);
    scene_dir_write("scene.obj", "mtllib scene.mtl\nusemtl floor\nv -3 0 -3\nv 3 0 -3\nv 3 0 3\n"
                                 "v -3 0 3\nf 1 4 3 2\nusemtl lamp\nv -0.5 1 -0.5\nv 0.5 1 -0.5\n"
                                 "v 0.5 1 0.5\nv -0.5 1 0.5\nvt 0 1\nvt 1 1\nvt 1 0\nvt 0 0\n"
                                 "f 5/1 6/2 7/3 8/4\n");
    static const char plain[] = "newmtl floor\nKd 0.5 0.5 0.5\nnewmtl lamp\nKd 0 0 0\nKe 4 4 4\n";
    static const char mapped[] = "newmtl floor\nKd 0.5 0.5 0.5\nnewmtl lamp\nKd 0 0 0\n"
                                 "Ke 4 4 4\nmap_Ke half.tga\n";
    for (int k = 0; k < 2; ++k) {
        double full = floor_light(k, plain), half = floor_light(k, mapped);
        print_message("%s: floor under Ke %.5f, under Ke x half-black map_Ke %.5f: ratio %.4f\n",
                      integrators[k], full, half, half / full);
        assert_true(full > 0.01);
        assert_true(fabs(half / full - 0.5) < 0.02);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(normal_map_lights_as_its_normal),
        cmocka_unit_test(bump_ramp_tilts_by_its_slope),
        cmocka_unit_test(steep_normal_map_is_not_black),
        cmocka_unit_test(emission_map_halves_the_light),
    };
    return cmocka_run_group_tests(tests, scene_dir_make, scene_dir_remove);
}
