/*
 * test_config.c: unit tests for src/scene/config.c, the scene.cfg parser.
 *
 * The well-formed tests check every value that reaches vkrt_config, since a silently wrong
 * number renders a silently wrong image. The malformed tests check the message itself, line
 * number first: a message that points at the wrong line sends the user to the wrong place.
 * Every failure must also leave the struct zeroed, because callers free nothing after a failure.
 */
#define _POSIX_C_SOURCE 200809L

#include <setjmp.h> /* cmocka needs these before its header */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "scene/config.h"

/* ---------------------------------------------------------------------------------------------
 * Helpers
 * ------------------------------------------------------------------------------------------- */

#define CAMERA "camera eye 0 0 5 look 0 0 0 up 0 1 0 fov 45\n"

static void assert_zeroed(const vkrt_config *cfg)
{
    static const vkrt_config zero;
    assert_memory_equal(cfg, &zero, sizeof zero);
}

static void parse_ok(const char *text, const char *base_dir, vkrt_config *cfg)
{
    vkrt_error err = {{0}};
    bool ok = vkrt_config_parse(text, strlen(text), "t.cfg", base_dir, cfg, &err);
    if (!ok)
        print_error("unexpected failure: %s\n", err.msg);
    assert_true(ok);
}

/* Parses text of size bytes, expecting failure: the message must start with prefix and
 * contain phrase, and cfg (filled with garbage first) must come back zeroed. */
static void parse_fails(const char *text, size_t size, const char *prefix, const char *phrase)
{
    vkrt_config cfg;
    memset(&cfg, 0xAB, sizeof cfg);
    vkrt_error err = {{0}};
    bool ok = vkrt_config_parse(text, size, "t.cfg", "base", &cfg, &err);
    if (ok) {
        print_error("parse succeeded, expected \"%s ... %s\"\n", prefix, phrase);
        vkrt_config_free(&cfg);
        fail();
    }
    if (strncmp(err.msg, prefix, strlen(prefix)) != 0 || !strstr(err.msg, phrase)) {
        print_error("message \"%s\"\n   expected prefix \"%s\" and phrase \"%s\"\n", err.msg,
                    prefix, phrase);
        fail();
    }
    assert_zeroed(&cfg);
}

static void assert_vec3(const float v[3], float x, float y, float z)
{
    assert_float_equal(v[0], x, 1e-6);
    assert_float_equal(v[1], y, 1e-6);
    assert_float_equal(v[2], z, 1e-6);
}

/* ---------------------------------------------------------------------------------------------
 * Well-formed files
 * ------------------------------------------------------------------------------------------- */

static void test_every_keyword(void **state)
{
    (void)state;
    const char *text = "# a full scene\n"
                       "geometry    model.obj\n"
                       "materials   model.materials\n"
                       "resolution  320 200\n"
                       "samples     16\n"
                       "max-depth   3\n"
                       "accel       bvh\n"
                       "output      cornell.exr\n"
                       "environment 0.05 0.25 0.5\n"
                       "light ambient      0.1 0.2 0.3\n"
                       "light directional  0 -2 0  1 2 3\n"
                       "light point        1 2 3   10 20 30\n"
                       "light spot         4 5 6  0 0 -3  30  7 8 9\n"
                       "camera eye 1 2 3 look 4 5 6 up 0 1 0 fov 60\n"
                       "integrator  path\n"
                       "bvh-splits  off\n"
                       "textures    nearest\n"
                       "environment-map sky/noon.exr scale 2.5 rotate -90\n"
                       "tonemap     agx\n"
                       "denoise     on\n";
    vkrt_config cfg;
    parse_ok(text, "scenes/demo", &cfg);

    assert_string_equal(cfg.path, "t.cfg");
    assert_string_equal(cfg.geometries[0].path, "scenes/demo/model.obj");
    assert_string_equal(cfg.materials, "scenes/demo/model.materials");
    assert_string_equal(cfg.output, "scenes/demo/cornell.exr");
    assert_int_equal(cfg.width, 320);
    assert_int_equal(cfg.height, 200);
    assert_int_equal(cfg.samples, 16);
    assert_int_equal(cfg.max_depth, 3);
    assert_int_equal(cfg.accel, VKRT_ACCEL_BVH);
    assert_int_equal(cfg.integrator, VKRT_INTEGRATOR_PATH);
    assert_int_equal(cfg.bvh_splits, VKRT_BVH_SPLITS_OFF);
    assert_int_equal(cfg.texture_filter, VKRT_TEXTURE_FILTER_NEAREST);
    assert_int_equal(cfg.tonemap, VKRT_TONEMAP_AGX);
    assert_true(cfg.denoise);
    assert_vec3(cfg.environment, 0.05f, 0.25f, 0.5f);
    assert_string_equal(cfg.environment_map, "scenes/demo/sky/noon.exr");
    assert_float_equal(cfg.environment_scale, 2.5f, 0);
    assert_float_equal(cfg.environment_rotate, -90.0f, 0);
    assert_int_equal(cfg.environment_map_line, 18);

    assert_int_equal(cfg.light_count, 4);
    const vkrt_config_light *l = cfg.lights;
    assert_int_equal(l[0].kind, VKRT_LIGHT_AMBIENT);
    assert_vec3(l[0].colour, 0.1f, 0.2f, 0.3f);
    assert_int_equal(l[0].line, 10);

    assert_int_equal(l[1].kind, VKRT_LIGHT_DIRECTIONAL);
    assert_vec3(l[1].direction, 0, -1, 0); /* normalised */
    assert_vec3(l[1].colour, 1, 2, 3);
    assert_int_equal(l[1].line, 11);

    assert_int_equal(l[2].kind, VKRT_LIGHT_POINT);
    assert_vec3(l[2].position, 1, 2, 3);
    assert_vec3(l[2].colour, 10, 20, 30);

    assert_int_equal(l[3].kind, VKRT_LIGHT_SPOT);
    assert_vec3(l[3].position, 4, 5, 6);
    assert_vec3(l[3].direction, 0, 0, -1);
    assert_float_equal(l[3].half_angle_deg, 30.0f, 1e-6);
    assert_vec3(l[3].colour, 7, 8, 9);
    assert_int_equal(l[3].line, 13);

    assert_int_equal(cfg.camera_count, 1);
    assert_vec3(cfg.cameras[0].eye, 1, 2, 3);
    assert_vec3(cfg.cameras[0].look, 4, 5, 6);
    assert_vec3(cfg.cameras[0].up, 0, 1, 0);
    assert_float_equal(cfg.cameras[0].fov_deg, 60.0f, 1e-6);
    assert_int_equal(cfg.cameras[0].line, 14);

    vkrt_config_free(&cfg);
    assert_zeroed(&cfg);
}

static void test_defaults(void **state)
{
    (void)state;
    vkrt_config cfg;
    parse_ok("geometry m.obj\n" CAMERA, NULL, &cfg);
    assert_string_equal(cfg.geometries[0].path, "m.obj");
    assert_null(cfg.materials);
    assert_null(cfg.output);
    assert_int_equal(cfg.width, 640);
    assert_int_equal(cfg.height, 480);
    assert_int_equal(cfg.samples, 1);
    assert_int_equal(cfg.max_depth, 6);
    assert_int_equal(cfg.accel, VKRT_ACCEL_AUTO);
    assert_int_equal(cfg.integrator, VKRT_INTEGRATOR_AUTO);
    assert_int_equal(cfg.bvh_splits, VKRT_BVH_SPLITS_AUTO);
    assert_int_equal(cfg.texture_filter, VKRT_TEXTURE_FILTER_CONE);
    assert_int_equal(cfg.tonemap, VKRT_TONEMAP_NONE);
    assert_vec3(cfg.environment, 0, 0, 0);
    assert_null(cfg.environment_map);
    assert_float_equal(cfg.environment_scale, 1.0f, 0);
    assert_float_equal(cfg.environment_rotate, 0.0f, 0);
    assert_int_equal(cfg.environment_map_line, 0);
    assert_int_equal(cfg.light_count, 0);
    assert_null(cfg.lights);
    assert_int_equal(cfg.camera_count, 1);
    vkrt_config_free(&cfg);
}

static void test_limits_accepted(void **state)
{
    (void)state;
    vkrt_config cfg;
    parse_ok("geometry m.obj\nresolution 16384 1\nsamples 65536\nmax-depth 0\n"
             "light spot 0 0 0 0 -1 0 90 0 0 0\n"
             "camera eye 0 0 0 look 0 0 -1 up 0 1 0 fov 179.9\n",
             "", &cfg);
    assert_int_equal(cfg.width, 16384);
    assert_int_equal(cfg.height, 1);
    assert_int_equal(cfg.samples, 65536);
    assert_int_equal(cfg.max_depth, 0);
    assert_float_equal(cfg.lights[0].half_angle_deg, 90.0f, 1e-6);
    vkrt_config_free(&cfg);
}

static void test_path_resolution(void **state)
{
    (void)state;
    vkrt_config cfg;

    parse_ok("geometry /abs/m.obj\nmaterials ../shared/x.materials\noutput out/f%04d.png\n" CAMERA,
             "scenes/a/", &cfg);
    assert_string_equal(cfg.geometries[0].path, "/abs/m.obj"); /* absolute: kept */
    assert_string_equal(cfg.materials, "scenes/a/../shared/x.materials"); /* no doubled '/' */
    assert_string_equal(cfg.output, "scenes/a/out/f%04d.png");
    vkrt_config_free(&cfg);

    parse_ok("geometry o'brien.obj\n" CAMERA, "", &cfg);
    assert_string_equal(cfg.geometries[0].path, "o'brien.obj");
    vkrt_config_free(&cfg);

    parse_ok("geometry m.obj\n" CAMERA, "/", &cfg);
    assert_string_equal(cfg.geometries[0].path, "/m.obj");
    vkrt_config_free(&cfg);

    /* The output is a frame pattern, so a '%' in the folder must not become a conversion. */
    parse_ok("geometry m.obj\noutput f%d.PNG\n" CAMERA, "100%done", &cfg);
    assert_string_equal(cfg.geometries[0].path, "100%done/m.obj");
    assert_string_equal(cfg.output, "100%%done/f%d.PNG");
    vkrt_config_free(&cfg);

    parse_ok("geometry m.obj\noutput 100%%.exr\n" CAMERA, NULL, &cfg);
    assert_string_equal(cfg.output, "100%%.exr");
    vkrt_config_free(&cfg);
}

static void test_crlf_bom_and_no_final_newline(void **state)
{
    (void)state;
    vkrt_config cfg;
    parse_ok("\xEF\xBB\xBFgeometry m.obj\r\nresolution 10 20\r\n\r\n"
             "camera eye 0 0 5 look 0 0 0 up 0 1 0 fov 45\r\nsamples 3",
             "d", &cfg);
    assert_string_equal(cfg.geometries[0].path, "d/m.obj");
    assert_int_equal(cfg.width, 10);
    assert_int_equal(cfg.height, 20);
    assert_int_equal(cfg.samples, 3);
    assert_float_equal(cfg.cameras[0].fov_deg, 45.0f, 1e-6);
    assert_int_equal(cfg.cameras[0].line, 4);
    vkrt_config_free(&cfg);

    /* Classic Mac OS line ends (a '\r' alone) are line ends too, counted as lines; mixed with
     * the others as well. */
    parse_ok("geometry m.obj\rresolution 10 20\r\r"
             "camera eye 0 0 5 look 0 0 0 up 0 1 0 fov 45\rsamples 3\r",
             "d", &cfg);
    assert_string_equal(cfg.geometries[0].path, "d/m.obj");
    assert_int_equal(cfg.width, 10);
    assert_int_equal(cfg.samples, 3);
    assert_int_equal(cfg.cameras[0].line, 4);
    vkrt_config_free(&cfg);
    parse_ok("geometry m.obj\r\nresolution 10 20\n\r"
             "camera eye 0 0 5 look 0 0 0 up 0 1 0 fov 45\rsamples 3",
             "d", &cfg);
    assert_int_equal(cfg.samples, 3);
    assert_int_equal(cfg.cameras[0].line, 4);
    vkrt_config_free(&cfg);
}

static void test_comments_and_whitespace(void **state)
{
    (void)state;
    vkrt_config cfg;
    parse_ok("# leading comment\n"
             "   # indented comment\n"
             "\n"
             "\t geometry\tm.obj   # trailing comment\n"
             "samples 4#no space before the comment\n"
             "accel grid # bvh\n"
             "# resolution 1 1\n"
             "# café, and not UTF-8: \xE9\n" CAMERA,
             NULL, &cfg);
    assert_string_equal(cfg.geometries[0].path, "m.obj");
    assert_int_equal(cfg.samples, 4);
    assert_int_equal(cfg.accel, VKRT_ACCEL_GRID);
    assert_int_equal(cfg.width, 640);
    assert_int_equal(cfg.cameras[0].line, 9);
    vkrt_config_free(&cfg);
}

static void test_flythrough(void **state)
{
    (void)state;
    vkrt_config cfg;
    parse_ok("geometry m.obj\n"
             "output frames/f%03d.png\n"
             "camera eye 0 0 5 look 0 0 0 up 0 1 0 fov 45\n"
             "# the middle frame\n"
             "camera eye 5 0 0 look 0 0 0 up 0 1 0 fov 50\n"
             "camera eye 0 5 5 look 0 1 0 up 0 0 -1 fov 55.5\n",
             NULL, &cfg);
    assert_int_equal(cfg.camera_count, 3);
    assert_vec3(cfg.cameras[0].eye, 0, 0, 5);
    assert_vec3(cfg.cameras[1].eye, 5, 0, 0);
    assert_vec3(cfg.cameras[2].eye, 0, 5, 5);
    assert_vec3(cfg.cameras[2].look, 0, 1, 0);
    assert_vec3(cfg.cameras[2].up, 0, 0, -1);
    assert_float_equal(cfg.cameras[0].fov_deg, 45.0f, 1e-6);
    assert_float_equal(cfg.cameras[1].fov_deg, 50.0f, 1e-6);
    assert_float_equal(cfg.cameras[2].fov_deg, 55.5f, 1e-6);
    assert_int_equal(cfg.cameras[0].line, 3);
    assert_int_equal(cfg.cameras[1].line, 5);
    assert_int_equal(cfg.cameras[2].line, 6);
    assert_string_equal(cfg.output, "frames/f%03d.png");
    vkrt_config_free(&cfg);
}

/* `ortho W` in place of `fov F`, and `name NAME` among the optional parts. */
static void test_orthographic_and_named_cameras(void **state)
{
    (void)state;
    vkrt_config cfg;
    parse_ok("geometry m.obj\n"
             "camera eye 0 0 5 look 0 0 0 up 0 1 0 ortho 7.5\n"
             "camera eye 0 0 5 look 0 0 0 up 0 1 0 ortho 2 name top aperture 0.1 focus 4\n"
             "camera eye 0 0 5 look 0 0 0 up 0 1 0 fov 30 name "
             "a123456789b123456789c123456789d123456789e123456789f123456789g12\n",
             NULL, &cfg);
    assert_int_equal(cfg.camera_count, 3);
    assert_true(cfg.cameras[0].ortho_width == 7.5f && cfg.cameras[0].fov_deg == 0);
    assert_string_equal(cfg.cameras[0].name, "");
    assert_true(cfg.cameras[1].ortho_width == 2 && cfg.cameras[1].aperture == 0.1f &&
                cfg.cameras[1].focus == 4);
    assert_string_equal(cfg.cameras[1].name, "top");
    assert_true(cfg.cameras[2].ortho_width == 0 && cfg.cameras[2].fov_deg == 30);
    assert_int_equal(strlen(cfg.cameras[2].name), 63);
    vkrt_config_free(&cfg);
}

static void test_many_lights_and_cameras(void **state)
{
    (void)state;
    /* Enough to make the arrays grow several times. */
    size_t cap = 200 * 64;
    char *text = malloc(cap);
    assert_non_null(text);
    size_t n = (size_t)snprintf(text, cap, "geometry m.obj\n");
    for (int i = 0; i < 100; i++) {
        n += (size_t)snprintf(text + n, cap - n, "light point %d 0 0 1 1 1\n", i);
        n += (size_t)snprintf(text + n, cap - n,
                              "camera eye %d 0 5 look 0 0 0 up 0 1 0 fov 45\n", i);
    }
    vkrt_config cfg;
    parse_ok(text, NULL, &cfg);
    assert_int_equal(cfg.light_count, 100);
    assert_int_equal(cfg.camera_count, 100);
    assert_float_equal(cfg.lights[99].position[0], 99.0f, 0);
    assert_float_equal(cfg.cameras[99].eye[0], 99.0f, 0);
    assert_int_equal(cfg.cameras[99].line, 201);
    vkrt_config_free(&cfg);
    free(text);
}

static void test_accel_names(void **state)
{
    (void)state;
    const vkrt_accel_kind all[] = {VKRT_ACCEL_AUTO, VKRT_ACCEL_BRUTE, VKRT_ACCEL_GRID,
                                   VKRT_ACCEL_BVH};
    const char *names[] = {"auto", "brute", "grid", "bvh"};
    for (int i = 0; i < 4; i++) {
        assert_string_equal(vkrt_accel_name(all[i]), names[i]);
        vkrt_accel_kind k = VKRT_ACCEL_AUTO;
        assert_true(vkrt_accel_parse(names[i], &k));
        assert_int_equal(k, all[i]);
    }
    vkrt_accel_kind k = VKRT_ACCEL_GRID;
    assert_false(vkrt_accel_parse("BVH", &k));
    assert_false(vkrt_accel_parse("", &k));
    assert_false(vkrt_accel_parse(NULL, &k));
    assert_int_equal(k, VKRT_ACCEL_GRID);
    assert_string_equal(vkrt_accel_name((vkrt_accel_kind)42), "unknown");
}

#define G "geometry m.obj\n"

static void test_integrator_names(void **state)
{
    (void)state;
    const vkrt_integrator all[] = {VKRT_INTEGRATOR_AUTO, VKRT_INTEGRATOR_WHITTED,
                                   VKRT_INTEGRATOR_PATH};
    const char *names[] = {"auto", "whitted", "path"};
    for (int i = 0; i < 3; i++) {
        assert_string_equal(vkrt_integrator_name(all[i]), names[i]);
        vkrt_integrator k = VKRT_INTEGRATOR_AUTO;
        assert_true(vkrt_integrator_parse(names[i], &k));
        assert_int_equal(k, all[i]);
        assert_true(vkrt_integrator_parse(names[i], NULL));
    }
    vkrt_integrator k = VKRT_INTEGRATOR_WHITTED;
    assert_false(vkrt_integrator_parse("Path", &k));
    assert_false(vkrt_integrator_parse("", &k));
    assert_false(vkrt_integrator_parse(NULL, &k));
    assert_int_equal(k, VKRT_INTEGRATOR_WHITTED);
    assert_string_equal(vkrt_integrator_name((vkrt_integrator)42), "unknown");
}

static void test_tonemap_names(void **state)
{
    (void)state;
    const vkrt_tonemap all[] = {VKRT_TONEMAP_NONE, VKRT_TONEMAP_ACES, VKRT_TONEMAP_AGX};
    const char *names[] = {"none", "aces", "agx"};
    for (int i = 0; i < 3; i++) {
        assert_string_equal(vkrt_tonemap_name(all[i]), names[i]);
        vkrt_tonemap k = VKRT_TONEMAP_NONE;
        assert_true(vkrt_tonemap_parse(names[i], &k));
        assert_int_equal(k, all[i]);
    }
    vkrt_tonemap k = VKRT_TONEMAP_ACES;
    assert_false(vkrt_tonemap_parse("AgX", &k));
    assert_false(vkrt_tonemap_parse("filmic", &k));
    assert_false(vkrt_tonemap_parse(NULL, &k));
    assert_int_equal(k, VKRT_TONEMAP_ACES);
    assert_string_equal(vkrt_tonemap_name((vkrt_tonemap)42), "unknown");
}

/* environment-map: its options in either order, alone, and beside a constant environment,
 * which it replaces (both are kept in the config; the renderer uses the map). */
static void test_environment_map(void **state)
{
    (void)state;
    vkrt_config cfg;
    parse_ok(G "environment-map /abs/sky.hdr\n" CAMERA, "scenes/a", &cfg);
    assert_string_equal(cfg.environment_map, "/abs/sky.hdr");
    assert_float_equal(cfg.environment_scale, 1.0f, 0);
    assert_float_equal(cfg.environment_rotate, 0.0f, 0);
    assert_int_equal(cfg.environment_map_line, 2);
    vkrt_config_free(&cfg);

    parse_ok(G "environment 0.1 0.2 0.3\n"
               "environment-map ../sky.exr rotate 45.5 scale 0\n" CAMERA,
             "scenes/a/", &cfg);
    assert_string_equal(cfg.environment_map, "scenes/a/../sky.exr");
    assert_float_equal(cfg.environment_scale, 0.0f, 0);
    assert_float_equal(cfg.environment_rotate, 45.5f, 0);
    assert_vec3(cfg.environment, 0.1f, 0.2f, 0.3f);
    assert_int_equal(cfg.environment_map_line, 3);
    vkrt_config_free(&cfg);

    /* The path is a plain path, never a frame pattern: '%' stays as written. */
    parse_ok(G "environment-map 100%.hdr scale 1e3\n" CAMERA, NULL, &cfg);
    assert_string_equal(cfg.environment_map, "100%.hdr");
    assert_float_equal(cfg.environment_scale, 1000.0f, 0);
    vkrt_config_free(&cfg);
}

/* Several geometry lines, each placed: the transforms are the operations in the order written
 * (scale, then rotate, then translate here), checked against the matrices written out by hand. */
static void test_geometry_placement(void **state)
{
    (void)state;
    const char *text = "geometry a.obj\n"
                       "geometry tree.glb scale 2 rotate y 90 translate 1 2 3\n"
                       "geometry tree.glb rotate 0 0 2 90 scale 1 2 3\n";
    vkrt_config cfg;
    parse_ok(text, "", &cfg);
    assert_int_equal(cfg.geometry_count, 3);
    assert_string_equal(cfg.geometries[1].path, "tree.glb");
    assert_false(cfg.geometries[0].placed);
    assert_true(cfg.geometries[1].placed);
    assert_int_equal(cfg.geometries[2].line, 3);
    static const float identity[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    /* rotate y 90 takes x to -z and z to x; after scale 2 and the translation: */
    static const float second[12] = {0, 0, 2, 1, 0, 2, 0, 2, -2, 0, 0, 3};
    /* rotate z 90 takes x to y and y to -x, then scale (1, 2, 3) multiplies the rows: */
    static const float third[12] = {0, -1, 0, 0, 2, 0, 0, 0, 0, 0, 3, 0};
    for (int i = 0; i < 12; i++) {
        assert_float_equal(cfg.geometries[0].transform[i], identity[i], 0.0f);
        assert_float_equal(cfg.geometries[1].transform[i], second[i], 1e-6f);
        assert_float_equal(cfg.geometries[2].transform[i], third[i], 1e-6f);
    }
    assert_int_equal(cfg.camera_count, 0); /* cameras may come from the scene file */
    vkrt_config_free(&cfg);
}

/* A scene file given alone: scene.cfg's defaults, the file placed as it is, its stem as output. */
static void test_for_geometry(void **state)
{
    (void)state;
    vkrt_config cfg;
    vkrt_error err = {0};
    assert_true(vkrt_config_for_geometry("some/dir/Duck.v2.glb", &cfg, &err));
    assert_true(cfg.from_scene_file);
    assert_int_equal(cfg.geometry_count, 1);
    assert_string_equal(cfg.geometries[0].path, "some/dir/Duck.v2.glb");
    assert_false(cfg.geometries[0].placed);
    assert_float_equal(cfg.geometries[0].transform[0], 1.0f, 0.0f);
    assert_float_equal(cfg.geometries[0].transform[10], 1.0f, 0.0f);
    assert_string_equal(cfg.output, "Duck.v2.png");
    assert_int_equal(cfg.width, 640);
    assert_int_equal(cfg.samples, 1);
    vkrt_config_free(&cfg);
}

static void test_free_zeroed_struct(void **state)
{
    (void)state;
    vkrt_config cfg;
    memset(&cfg, 0, sizeof cfg);
    vkrt_config_free(&cfg);
    vkrt_config_free(NULL);
    assert_zeroed(&cfg);
}

/* ---------------------------------------------------------------------------------------------
 * Malformed files
 * ------------------------------------------------------------------------------------------- */

#undef G

typedef struct bad_case {
    const char *text;
    const char *prefix;
    const char *phrase;
} bad_case;

#define G "geometry m.obj\n"

static const bad_case bad_cases[] = {
    /* keywords */
    {G "foo 1 2\n", "t.cfg:2: ", "unknown keyword 'foo' (expected geometry, materials, resolution, samples, max-depth, shutter, accel, integrator, bvh-splits, textures, tonemap, denoise, output, environment, environment-map, light or camera)"},
    {G "Samples 2\n", "t.cfg:2: ", "unknown keyword 'Samples'"},
    {G "resolution 1 1\n\nresolution 2 2\n", "t.cfg:4: ", "resolution given twice (first on line 2)"},
    {G "geometry b.obj translate 1 2\n", "t.cfg:2: ", "geometry translate needs 3 numbers"},
    {G "geometry b.obj rotate q 90\n", "t.cfg:2: ", "geometry rotate needs an axis and an angle"},
    {G "geometry b.obj rotate 0 0 0 90\n", "t.cfg:2: ", "geometry rotate axis has zero length"},
    {G "geometry b.obj scale 0\n", "t.cfg:2: ", "geometry scale must not be 0"},
    {G "geometry b.obj scale\n", "t.cfg:2: ", "geometry scale needs 1 or 3 numbers"},
    {G "geometry b.obj spin 3\n", "t.cfg:2: ", "geometry: unexpected 'spin'"},
    /* 16 scales are 34 words: past the words a line keeps (the fuzzer's find). */
    {G "geometry b.obj" " scale 4 scale 4 scale 4 scale 4 scale 4 scale 4 scale 4 scale 4"
       " scale 4 scale 4 scale 4 scale 4 scale 4 scale 4 scale 4 scale 4\n",
     "t.cfg:2: ", "geometry: 34 words on one line, at most 32"},
    {G "geometry b.obj translate 1e12 0 0\n", "t.cfg:2: ", "geometry translate 1e+12 is outside"},
    {G "output a.png\noutput b.png\n", "t.cfg:3: ", "output given twice (first on line 2)"},
    {G "accel bvh\naccel grid\n", "t.cfg:3: ", "accel given twice (first on line 2)"},
    {G "integrator path\nintegrator path\n", "t.cfg:3: ", "integrator given twice (first on line 2)"},
    {G "tonemap agx\ntonemap aces\n", "t.cfg:3: ", "tonemap given twice (first on line 2)"},
    {G "tonemap filmic\n", "t.cfg:2: ", "unknown tonemap 'filmic' (expected none, aces or agx)"},
    {G "tonemap\n", "t.cfg:2: ", "tonemap needs one name (none, aces or agx), got 0"},
    {G "denoise yes\n", "t.cfg:2: ", "denoise: 'yes' is not on or off"},
    {G "denoise on\ndenoise off\n", "t.cfg:3: ", "denoise given twice (first on line 2)"},
    {G "environment-map a.hdr\nenvironment-map b.hdr\n", "t.cfg:3: ", "environment-map given twice (first on line 2)"},
    /* integrator */
    {G "integrator bidir\n", "t.cfg:2: ", "unknown integrator 'bidir' (expected auto, whitted or path)"},
    {G "textures mip\n", "t.cfg:2: ", "unknown textures 'mip' (expected cone, bilinear or nearest)"},
    {G "textures\n", "t.cfg:2: ", "textures needs one name (cone, bilinear or nearest), got 0"},
    {G "bvh-splits yes\n", "t.cfg:2: ", "unknown bvh-splits 'yes' (expected auto, on or off)"},
    {G "bvh-splits\n", "t.cfg:2: ", "bvh-splits needs one name (auto, on or off), got 0"},
    {G "bvh-splits on\nbvh-splits off\n", "t.cfg:3: ", "bvh-splits given twice (first on line 2)"},
    {G "integrator\n", "t.cfg:2: ", "integrator needs one name (auto, whitted or path), got 0"},
    {G "integrator path whitted\n", "t.cfg:2: ", "integrator needs one name (auto, whitted or path), got 2"},
    /* environment-map */
    {G "environment-map\n", "t.cfg:2: ", "environment-map needs a path (write: environment-map FILE [scale S] [rotate DEGREES])"},
    {G "environment-map \"my sky.hdr\"\n", "t.cfg:2: ", "environment-map: quotes are not supported"},
    {G "environment-map my sky.hdr\n", "t.cfg:2: ", "environment-map: unexpected 'sky.hdr' (write: environment-map FILE"},
    {G "environment-map sky.hdr scale\n", "t.cfg:2: ", "environment-map scale needs a number"},
    {G "environment-map sky.hdr rotate\n", "t.cfg:2: ", "environment-map rotate needs a number"},
    {G "environment-map sky.hdr scale 2 scale 3\n", "t.cfg:2: ", "environment-map scale given twice"},
    {G "environment-map sky.hdr rotate 2 scale 1 rotate 3\n", "t.cfg:2: ", "environment-map rotate given twice"},
    {G "environment-map sky.hdr scale -1\n", "t.cfg:2: ", "environment-map scale must not be negative, got -1"},
    {G "environment-map sky.hdr scale bright\n", "t.cfg:2: ", "environment-map scale 'bright' is not a number"},
    {G "environment-map sky.hdr scale inf\n", "t.cfg:2: ", "environment-map scale 'inf' is not a finite number"},
    {G "environment-map sky.hdr rotate nan\n", "t.cfg:2: ", "environment-map rotate 'nan' is not a finite number"},
    {G "environment-map sky.hdr rotate 90 spin 2\n", "t.cfg:2: ", "environment-map: unexpected 'spin'"},
    /* resolution, samples, max-depth */
    {G "resolution 640 abc\n", "t.cfg:2: ", "resolution height 'abc' is not a number"},
    {G "resolution 640\n", "t.cfg:2: ", "resolution needs 2 numbers, got 1"},
    {G "resolution\n", "t.cfg:2: ", "resolution needs 2 numbers, got 0"},
    {G "resolution 640 480 12\n", "t.cfg:2: ", "resolution needs 2 numbers, got 3: unexpected '12'"},
    {G "resolution 0 480\n", "t.cfg:2: ", "resolution width must be between 1 and 16384, got 0"},
    {G "resolution -640 480\n", "t.cfg:2: ", "resolution width must be between 1 and 16384"},
    {G "resolution 640 16385\n", "t.cfg:2: ", "resolution height must be between 1 and 16384"},
    {G "resolution 99999999999999999999999 1\n", "t.cfg:2: ", "between 1 and 16384"},
    {G "resolution 640.5 480\n", "t.cfg:2: ", "resolution width must be a whole number"},
    {G "samples 0\n", "t.cfg:2: ", "samples must be between 1 and 65536, got 0"},
    {G "samples 65537\n", "t.cfg:2: ", "samples must be between 1 and 65536"},
    {G "samples 1e3\n", "t.cfg:2: ", "samples must be a whole number, got '1e3'"},
    {G "samples\n", "t.cfg:2: ", "samples needs 1 number, got 0"},
    {G "max-depth 65\n", "t.cfg:2: ", "max-depth must be between 0 and 64"},
    {G "max-depth -1\n", "t.cfg:2: ", "max-depth must be between 0 and 64"},
    /* numbers */
    {G "environment nan 0 0\n", "t.cfg:2: ", "environment r 'nan' is not a finite number"},
    {G "environment 0 inf 0\n", "t.cfg:2: ", "environment g 'inf' is not a finite number"},
    {G "environment 0 0 1e999\n", "t.cfg:2: ", "environment b '1e999' is not a finite number"},
    {G "environment 0 0 1e39\n", "t.cfg:2: ", "environment b '1e39' is too large"},
    {G "environment 0 0 0.5x\n", "t.cfg:2: ", "environment b '0.5x' is not a number"},
    {G "environment -0.1 0 0\n", "t.cfg:2: ", "environment r must not be negative, got -0.1"},
    {G "environment 1 1\n", "t.cfg:2: ", "environment needs 3 numbers, got 2"},
    /* accel, output */
    {G "accel fast\n", "t.cfg:2: ", "unknown accel 'fast' (expected auto, brute, grid, bvh or kdtree)"},
    {G "accel octree\n", "t.cfg:2: ", "unknown accel 'octree' (expected auto, brute, grid, bvh or kdtree)"},
    {G "accel\n", "t.cfg:2: ", "accel needs one name (auto, brute, grid, bvh or kdtree), got 0"},
    {G "integrator mlt\n", "t.cfg:2: ", "unknown integrator 'mlt' (expected auto, whitted or path)"},
    {G "bvh-splits yes\n", "t.cfg:2: ", "unknown bvh-splits 'yes' (expected auto, on or off)"},
    {G "accel\n", "t.cfg:2: ", "accel needs one name"},
    {G "output x.jpg\n", "t.cfg:2: ", "output 'x.jpg' must end in .png or .exr"},
    {G "output out/f%s.png\n", "t.cfg:2: ", "unsupported conversion '%s' (use %d, %04d, or %% for a literal %)"},
    {G "output out/f%0d.png\n", "t.cfg:2: ", "unsupported conversion '%0d'"},
    {G "output out/f%123d.png\n", "t.cfg:2: ", "unsupported conversion '%123d'"},
    {G "output out/f%.exr\n", "t.cfg:2: ", "unsupported conversion '%.'"},
    {G "output f%d_%d.png\n", "t.cfg:2: ", "more than one frame number"},
    {G "output my frame.png\n", "t.cfg:2: ", "paths may not contain spaces"},
    /* paths */
    {"geometry\n", "t.cfg:1: ", "geometry needs a path"},
    {"geometry my model.obj\n", "t.cfg:1: ", "geometry: unexpected 'model.obj'"},
    {"geometry \"my model.obj\"\n", "t.cfg:1: ", "quotes are not supported"},
    {G "materials a b\n", "t.cfg:2: ", "paths may not contain spaces"},
    {G "materials 'a b'\n", "t.cfg:2: ", "quotes are not supported"},
    /* lights */
    {G "light spot 0 0 0 0 -1 0 30\n", "t.cfg:2: ", "light spot needs 10 numbers, got 7"},
    {G "light spot 0 0 0 0 -1 0 30 1 1 1 1\n", "t.cfg:2: ", "light spot needs 10 numbers, got 11"},
    {G "light spot 0 0 0 0 -1 0 0 1 1 1\n", "t.cfg:2: ", "half angle must be in (0, 90] degrees, got 0"},
    {G "light spot 0 0 0 0 -1 0 91 1 1 1\n", "t.cfg:2: ", "half angle must be in (0, 90] degrees, got 91"},
    {G "light spot 0 0 0 0 0 0 30 1 1 1\n", "t.cfg:2: ", "light spot direction has zero length"},
    {G "light spot 0 0 0 0 -1 0 x 1 1 1\n", "t.cfg:2: ", "light spot half angle 'x' is not a number"},
    {G "light directional 0 0 0 1 1 1\n", "t.cfg:2: ", "light directional direction has zero length"},
    {G "light directional 0 -1 zero 1 1 1\n", "t.cfg:2: ", "light directional direction z 'zero' is not a number"},
    {G "light point 0 0 0 1 -1 1\n", "t.cfg:2: ", "light point colour g must not be negative"},
    {G "light point 0 0 0 1 1\n", "t.cfg:2: ", "light point needs 6 numbers, got 5"},
    {G "light ambient 1 1\n", "t.cfg:2: ", "light ambient needs 3 numbers, got 2"},
    {G "light area 0 0 0\n", "t.cfg:2: ", "unknown light kind 'area'"},
    {G "light\n", "t.cfg:2: ", "light needs a kind"},
    /* coordinates beyond what the kernels' float arithmetic renders (coordinate_limit.h) */
    {G "light point 0 0 2e11 1 1 1\n", "t.cfg:2: ", "light point position z 2e11 is outside [-1e11, 1e11]"},
    {G "light spot -1.00001e11 0 0 0 -1 0 30 1 1 1\n", "t.cfg:2: ", "light spot position x -1.00001e11 is outside [-1e11, 1e11]"},
    {G "camera eye 0 1e38 5 look 0 0 0 up 0 1 0 fov 45\n", "t.cfg:2: ", "camera eye y 1e38 is outside [-1e11, 1e11]"},
    {G "camera eye 0 0 5 look 0 0 -1.00001e11 up 0 1 0 fov 45\n", "t.cfg:2: ", "camera look z -1.00001e11 is outside [-1e11, 1e11]"},
    /* cameras */
    {G "camera eye 0 0 0 look 0 0 0 up 0 1 0 fov 45\n", "t.cfg:2: ", "eye and look are the same point"},
    {G "camera eye 0 0 0 look 0 5 0 up 0 1 0 fov 45\n", "t.cfg:2: ", "up is parallel to the view direction"},
    {G "camera eye 0 0 0 look 0 0 -1 up 0 0 0 fov 45\n", "t.cfg:2: ", "camera up has zero length"},
    {G "camera eye 0 0 5 look 0 0 0 up 0 1 0 fov 180\n", "t.cfg:2: ", "fov must be between 0 and 180 degrees (exclusive), got 180"},
    {G "camera eye 0 0 5 look 0 0 0 up 0 1 0 fov 0\n", "t.cfg:2: ", "fov must be between 0 and 180"},
    {G "camera eye 0 0 5 look 0 0 0 up 0 1 0 fov -10\n", "t.cfg:2: ", "fov must be between 0 and 180"},
    {G "camera look 0 0 0 eye 0 0 5 up 0 1 0 fov 45\n", "t.cfg:2: ", "camera: expected 'eye' but found 'look'"},
    {G "camera eye 0 0 5 look 0 0 0 fov 45 up 0 1 0\n", "t.cfg:2: ", "camera: expected 'up' but found 'fov'"},
    {G "camera eye 0 0 5 look 0 0 0 up 0 1 0\n", "t.cfg:2: ", "camera is missing 'fov'"},
    {G "camera\n", "t.cfg:2: ", "camera is missing 'eye'"},
    {G "camera eye 0 0 look 0 0 0 up 0 1 0 fov 45\n", "t.cfg:2: ", "camera eye needs 3 numbers, got 2"},
    {G "camera eye 0 0 5 look 0 0 0 up 0 1 0 fov\n", "t.cfg:2: ", "camera fov needs 1 number, got 0"},
    {G "camera eye 0 0 5 look 0 0 0 up 0 1 0 fov 45 60\n", "t.cfg:2: ", "camera: unexpected '60' after fov"},
    {G "camera eye 0 a 5 look 0 0 0 up 0 1 0 fov 45\n", "t.cfg:2: ", "camera eye y 'a' is not a number"},
    {G "camera eye 0 0 5 look 0 0 0 up 0 1 0 fov wide\n", "t.cfg:2: ", "camera fov 'wide' is not a number"},
    /* orthographic cameras and names */
    {G "camera eye 0 0 5 look 0 0 0 up 0 1 0 ortho 0\n", "t.cfg:2: ", "camera ortho (the view's width in scene units) must be positive and at most 1e+11, got 0"},
    {G "camera eye 0 0 5 look 0 0 0 up 0 1 0 ortho -2\n", "t.cfg:2: ", "camera ortho (the view's width in scene units) must be positive"},
    {G "camera eye 0 0 5 look 0 0 0 up 0 1 0 ortho 2e11\n", "t.cfg:2: ", "at most 1e+11, got 2e11"},
    {G "camera eye 0 0 5 look 0 0 0 up 0 1 0 ortho wide\n", "t.cfg:2: ", "camera ortho 'wide' is not a number"},
    {G "camera eye 0 0 5 look 0 0 0 up 0 1 0 ortho\n", "t.cfg:2: ", "camera ortho needs 1 number, got 0"},
    {G "camera eye 0 0 5 look 0 0 0 up 0 1 0 fov 45 ortho 3\n", "t.cfg:2: ", "camera: unexpected 'ortho' after fov"},
    {G "camera eye 0 0 5 look 0 0 0 up 0 1 0 ortho 3 fov 45\n", "t.cfg:2: ", "camera: unexpected 'fov' after ortho"},
    {G "camera eye 0 0 5 look 0 0 0 up 0 1 0 width 3\n", "t.cfg:2: ", "camera: expected 'fov' or 'ortho' but found 'width'"},
    {G "camera eye 0 0 5 look 0 0 0 up 0 1 0 fov 45 name\n", "t.cfg:2: ", "camera name needs a word"},
    {G "camera eye 0 0 5 look 0 0 0 up 0 1 0 fov 45 name "
       "a123456789b123456789c123456789d123456789e123456789f123456789g123\n", "t.cfg:2: ",
     "camera name 'a123456789b123456789c123456789d123456789e123456789f123456789...' is longer than 63 bytes"},
    /* the first error wins, and its line is counted across CRLF, blanks and comments */
    {"# c\r\n\r\n" G "samples 0\r\nfoo\r\n", "t.cfg:4: ", "samples must be between 1 and 65536"},
    {"# c\r\r" G "samples 0\rfoo\r", "t.cfg:4: ", "samples must be between 1 and 65536"},
    /* text that is not a scene.cfg */
    {G "samples 1\x01\n", "t.cfg:2: ", "not a text line (control character 0x01"},
    {G "\xff\xfe\xfd\n", "t.cfg:2: ", "not a text line (invalid UTF-8 at column 1)"},
    {G "geometry \xc3\x28.obj\n", "t.cfg:2: ", "invalid UTF-8 at column 10"},
    /* whole file */
    {"", "t.cfg: ", "no 'geometry' line"},
    {"# only a comment\n" CAMERA, "t.cfg: ", "no 'geometry' line"},
};

/* Points up to 1e11 from the origin are taken as given; up is a direction, which any finite
 * size may have (the camera's frame normalises it). */
static void test_coordinates_at_the_limit(void **state)
{
    (void)state;
    vkrt_config cfg;
    parse_ok("geometry m.obj\nlight point 1e11 -1e11 0 1 1 1\nlight spot 0 1e11 0 0 -1 0 30 1 1 1\n"
             "camera eye -1e11 0 1e11 look 1e11 0 -1e11 up 0 1e30 0 fov 45\n",
             "base", &cfg);
    assert_vec3(cfg.lights[0].position, 1e11f, -1e11f, 0);
    assert_vec3(cfg.lights[1].position, 0, 1e11f, 0);
    assert_vec3(cfg.cameras[0].eye, -1e11f, 0, 1e11f);
    assert_vec3(cfg.cameras[0].look, 1e11f, 0, -1e11f);
    vkrt_config_free(&cfg);
}

static void test_malformed(void **state)
{
    (void)state;
    for (size_t i = 0; i < sizeof bad_cases / sizeof bad_cases[0]; i++) {
        const bad_case *c = &bad_cases[i];
        parse_fails(c->text, strlen(c->text), c->prefix, c->phrase);
    }
}

static void test_nul_and_binary(void **state)
{
    (void)state;
    static const char nul_text[] = "geometry m.obj\nsam\0ples 2\n" CAMERA;
    parse_fails(nul_text, sizeof nul_text - 1, "t.cfg:2: ", "not a text line (NUL byte");

    /* Bytes that look like an ELF file must be refused on line 1, not crash the parser. */
    unsigned char garbage[512];
    garbage[0] = 0x7F;
    memcpy(garbage + 1, "ELF", 3);
    for (size_t i = 4; i < sizeof garbage; i++)
        garbage[i] = (unsigned char)(i * 37 + 11);
    parse_fails((const char *)garbage, sizeof garbage, "t.cfg:1: ", "not a text line");

    /* size bounds the text: nothing past it is read (the sanitizer checks that). */
    char *exact = malloc(14);
    assert_non_null(exact);
    memcpy(exact, "geometry m.ob\x01", 14);
    parse_fails(exact, 14, "t.cfg:1: ", "not a text line");
    free(exact);

    /* NULL text of size 0 is an empty file. */
    parse_fails(NULL, 0, "t.cfg: ", "no 'geometry' line");
}

static void test_long_lines(void **state)
{
    (void)state;
    size_t n = 10000;
    char *text = malloc(n + 32);
    assert_non_null(text);
    int head = snprintf(text, n + 32, "%s# ", G);
    memset(text + head, 'x', n);
    strcpy(text + head + n, "\n");
    parse_fails(text, strlen(text), "t.cfg:2: ", "line is longer than 4096 bytes");

    /* Exactly 4096 bytes is allowed; a long token is quoted cut short in the message. */
    head = snprintf(text, n + 32, "%sfoo", G);
    memset(text + head, 'y', 4096 - 3);
    strcpy(text + head + 4096 - 3, "\n");
    parse_fails(text, strlen(text), "t.cfg:2: ", "unknown keyword 'fooyyy");
    parse_fails(text, strlen(text), "t.cfg:2: ", "yyy...' (expected geometry");

    /* Many tokens on one line still give a true count. */
    strcpy(text, G "resolution");
    for (int i = 0; i < 100; i++)
        strcat(text, " 1");
    strcat(text, "\n");
    parse_fails(text, strlen(text), "t.cfg:2: ", "resolution needs 2 numbers, got 100");
    free(text);
}

/* ---------------------------------------------------------------------------------------------
 * vkrt_config_load
 * ------------------------------------------------------------------------------------------- */

/* The name lists of messages hold every name the parsers take: each enum value's name is in
 * its list, and each listed name parses. */
static void test_name_lists(void **state)
{
    (void)state;
    char names[VKRT_NAMES_BYTES];
    for (int k = VKRT_ACCEL_AUTO; k <= VKRT_ACCEL_KDTREE; k++)
        assert_non_null(strstr(vkrt_accel_names(names), vkrt_accel_name((vkrt_accel_kind)k)));
    for (int k = VKRT_INTEGRATOR_AUTO; k <= VKRT_INTEGRATOR_PATH; k++)
        assert_non_null(
            strstr(vkrt_integrator_names(names), vkrt_integrator_name((vkrt_integrator)k)));
    for (int k = VKRT_BVH_SPLITS_AUTO; k <= VKRT_BVH_SPLITS_OFF; k++)
        assert_non_null(
            strstr(vkrt_bvh_splits_names(names), vkrt_bvh_splits_name((vkrt_bvh_splits)k)));
    char *save = NULL;
    vkrt_accel_names(names);
    for (char *n = strtok_r(names, ", ", &save); n;
         n = strtok_r(NULL, ", ", &save))
        assert_true(strcmp(n, "or") == 0 || vkrt_accel_parse(n, NULL));
}

static void test_load_file(void **state)
{
    (void)state;
    char dir[] = "/tmp/vkrt-test-config-XXXXXX";
    assert_non_null(mkdtemp(dir));
    char path[128];
    snprintf(path, sizeof path, "%s/scene.cfg", dir);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    fputs("geometry model.obj\noutput /tmp/x.png\n" CAMERA, f);
    fclose(f);

    vkrt_config cfg;
    vkrt_error err = {{0}};
    assert_true(vkrt_config_load(path, &cfg, &err));
    char want[160];
    snprintf(want, sizeof want, "%s/model.obj", dir);
    assert_string_equal(cfg.path, path);
    assert_string_equal(cfg.geometries[0].path, want);
    assert_string_equal(cfg.output, "/tmp/x.png");
    vkrt_config_free(&cfg);

    /* A malformed file names itself by the path as given. */
    f = fopen(path, "wb");
    assert_non_null(f);
    fputs("geometry model.obj\nsamples many\n", f);
    fclose(f);
    memset(&cfg, 0xAB, sizeof cfg);
    assert_false(vkrt_config_load(path, &cfg, &err));
    char prefix[256];
    snprintf(prefix, sizeof prefix, "%s:2: samples 'many' is not a number", path);
    assert_string_equal(err.msg, prefix);
    assert_zeroed(&cfg);

    /* A directory opens but cannot be read. */
    memset(&cfg, 0xAB, sizeof cfg);
    assert_false(vkrt_config_load(dir, &cfg, &err));
    assert_non_null(strstr(err.msg, "cannot read"));
    assert_zeroed(&cfg);

    unlink(path);
    rmdir(dir);
}

static void test_load_relative_name(void **state)
{
    (void)state;
    /* A bare file name resolves against the current folder: paths stay as written. */
    char dir[] = "/tmp/vkrt-test-config-XXXXXX";
    assert_non_null(mkdtemp(dir));
    char old[4096];
    assert_non_null(getcwd(old, sizeof old));
    assert_int_equal(chdir(dir), 0);
    FILE *f = fopen("s.cfg", "wb");
    assert_non_null(f);
    fputs("geometry m.obj\n" CAMERA, f);
    fclose(f);
    vkrt_config cfg;
    vkrt_error err = {{0}};
    bool ok = vkrt_config_load("s.cfg", &cfg, &err);
    unlink("s.cfg");
    assert_int_equal(chdir(old), 0);
    rmdir(dir);
    assert_true(ok);
    assert_string_equal(cfg.geometries[0].path, "m.obj");
    vkrt_config_free(&cfg);
}

static void test_load_missing_file(void **state)
{
    (void)state;
    vkrt_config cfg;
    memset(&cfg, 0xAB, sizeof cfg);
    vkrt_error err = {{0}};
    assert_false(vkrt_config_load("/nonexistent/vkrt/scene.cfg", &cfg, &err));
    assert_string_equal(err.msg, "/nonexistent/vkrt/scene.cfg: cannot open: No such file or "
                                 "directory");
    assert_zeroed(&cfg);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_keyword),
        cmocka_unit_test(test_defaults),
        cmocka_unit_test(test_limits_accepted),
        cmocka_unit_test(test_path_resolution),
        cmocka_unit_test(test_crlf_bom_and_no_final_newline),
        cmocka_unit_test(test_comments_and_whitespace),
        cmocka_unit_test(test_flythrough),
        cmocka_unit_test(test_orthographic_and_named_cameras),
        cmocka_unit_test(test_many_lights_and_cameras),
        cmocka_unit_test(test_accel_names),
        cmocka_unit_test(test_integrator_names),
        cmocka_unit_test(test_tonemap_names),
        cmocka_unit_test(test_environment_map),
        cmocka_unit_test(test_geometry_placement),
        cmocka_unit_test(test_for_geometry),
        cmocka_unit_test(test_free_zeroed_struct),
        cmocka_unit_test(test_malformed),
        cmocka_unit_test(test_coordinates_at_the_limit),
        cmocka_unit_test(test_nul_and_binary),
        cmocka_unit_test(test_long_lines),
        cmocka_unit_test(test_name_lists),
        cmocka_unit_test(test_load_file),
        cmocka_unit_test(test_load_relative_name),
        cmocka_unit_test(test_load_missing_file),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
