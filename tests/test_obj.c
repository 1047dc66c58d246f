/*
 * test_obj.c: tests of the OBJ loader (src/scene/obj/obj_load.h).
 *
 * Small OBJ/MTL files written to a temporary folder pin down the behaviour (fan order, negative
 * indices, geometric normals, CRLF, errors with file:line, odd encodings, materials). Then the
 * shared scenes, when $VKRT_SCENES_DIR is set: every .obj of the tinyobjloader and assimp parser
 * suites must load or fail cleanly, with triangle counts matching their SOURCE.txt, and the
 * Cornell box and the Stanford bunny must load whole. The parallel parse (obj_geometry.h) is held
 * to the serial one: every suite file, and a file written to put every case at a cut, give the
 * same mesh, warnings or error whether read whole on one thread or cut at every line on several.
 */
#define _XOPEN_SOURCE 700
#include <dirent.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>

#include "scene/obj/mtl.h"
#include "scene/obj/obj_load.h"
#include "scene/text_file.h"
#include "shared_scenes.h"
#include "temp_dir.h"

/* ------------------------------------------------------------------------ helpers */

static void assert_close(float got, float want)
{
    if (fabsf(got - want) > 1e-5f)
        fail_msg("got %g, want %g", (double)got, (double)want);
}

static void assert_vec3(const float *got, float x, float y, float z)
{
    assert_close(got[0], x);
    assert_close(got[1], y);
    assert_close(got[2], z);
}

/* Loads path, expecting failure whose message starts with "path" then `after` (e.g. ":3: vertex"). */
static void assert_load_fails(const char *path, const char *after)
{
    vkrt_model mesh;
    vkrt_error err = {{0}};
    assert_false(vkrt_obj_load(path, &mesh, &err));
    size_t n = strlen(path);
    if (strncmp(err.msg, path, n) != 0 || strncmp(err.msg + n, after, strlen(after)) != 0)
        fail_msg("error \"%s\" does not read \"%s%s...\"", err.msg, path, after);
    assert_null(mesh.meshes);
    assert_int_equal(mesh.triangle_count, 0);
}

/* Writes text to name in the folder and loads it, expecting the failure assert_load_fails
 * checks. */
static void assert_text_fails(temp_dir *fx, const char *name, const char *text, const char *after)
{
    assert_load_fails(temp_dir_write_text(fx, name, text), after);
}

static vkrt_model load_ok(const char *path)
{
    vkrt_model mesh;
    vkrt_error err = {{0}};
    if (!vkrt_obj_load(path, &mesh, &err))
        fail_msg("loading %s failed: %s", path, err.msg);
    return mesh;
}

/* ------------------------------------------------------------------------ the parallel parse */

static void assert_same_floats(const float *a, const float *b, size_t n, const char *what,
                               const char *name)
{
    if ((a == NULL) != (b == NULL))
        fail_msg("%s: %s present in one parse only", name, what);
    if (a && memcmp(a, b, n * sizeof *a) != 0)
        fail_msg("%s: %s differ between the serial and the split parse", name, what);
}

/* The mesh's bounds are those of its positions, taken in one pass in order (the loader computes
 * them per group of faces on every core and merges them). */
static void assert_bounds_of_positions(const vkrt_model *m, const char *name)
{
    float lo[3], hi[3];
    for (int a = 0; a < 3; a++)
        lo[a] = hi[a] = m->meshes[0].positions[a];
    for (size_t i = 0; i < (size_t)m->triangle_count * 3; i++)
        for (int a = 0; a < 3; a++) {
            float v = m->meshes[0].positions[3 * i + a];
            lo[a] = v < lo[a] ? v : lo[a];
            hi[a] = v > hi[a] ? v : hi[a];
        }
    if (memcmp(lo, m->bounds_min, sizeof lo) != 0 || memcmp(hi, m->bounds_max, sizeof hi) != 0)
        fail_msg("%s: bounds (%g %g %g)-(%g %g %g) are not those of the positions", name,
                 (double)m->bounds_min[0], (double)m->bounds_min[1], (double)m->bounds_min[2],
                 (double)m->bounds_max[0], (double)m->bounds_max[1], (double)m->bounds_max[2]);
}

/* The two parses of one text agree on everything: the error, or the mesh and its warnings. */
static void assert_same_parse(bool ok_a, const vkrt_model *a, const vkrt_error *err_a, bool ok_b,
                              const vkrt_model *b, const vkrt_error *err_b, const char *name,
                              size_t chunk)
{
    if (ok_a != ok_b || (!ok_a && strcmp(err_a->msg, err_b->msg) != 0))
        fail_msg("%s cut every %zu bytes: \"%s\" against \"%s\" serially", name, chunk,
                 ok_b ? "loaded" : err_b->msg, ok_a ? "loaded" : err_a->msg);
    if (!ok_a)
        return;
    size_t n = a->triangle_count;
    if (n != b->triangle_count)
        fail_msg("%s cut every %zu bytes: %u triangles against %zu", name, chunk, b->triangle_count,
                 n);
    assert_same_floats(a->meshes[0].positions, b->meshes[0].positions, 9 * n, "positions", name);
    assert_bounds_of_positions(a, name);
    assert_bounds_of_positions(b, name);
    assert_same_floats(a->meshes[0].normals, b->meshes[0].normals, 9 * n, "normals", name);
    assert_same_floats(a->meshes[0].texcoords, b->meshes[0].texcoords, 6 * n, "texture coordinates", name);
    if (memcmp(a->meshes[0].material, b->meshes[0].material, n * sizeof *a->meshes[0].material) != 0)
        fail_msg("%s cut every %zu bytes: materials of the triangles differ", name, chunk);
    assert_int_equal(a->material_count, b->material_count);
    for (uint32_t i = 0; i < a->material_count; i++)
        assert_string_equal(a->materials[i].name, b->materials[i].name);
    assert_string_equal(a->warnings, b->warnings);
    assert_string_equal(a->warnings_all ? a->warnings_all : "",
                        b->warnings_all ? b->warnings_all : "");
}

/* Parses text whole on one thread, then cut every 1, 2, 7, 64 and 4096 bytes (at the next line
 * end) on two and on five threads, and holds every cut parse to the whole one. base_dir as for
 * vkrt_obj_parse. Returns the serial parse's success. */
static bool check_split_parses(const char *text, size_t size, const char *name,
                               const char *base_dir)
{
    static const size_t CHUNKS[] = {1, 2, 7, 64, 4096};
    vkrt_model whole;
    vkrt_error whole_err = {{0}};
    bool whole_ok =
        vkrt_obj_parse_split(text, size, name, base_dir, SIZE_MAX, 1, &whole, &whole_err);
    for (size_t c = 0; c < sizeof CHUNKS / sizeof CHUNKS[0]; c++) {
        if (CHUNKS[c] > size && c > 0)
            break;
        for (unsigned threads = 2; threads <= 5; threads += 3) {
            vkrt_model cut;
            vkrt_error cut_err = {{0}};
            bool cut_ok = vkrt_obj_parse_split(text, size, name, base_dir, CHUNKS[c], threads, &cut,
                                               &cut_err);
            assert_same_parse(whole_ok, &whole, &whole_err, cut_ok, &cut, &cut_err, name,
                              CHUNKS[c]);
            vkrt_model_free(&cut);
        }
    }
    vkrt_model_free(&whole);
    return whole_ok;
}

/* check_split_parses on the file at path, with its folder for the .mtl files. */
static void check_split_file(const char *path)
{
    char *text, *folder = vkrt_text_dir_of(path);
    size_t size;
    vkrt_error err = {{0}};
    if (!vkrt_text_read_file(path, SIZE_MAX, "OBJ", &text, &size, &err))
        fail_msg("%s", err.msg);
    check_split_parses(text, size, path, folder);
    free(text);
    free(folder);
}

/* What crosses a cut: relative indices (v, vt and vn) reaching back over many chunks, the usemtl,
 * g, o and s in force, line numbers in warnings; and lines that end in CRLF, in "\\" (rc10 knows
 * no continuation lines: "f 1 2 \\" then "3" is a refused face), in nothing at the file's end. */
static const char AWKWARD_MTL[] = "newmtl red\nKd 1 0 0\nnewmtl blue\nKd 0 0 1\n";
static const char AWKWARD[] = "# cut anywhere\nmtllib awkward.mtl\nv 0 0 0\nv 1 0 0\r\nv 1 1 0\nv "
                              "0 1 0\n\nvt 0 0\nvt 1 0\nvt 1 1\n"
                              "vn 0 0 1\nvn 0 0 nan\no first\ng box side\nusemtl red\ns 1\n"
                              "f -4/-3/-2 -3/-2/-2 -2/-1/-2\n"
                              "   \t\n"
                              "f 1/1/1 2/2/1 3/3/1 4/3/1\r\n"
                              "usemtl nothing\nf 1 2\nf 2 3 4\n"
                              "v 0 0 1\nv 0 1 1\nvw 0 0 0.5\nusemtl blue\ng other\ns off\n"
                              "f -1 -2 -6//-1\nf -6/-3 -5/-2 -4/-1\n"
                              "usemtl red\nl 1 2\np 3\nf 4 5 6 -1";
static const char CONTINUED[] = "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 \\\n3\n";

static void split_parse_matches_serial(void **state)
{
    temp_dir_write_text(*state, "awkward.mtl", AWKWARD_MTL);
    const char *dir = temp_dir_path(*state, "");
    assert_true(check_split_parses(AWKWARD, strlen(AWKWARD), "awkward.obj", dir));
    /* the same at every start offset of the cuts: chunks of 1 byte end at every line end anyway,
     * so the file is cut again after a prefix of every length */
    vkrt_model m;
    vkrt_error err = {{0}};
    assert_true(vkrt_obj_parse_split(AWKWARD, strlen(AWKWARD), "awkward.obj", dir, 3, 4, &m, &err));
    assert_int_equal(m.triangle_count, 7); /* f 4 5 6 -1's second triangle (4 6 6) has no area */
    assert_int_equal(m.meshes[0].material[2], 0);  /* red, from before every cut */
    assert_int_equal(m.meshes[0].material[3], -1); /* usemtl nothing */
    assert_int_equal(m.meshes[0].material[4], 1);  /* blue */
    assert_int_equal(m.meshes[0].material[6], 0);
    assert_vec3(&m.meshes[0].positions[36], 0, 1, 1); /* f -1 -2 -6//-1: v 6, v 5, v 1 */
    assert_vec3(&m.meshes[0].positions[39], 0, 0, 1);
    assert_vec3(&m.meshes[0].positions[42], 0, 0, 0);
    assert_vec3(&m.meshes[0].normals[36], 1, 0, 0); /* vn 2 (nan) is unusable: the geometric normal */
    assert_non_null(
        strstr(m.warnings_all, "awkward.obj:21: warning: face of fewer than 3 corners"));
    assert_non_null(strstr(m.warnings_all, "awkward.obj:20: warning: usemtl nothing"));
    vkrt_model_free(&m);
    assert_false(check_split_parses(CONTINUED, strlen(CONTINUED), "continued.obj", NULL));
    assert_false(
        vkrt_obj_parse_split(CONTINUED, strlen(CONTINUED), "continued.obj", NULL, 1, 2, &m, &err));
    assert_string_equal(err.msg, "continued.obj:4: face index '\\' is not a number");
}

/* ------------------------------------------------------------------------ small files */

static const char QUAD[] = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";

static void quad_becomes_fan(void **state)
{
    vkrt_model m = load_ok(temp_dir_write_text(*state, "quad.obj", QUAD));
    assert_int_equal(m.triangle_count, 2);
    /* fan: (v0 v1 v2), (v0 v2 v3) */
    assert_vec3(&m.meshes[0].positions[0], 0, 0, 0);
    assert_vec3(&m.meshes[0].positions[3], 1, 0, 0);
    assert_vec3(&m.meshes[0].positions[6], 1, 1, 0);
    assert_vec3(&m.meshes[0].positions[9], 0, 0, 0);
    assert_vec3(&m.meshes[0].positions[12], 1, 1, 0);
    assert_vec3(&m.meshes[0].positions[15], 0, 1, 0);
    assert_null(m.meshes[0].normals);
    assert_null(m.meshes[0].texcoords);
    assert_int_equal(m.meshes[0].material[0], -1);
    assert_int_equal(m.meshes[0].material[1], -1);
    assert_vec3(m.bounds_min, 0, 0, 0);
    assert_vec3(m.bounds_max, 1, 1, 0);
    assert_string_equal(m.warnings, "");
    vkrt_model_free(&m);
    assert_null(m.meshes);
    vkrt_model_free(&m); /* safe on a zeroed struct */
}

/* More than 255 corners: tinyobjloader's per-face count is an unsigned char. */
static void big_polygon_keeps_all_corners(void **state)
{
    enum { N = 300 };
    static char text[N * 40];
    size_t len = 0;
    for (int i = 0; i < N; i++) {
        double a = 6.283185307179586 * i / N;
        len += (size_t)snprintf(text + len, sizeof text - len, "v %f %f 0\n", cos(a), sin(a));
    }
    len += (size_t)snprintf(text + len, sizeof text - len, "f");
    for (int i = 1; i <= N; i++)
        len += (size_t)snprintf(text + len, sizeof text - len, " %d", i);
    snprintf(text + len, sizeof text - len, "\nf 1 2 3\n");
    vkrt_model m = load_ok(temp_dir_write_text(*state, "big.obj", text));
    assert_int_equal(m.triangle_count, N - 2 + 1);
    assert_vec3(&m.meshes[0].positions[9 * (N - 3) + 6], (float)cos(6.283185307179586 * (N - 1) / N),
                (float)sin(6.283185307179586 * (N - 1) / N), 0);
    vkrt_model_free(&m);
}

static void negative_indices(void **state)
{
    const char *text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0.25 0.5\nvn 0 0 1\n"
                       "f -4/-1/-1 -3/-1/-1 -2/-1/-1 -1/-1/-1\n";
    vkrt_model m = load_ok(temp_dir_write_text(*state, "neg.obj", text));
    assert_int_equal(m.triangle_count, 2);
    assert_vec3(&m.meshes[0].positions[6], 1, 1, 0);
    assert_vec3(&m.meshes[0].positions[15], 0, 1, 0);
    assert_non_null(m.meshes[0].texcoords);
    assert_close(m.meshes[0].texcoords[0], 0.25f);
    assert_close(m.meshes[0].texcoords[1], 0.5f);
    assert_non_null(m.meshes[0].normals);
    assert_vec3(&m.meshes[0].normals[0], 0, 0, 1);
    vkrt_model_free(&m);
}

static void geometric_normal_for_faces_without(void **state)
{
    /* Triangle 1 has a (non-unit) file normal; triangle 2 lies in the xz plane, wound so that
     * (v1-v0) x (v2-v0) = (0,0,1) x (1,0,0) = (0,1,0); triangle 3 is degenerate, and dropped. */
    const char *text = "v 0 0 0\nv 0 0 1\nv 1 0 0\nvn 0 0 2\n"
                       "f 1//1 2//1 3//1\n"
                       "f 1 2 3\n"
                       "f 1 1 1\n";
    vkrt_model m = load_ok(temp_dir_write_text(*state, "normals.obj", text));
    assert_int_equal(m.triangle_count, 2);
    assert_non_null(m.meshes[0].normals);
    for (int k = 0; k < 3; k++) {
        assert_vec3(&m.meshes[0].normals[3 * k], 0, 0, 1);
        assert_vec3(&m.meshes[0].normals[9 + 3 * k], 0, 1, 0);
    }
    vkrt_model_free(&m);
}

static void unusable_file_normal_becomes_geometric(void **state)
{
    const char *text = "v 0 0 0\nv 0 0 1\nv 1 0 0\nvn nan 0 0\nvn 0 0 0\nf 1//1 2//1 3//1\nf 1//2 2//2 3//2\n";
    vkrt_model m = load_ok(temp_dir_write_text(*state, "badnormal.obj", text));
    assert_int_equal(m.triangle_count, 2);
    assert_vec3(&m.meshes[0].normals[0], 0, 1, 0);
    assert_vec3(&m.meshes[0].normals[9], 0, 1, 0);
    assert_non_null(strstr(m.warnings, "geometric normal"));
    vkrt_model_free(&m);
}

/* Normals named by faces of a file without any vn records are dropped with a warning (the
 * tinyobjloader suite has two such files); with some vn records a bad index is an error. */
static void references_to_absent_normals_are_dropped(void **state)
{
    const char *text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1/1 2/2/2 3/3/3\n";
    vkrt_model m = load_ok(temp_dir_write_text(*state, "stripped.obj", text));
    assert_int_equal(m.triangle_count, 1);
    assert_null(m.meshes[0].normals);
    assert_null(m.meshes[0].texcoords);
    assert_non_null(strstr(m.warnings, "no vn records"));
    assert_non_null(strstr(m.warnings, "no vt records"));
    vkrt_model_free(&m);
}

static void crlf_line_endings(void **state)
{
    temp_dir *fx = *state;
    const char *text = "v 0 0 0\r\nv 1 0 0\r\nv 1 1 0\r\nv 0 1 0\r\nf 1 2 3 4\r\n";
    vkrt_model m = load_ok(temp_dir_write_text(fx, "crlf.obj", text));
    assert_int_equal(m.triangle_count, 2);
    assert_vec3(&m.meshes[0].positions[15], 0, 1, 0);
    vkrt_model_free(&m);
    /* line numbers count CRLF (and lone CR) as one line end */
    assert_text_fails(fx, "crlf_nan.obj", "v 0 0 0\r\n\r\nv 1 nan 0\r\nv 0 1 0\r\nf 1 2 3\r\n",
                      ":3: vertex coordinate is not finite");
    assert_text_fails(fx, "cr_nan.obj", "v 0 0 0\rv 1 0 0\rv inf 1 0\rf 1 2 3\r",
                      ":3: vertex coordinate is not finite");
}

static void non_finite_vertex_names_line(void **state)
{
    temp_dir *fx = *state;
    const char *bad[] = {"nan", "-nan", "inf", "-inf", "1e999", "1.#IND", "1e39"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char text[200];
        snprintf(text, sizeof text, "# comment\nv 0 0 0\nv 1 %s 0\nv 0 1 0\nf 1 2 3\n", bad[i]);
        assert_text_fails(fx, "nan.obj", text, ":3: vertex coordinate is not finite");
    }
    /* tinyobjloader would read these as 0 or as a prefix; we refuse them */
    assert_text_fails(fx, "abc.obj", "v 0 0 0\nv 1 abc 0\nv 0 1 0\nf 1 2 3\n",
                      ":2: vertex coordinate 'abc' is not a number");
    assert_text_fails(fx, "plus.obj", "v 0 0 0\nv 1 0 0\nv 3.1+e2 1 0\nf 1 2 3\n",
                      ":3: vertex coordinate '3.1+e2' is not a number");
    assert_text_fails(fx, "short.obj", "v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n",
                      ":2: vertex has 2 coordinates, needs 3");
    assert_text_fails(fx, "vt.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt inf 0\nf 1/1 2/1 3/1\n",
                      ":4: texture coordinate is not finite");
}

/* A finite coordinate past the range the kernels' float arithmetic renders (1e11,
 * src/scene/coordinate_limit.h) is refused with its line: 1e38 used to render a black image with
 * exit 0. Coordinates at the limit load as they are. */
static void vertex_beyond_coordinate_limit_names_line(void **state)
{
    temp_dir *fx = *state;
    const char *bad[] = {"1e38", "-1e38", "1.00001e11", "-3.4e38"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char text[200], after[100];
        snprintf(text, sizeof text, "v 0 0 0\nv %s 0 0\nv 0 1 0\nf 1 2 3\n", bad[i]);
        snprintf(after, sizeof after, ":2: vertex coordinate %s is outside [-1e11, 1e11]", bad[i]);
        assert_text_fails(fx, "far.obj", text, after);
    }
    vkrt_model m = load_ok(
        temp_dir_write_text(fx, "edge.obj", "v -1e11 0 0\nv 1e11 0 0\nv 0 1e11 -1e11\nf 1 2 3\n"));
    assert_int_equal(m.triangle_count, 1);
    assert_vec3(&m.meshes[0].positions[0], -1e11f, 0, 0);
    assert_vec3(&m.meshes[0].positions[6], 0, 1e11f, -1e11f);
    vkrt_model_free(&m);
}

static void out_of_range_index_names_line(void **state)
{
    temp_dir *fx = *state;
    assert_text_fails(fx, "range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 9\n",
                      ":5: face index 9 out of range (file has 3 vertices)");
    assert_text_fails(fx, "huge.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999\n",
                      ":4: face index 99999999999 is too large (more than 2147483647)");
    assert_text_fails(fx, "rel.obj", "v 0 0 0\nv 1 0 0\nf -1 -2 -3\nv 0 1 0\n",
                      ":3: face index -3 out of range (only 2 vertices before this line)");
    assert_text_fails(fx, "vn.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//2\n",
                      ":5: face normal index 2 out of range (file has 1 normals)");
    assert_text_fails(fx, "vt_range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/4 3/1\n",
                      ":5: face texture coordinate index 4 out of range (file has 1 texture");
}

static void empty_and_triangle_free_files_fail(void **state)
{
    temp_dir *fx = *state;
    assert_text_fails(fx, "empty.obj", "", ": no triangles");
    assert_text_fails(fx, "lines.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\np 3\nf 1 2\n",
                      ": no triangles");
    char missing[600];
    snprintf(missing, sizeof missing, "%s/does_not_exist.obj", fx->dir);
    assert_load_fails(missing, ": cannot open");
    /* why there are none, from what the file holds */
    assert_text_fails(fx, "empty.obj", "", ": no triangles (no v or f records)");
    assert_text_fails(fx, "lines.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\np 3\nf 1 2\n",
                      ": no triangles (every f record has fewer than 3 corners)");
    assert_text_fails(fx, "points.obj", "v 0 0 0\nv 1 0 0\np 1 2\n", ": no triangles (no f records)");
}

/* Triangles of zero area (corners on a line or at one point) are dropped with one warning that
 * counts them; a file with nothing else is an error, not a black picture. */
static void zero_area_faces(void **state)
{
    temp_dir *fx = *state;
    assert_text_fails(fx, "flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\nf 1 1 2\nf 3 3 3\n",
                      ": all 3 faces have zero area (their corners lie on a line or at one point): "
                      "nothing to draw");
    vkrt_model m = load_ok(temp_dir_write_text(
        fx, "some.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 9 9 9\nf 1 2 3\nf 1 2 4\nf 5 5 5\nf 2 2 4\n"));
    assert_int_equal(m.triangle_count, 1);
    assert_vec3(&m.meshes[0].positions[6], 0, 1, 0);
    assert_vec3(m.meshes[0].bounds_max, 1, 1, 0); /* the box of what is left: not the stray 9 9 9 */
    char want[700];
    snprintf(want, sizeof want, "%s/some.obj: warning: 3 triangles have zero area (lines or points) and were dropped",
             fx->dir);
    assert_string_equal(m.warnings, want);
    vkrt_model_free(&m);
}

/* tinyobjloader refuses an f line with an index it reads as 0; the message says which index and
 * why, in our words (its own was "Failed parse `f' line(e.g. zero value for face index. line 4.)"). */
static void refused_face_index_names_line_and_index(void **state)
{
    temp_dir *fx = *state;
    const char *v = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n";
    static const struct {
        const char *face, *after;
    } cases[] = {
        {"f 0 1 2", ":6: face index 0 is not valid (OBJ indices start at 1)"},
        {"f 1/1/1 2/0/1 3/1/1", ":6: face texture coordinate index 0 is not valid (OBJ indices start at 1)"},
        {"f 1//1 2//1 3//-0", ":6: face normal index 0 is not valid (OBJ indices start at 1)"},
        {"f 1/1/1 2/1/0 3/1/1", ":6: face normal index 0 is not valid"},
        {"f 1 2 3/", ":6: face texture coordinate index missing in corner '3/'"},
        {"f 1 x 3", ":6: face index 'x' is not a number"},
        {"f 1 2 4294967296", ":6: face index 4294967296 is too large"},
        /* atoi's readings, which rc10 takes: 99999999999999999999 saturates to -1 (the last
         * vertex), 4294967298 wraps to 2, "2x", "1.5" and "1e5" stop at the first non-digit */
        {"f 1 2 99999999999999999999", ":6: face index 99999999999999999999 is too large (more than 2147483647)"},
        {"f 1 2 4294967298", ":6: face index 4294967298 is too large (more than 2147483647)"},
        {"f 1 2 -4294967298", ":6: face index -4294967298 is too large (more than 2147483647)"},
        {"f 1 2 2x", ":6: face index '2x' is not a number"},
        {"f 1 2 1.5", ":6: face index '1.5' is not a whole number"},
        {"f 1 2 1e5", ":6: face index '1e5' is not a whole number"},
        {"f 1/1x 2/1 3/1", ":6: face texture coordinate index '1x' is not a number"},
        {"f 1//1 2//1 3//4294967297", ":6: face normal index 4294967297 is too large"},
        {"f 1/1/1.0 2/1/1 3/1/1", ":6: face normal index '1.0' is not a whole number"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char text[300];
        snprintf(text, sizeof text, "%s%s\n", v, cases[i].face);
        assert_text_fails(fx, "zero.obj", text, cases[i].after);
    }
    /* line and point records: vkrt draws neither, but tinyobjloader refuses them the same way */
    char text[300];
    snprintf(text, sizeof text, "%sl 0 1\nf 1 2 3\n", v);
    assert_text_fails(fx, "line0.obj", text,
                      ":6: line (l) record has an index of 0 or one that is not a number");
}

/* An image, or another binary format, named as the OBJ: the message says what the file is. */
static void binary_formats_are_named(void **state)
{
    temp_dir *fx = *state;
    /* the start of a real PNG: signature, IHDR of a 1x1 RGBA image */
    const unsigned char png[] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n', 0, 0, 0, 13, 'I', 'H', 'D',
                                 'R',  0,   0,   0,   1,    0,    0,    0,    1, 8, 6, 0,  0,   0};
    temp_dir_write(fx, "texture.png", png, sizeof png);
    assert_load_fails(fx->path, ": not an OBJ text file: it starts like a PNG image");
    const unsigned char jpeg[] = {0xFF, 0xD8, 0xFF, 0xE0, 0, 16, 'J', 'F', 'I', 'F', 0};
    temp_dir_write(fx, "photo.obj", jpeg, sizeof jpeg);
    assert_load_fails(fx->path, ": not an OBJ text file: it starts like a JPEG image");
    /* text formats have no NUL byte to give them away */
    temp_dir_write_text(fx, "sky.obj", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 1\nabcd");
    assert_load_fails(fx->path, ": not an OBJ text file: it starts like a Radiance HDR image");
    temp_dir_write_text(fx, "mesh.obj", "ply\nformat ascii 1.0\nelement vertex 3\n");
    assert_load_fails(fx->path, ": not an OBJ text file: it starts like a PLY file");
}

/* Deterministic bytes so a failure can be reproduced. */
static void fill_garbage(unsigned char *buf, size_t n, uint32_t seed, int allow_nul)
{
    for (size_t i = 0; i < n; i++) {
        seed = seed * 1664525u + 1013904223u;
        buf[i] = (unsigned char)(seed >> 24);
        if (!allow_nul && buf[i] == 0)
            buf[i] = 'f';
    }
}

static void binary_garbage_fails_cleanly(void **state)
{
    temp_dir *fx = *state;
    static unsigned char buf[8192];
    fill_garbage(buf, sizeof buf, 12345u, 1);
    temp_dir_write(fx, "garbage.obj", buf, sizeof buf);
    assert_load_fails(fx->path, ": not an OBJ text file: byte 117 is a NUL, so it holds binary data");
    /* without NUL bytes the text goes through both parsers; any clean outcome will do */
    for (uint32_t seed = 1; seed <= 20; seed++) {
        fill_garbage(buf, sizeof buf, seed, 0);
        temp_dir_write(fx, "garbage2.obj", buf, sizeof buf);
        vkrt_model m;
        vkrt_error err = {{0}};
        if (vkrt_obj_load(fx->path, &m, &err))
            vkrt_model_free(&m);
        else
            assert_int_equal(strncmp(err.msg, fx->path, strlen(fx->path)), 0);
    }
    /* "v 0 0 0\n" in UTF-16LE with a BOM, and big-endian without one */
    const char le[] = "\xff\xfev\0 \0000\0 \0000\0 \0000\0\n\0";
    temp_dir_write(fx, "utf16le.obj", le, sizeof le - 1);
    assert_load_fails(fx->path, ": looks like UTF-16 text; save it as UTF-8");
    const char be[] = "\0v\0 \0000\0 \0000\0 \0000\0\n\0f\0 \0001\0 \0001\0 \0001\0\n";
    temp_dir_write(fx, "utf16be.obj", be, sizeof be - 1);
    assert_load_fails(fx->path, ": looks like UTF-16 text");
}

static void utf8_bom_is_skipped(void **state)
{
    vkrt_model m = load_ok(
        temp_dir_write_text(*state, "bom.obj", "\xef\xbb\xbfv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"));
    assert_int_equal(m.triangle_count, 1);
    vkrt_model_free(&m);
}

/* Every line of warnings reads "<a file under dir>[:LINE]: warning: ...", in vkrt's words: none of
 * tinyobjloader's phrases ("Failed to load", "[ '", "Use default") gets through. */
static void assert_warning_lines(const char *warnings, const char *dir)
{
    const char *line = warnings;
    while (line && *line) {
        size_t n = strcspn(line, "\n");
        char text[1100];
        snprintf(text, sizeof text, "%.*s", (int)n, line);
        if (strncmp(text, dir, strlen(dir)) != 0 || !strstr(text, ": warning: ") ||
            strstr(text, "Failed") || strstr(text, "[ '") || strstr(text, "Use default"))
            fail_msg("warning \"%s\" does not read \"%s...: warning: ...\" in vkrt's words", text, dir);
        line += n + (line[n] == '\n');
    }
}

/* What vkrt_model_print_warnings writes, in a malloc'd string. */
static char *printed_warnings(const vkrt_model *m, bool verbose)
{
    char *out = NULL;
    size_t size = 0;
    FILE *f = open_memstream(&out, &size);
    assert_non_null(f);
    vkrt_model_print_warnings(m, "vkrt: ", verbose, f);
    fclose(f);
    return out;
}

static void missing_mtl_is_a_warning(void **state)
{
    temp_dir *fx = *state;
    const char *text = "mtllib nothere.mtl\nusemtl red\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    vkrt_model m = load_ok(temp_dir_write_text(fx, "nomtl.obj", text));
    assert_int_equal(m.triangle_count, 1);
    assert_int_equal(m.meshes[0].material[0], -1);
    assert_int_equal(m.material_count, 0);
    /* one line, at the mtllib line: not also tinyobjloader's "Failed to load material file(s)"
     * nor a warning for the usemtl the missing file explains */
    char want[1200];
    snprintf(want, sizeof want,
             "%s/nomtl.obj:1: warning: material library %s/nothere.mtl not found; faces using its "
             "materials get the default material",
             fx->dir, fx->dir);
    assert_string_equal(m.warnings, want);
    assert_string_equal(m.warnings_all, want);
    vkrt_model_free(&m);
    assert_null(m.warnings_all);
}

/* tinyobjloader's warnings in vkrt's words, repeated ones folded into one line with a count and
 * the first names, and all of them, one a line, in warnings_all (what --verbose prints). */
static void warnings_are_ours_and_folded(void **state)
{
    temp_dir *fx = *state;
    char mtl[600] = "";
    for (int i = 0; i < 5; i++) /* Tr after d: lines 3, 6, 9, 12, 15 */
        snprintf(mtl + strlen(mtl), sizeof mtl - strlen(mtl), "newmtl m%d\nd 0.5\nTr 0.5\n", i);
    temp_dir_write_text(fx, "d.mtl", mtl);
    const char *text = "mtllib d.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"
                       "usemtl m0\nf 1 2 3\n"      /* 5, 6 */
                       "usemtl nosuch\nf 1 2 3\n"  /* 7, 8 */
                       "usemtl nosuch\nf 1 3 2\n"  /* 9, 10: said once */
                       "f 1 2\nf 1\n"              /* 11, 12: dropped */
                       "usemtl other\nf 2 3 1\n"; /* 13, 14 */
    vkrt_model m = load_ok(temp_dir_write_text(fx, "w.obj", text));
    assert_int_equal(m.triangle_count, 4);
    char want[2000];
    snprintf(want, sizeof want,
             "%s/d.mtl: warning: 5 materials define both d and Tr; d is used (m0, m1, m2, ...)\n"
             "%s/w.obj: warning: 2 usemtl names have no material in %s/d.mtl; the default "
             "material is used (nosuch, other)\n"
             "%s/w.obj: warning: 2 faces of fewer than 3 corners ignored (lines 11, 12)",
             fx->dir, fx->dir, fx->dir, fx->dir);
    assert_string_equal(m.warnings, want);
    assert_warning_lines(m.warnings, fx->dir);
    assert_warning_lines(m.warnings_all, fx->dir);
    snprintf(want, sizeof want,
             "%s/d.mtl:3: warning: material 'm0' defines both d and Tr; d is used\n", fx->dir);
    assert_non_null(strstr(m.warnings_all, want));
    snprintf(want, sizeof want,
             "%s/d.mtl:15: warning: material 'm4' defines both d and Tr; d is used\n", fx->dir);
    assert_non_null(strstr(m.warnings_all, want));
    snprintf(want, sizeof want,
             "%s/w.obj:7: warning: usemtl nosuch: no material of that name in %s/d.mtl; the "
             "default material is used\n",
             fx->dir, fx->dir);
    assert_non_null(strstr(m.warnings_all, want));
    snprintf(want, sizeof want, "%s/w.obj:12: warning: face of fewer than 3 corners ignored", fx->dir);
    assert_non_null(strstr(m.warnings_all, want));

    /* A file cut short just after an f: the bare keyword on its last line is a face too. */
    vkrt_model cut = load_ok(temp_dir_write_text(fx, "cut.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf"));
    assert_int_equal(cut.triangle_count, 1);
    snprintf(want, sizeof want, "%s/cut.obj:5: warning: face of fewer than 3 corners ignored", fx->dir);
    assert_string_equal(cut.warnings, want);
    vkrt_model_free(&cut);

    /* printed: every line after the prefix; verbose prints all nine */
    char *folded = printed_warnings(&m, false), *all = printed_warnings(&m, true);
    snprintf(want, sizeof want, "vkrt: %s/d.mtl: warning: 5 materials", fx->dir);
    assert_int_equal(strncmp(folded, want, strlen(want)), 0);
    int lines = 0;
    for (const char *c = all; *c; c++)
        lines += *c == '\n';
    assert_int_equal(lines, 9);
    snprintf(want, sizeof want, "\nvkrt: %s/w.obj:13: warning: usemtl other", fx->dir);
    assert_non_null(strstr(all, want));
    free(folded);
    free(all);
    vkrt_model_free(&m);

    /* a file without warnings prints nothing */
    m = load_ok(temp_dir_write_text(fx, "quad.obj", QUAD));
    assert_null(m.warnings_all);
    char *none = printed_warnings(&m, true);
    assert_string_equal(none, "");
    free(none);
    vkrt_model_free(&m);
}

/* "newmtl  RearLights" (two blanks, as a real exporter wrote it) is the material `usemtl
 * RearLights` names: material names are matched trimmed, as other OBJ readers do. */
static void material_names_are_trimmed(void **state)
{
    temp_dir *fx = *state;
    temp_dir_write_text(fx, "car.mtl", "newmtl  RearLights\nKd 1 0 0\nnewmtl \t Body\t \nKd 0 0 1\n");
    const char *text = "mtllib car.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"
                       "usemtl RearLights\nf 1 2 3\nusemtl Body\nf 1 3 2\n";
    vkrt_model m = load_ok(temp_dir_write_text(fx, "car.obj", text));
    assert_string_equal(m.warnings, "");
    assert_true(m.meshes[0].material[0] >= 0 && m.meshes[0].material[1] >= 0);
    assert_string_equal(m.materials[m.meshes[0].material[0]].name, "RearLights");
    assert_vec3(m.materials[m.meshes[0].material[0]].base_colour, 1, 0, 0);
    assert_string_equal(m.materials[m.meshes[0].material[1]].name, "Body");
    assert_vec3(m.materials[m.meshes[0].material[1]].base_colour, 0, 0, 1);
    vkrt_model_free(&m);
}

/* The .mtl's fields in the model's record: Kd, Ks, Ke, Ns, Ni and d as base colour, specular,
 * emission, exponent, ior and opacity; illum 5 the mirror family; map_Kd an sRGB colour texture
 * with its line, sampled as the kernels do (repeat, bilinear); absent fields the defaults of
 * mtl.h, and Ns 0 roughness 1 (vkrt_ns_roughness). */
static void mtl_fields_are_parsed(void **state)
{
    temp_dir *fx = *state;
    temp_dir_write_text(fx, "tex.png", "not really a png");
    temp_dir_write_text(fx, "m.mtl",
               "newmtl shiny\r\n"
               "Kd 0.1 0.2 0.3\r\nKs 0.4 0.5 0.6\r\nKe 7 8 9\r\nNs 250\r\nNi 1.45\r\nd 0.5\r\nillum 5\r\n"
               "map_Kd tex.png\r\n"
               "\r\nnewmtl plain\r\n");
    const char *text = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl plain\nf 1 2 3\nusemtl shiny\nf 1 3 2\n";
    vkrt_model m = load_ok(temp_dir_write_text(fx, "mtl.obj", text));
    assert_int_equal(m.triangle_count, 2);
    assert_int_equal(m.material_count, 2);
    const vkrt_material *shiny = &m.materials[m.meshes[0].material[1]];
    const vkrt_material *plain = &m.materials[m.meshes[0].material[0]];
    assert_string_equal(shiny->name, "shiny");
    assert_int_equal(shiny->bsdf, VKRT_BSDF_MIRROR);
    assert_vec3(shiny->base_colour, 0.1f, 0.2f, 0.3f);
    assert_vec3(shiny->specular, 0.4f, 0.5f, 0.6f);
    assert_vec3(shiny->emission, 7, 8, 9);
    assert_close(shiny->specular_exponent, 250);
    assert_close(shiny->roughness, vkrt_ns_roughness(250));
    assert_close(shiny->ior, 1.45f);
    assert_close(shiny->opacity, 0.5f);
    char want[600];
    snprintf(want, sizeof want, "%s/tex.png", fx->dir);
    const vkrt_texture_ref *colour = &shiny->maps[VKRT_MAP_BASE_COLOUR];
    assert_string_equal(colour->path, want);
    assert_int_equal(colour->space, VKRT_TEXTURE_COLOUR);
    assert_int_equal(colour->sampler.wrap_u, VKRT_WRAP_REPEAT);
    assert_int_equal(colour->sampler.wrap_v, VKRT_WRAP_REPEAT);
    assert_int_equal(colour->sampler.filter, VKRT_FILTER_LINEAR);
    /* absent fields take the defaults documented in mtl.h */
    assert_string_equal(plain->name, "plain");
    assert_int_equal(plain->bsdf, VKRT_BSDF_DIFFUSE);
    assert_vec3(plain->base_colour, 0.8f, 0.8f, 0.8f);
    assert_vec3(plain->specular, 0, 0, 0);
    assert_vec3(plain->emission, 0, 0, 0);
    assert_close(plain->specular_exponent, 0);
    assert_close(plain->roughness, 1);
    assert_close(plain->ior, 1);
    assert_close(plain->opacity, 1);
    assert_vec3(plain->transmission_filter, 1, 1, 1);
    for (int k = 0; k < VKRT_MAP_COUNT; k++)
        assert_null(plain->maps[k].path);
    snprintf(want, sizeof want, "%s/m.mtl", fx->dir);
    assert_string_equal(shiny->file, want);
    assert_int_equal(colour->line, 9);
    vkrt_model_free(&m);
}

/* The PBR extension as Blender's exporter writes it, in the record: Pr as roughness (a map_Pr,
 * a data texture with its line, replaces the number by 1; without Pr the roughness comes from Ns),
 * Pm as metallic, the clear coat Pc/Pcr as coat Pc / 4 and its roughness (a Pc above 0 alone
 * makes a material principled; Pc 0 does not), the sheen Ps and map_Ps (either alone makes a
 * material principled, Ps 0 does not; on a mirror or glass, which have no sheen, the loader warns
 * at the Ps line, and glass stays the smooth dielectric). */
static void mtl_pbr_fields_are_parsed(void **state)
{
    temp_dir *fx = *state;
    temp_dir_write_text(fx, "m.mtl",
                        "newmtl metal\nKd 0.9 0.6 0.2\nPr 0.25\nPm 1\nmap_Pr rough.png\n"
                        "newmtl coated\nKd 0.5 0.5 0.5\nPm 0.5\nPc 1\nPcr 0.1\nPs 0.3\n"
                        "newmtl old\nKs 0.5 0.5 0.5\nNs 30\nPc 0\n"
                        "newmtl varnish\nKd 0.5 0.5 0.5\nPc 2\nPcr 0.3\n"
                        "newmtl chrome\nKs 1 1 1\nillum 3\nPc 1\n"
                        "newmtl velvet\nKd 0.3 0 0\nPs 0.75\n"              /* 24-26 */
                        "newmtl cloth\nKd 0.3 0 0\nmap_Ps sheen.png\nPs 0\n" /* 27-30 */
                        "newmtl matte\nKd 0.3 0 0\nPs 0\n"                  /* 31-33 */
                        "newmtl bottle\nNi 1.5\nillum 7\nKs 1 1 1\nPs 1\n"  /* 34-38 */
                        "newmtl frosted\nNi 1.4\nillum 4\nPr 0.3\n");      /* 39-42 */
    const char *text = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl metal\nf 1 2 3\n"
                       "usemtl coated\nf 1 3 2\nusemtl old\nf 2 1 3\nusemtl varnish\nf 3 2 1\n"
                       "usemtl velvet\nf 1 2 3\nusemtl cloth\nf 1 2 3\nusemtl matte\nf 1 2 3\n"
                       "usemtl bottle\nf 1 2 3\nusemtl frosted\nf 1 2 3\n";
    vkrt_model m = load_ok(temp_dir_write_text(fx, "pbr.obj", text));
    const vkrt_material *metal = &m.materials[m.meshes[0].material[0]];
    const vkrt_material *coated = &m.materials[m.meshes[0].material[1]];
    const vkrt_material *old = &m.materials[m.meshes[0].material[2]];
    const vkrt_material *varnish = &m.materials[m.meshes[0].material[3]];
    assert_int_equal(metal->bsdf, VKRT_BSDF_PRINCIPLED);
    assert_close(metal->roughness, 1); /* map_Pr replaces Pr 0.25 */
    assert_close(metal->metallic, 1);
    char want[600];
    snprintf(want, sizeof want, "%s/rough.png", fx->dir);
    assert_string_equal(metal->maps[VKRT_MAP_ROUGHNESS].path, want);
    assert_int_equal(metal->maps[VKRT_MAP_ROUGHNESS].line, 5);
    assert_int_equal(metal->maps[VKRT_MAP_ROUGHNESS].space, VKRT_TEXTURE_DATA);
    assert_null(metal->maps[VKRT_MAP_METALLIC].path);
    assert_int_equal(coated->bsdf, VKRT_BSDF_PRINCIPLED);
    assert_close(coated->roughness, vkrt_ns_roughness(0)); /* no Pr: from Ns */
    assert_close(coated->metallic, 0.5f);
    assert_close(coated->coat, 0.25f);
    assert_close(coated->coat_roughness, 0.1f);
    assert_int_equal(old->bsdf, VKRT_BSDF_GLOSSY_PHONG);
    assert_close(old->roughness, vkrt_ns_roughness(30));
    assert_int_equal(varnish->bsdf, VKRT_BSDF_PRINCIPLED);
    assert_close(varnish->coat, 0.5f);
    assert_close(varnish->coat_roughness, 0.3f);
    assert_close(coated->sheen, 0.3f);
    assert_null(strstr(m.warnings, "'coated'"));
    assert_null(strstr(m.warnings, "'varnish'"));
    const vkrt_material *velvet = &m.materials[m.meshes[0].material[4]];
    const vkrt_material *cloth = &m.materials[m.meshes[0].material[5]];
    const vkrt_material *matte = &m.materials[m.meshes[0].material[6]];
    const vkrt_material *bottle = &m.materials[m.meshes[0].material[7]];
    const vkrt_material *frosted = &m.materials[m.meshes[0].material[8]];
    assert_int_equal(velvet->bsdf, VKRT_BSDF_PRINCIPLED);
    assert_close(velvet->sheen, 0.75f);
    assert_null(velvet->maps[VKRT_MAP_SHEEN].path);
    assert_int_equal(cloth->bsdf, VKRT_BSDF_PRINCIPLED);
    snprintf(want, sizeof want, "%s/sheen.png", fx->dir);
    assert_string_equal(cloth->maps[VKRT_MAP_SHEEN].path, want);
    assert_int_equal(cloth->maps[VKRT_MAP_SHEEN].line, 29);
    assert_close(cloth->sheen, 1); /* map_Ps replaces Ps 0 */
    assert_int_equal(matte->bsdf, VKRT_BSDF_DIFFUSE);
    assert_close(matte->sheen, 0);
    assert_int_equal(bottle->bsdf, VKRT_BSDF_DIELECTRIC);
    assert_close(bottle->ior, 1.5f);
    assert_close(bottle->sheen, 1);
    assert_int_equal(frosted->bsdf, VKRT_BSDF_ROUGH_DIELECTRIC);
    assert_close(frosted->ior, 1.4f);
    assert_close(frosted->roughness, 0.3f);
    assert_non_null(strstr(m.warnings, "m.mtl:38: warning: material 'bottle' has a sheen (Ps, "
                                       "map_Ps) but illum 3 to 7"));
    assert_non_null(strstr(m.warnings, "m.mtl:23: warning: material 'chrome' has a clear coat (Pc) "
                                       "but illum 3 or 5"));
    vkrt_model_free(&m);
}

/* The surface maps as exporters write them, in the record's detail and emission slots: norm (a
 * normal map) wins over map_Bump or bump, whose image decides what it is; the -bm of the map
 * used is the detail scale; map_Ke is a colour texture, and the emission itself (1 1 1) where
 * no Ke is given. */
static void mtl_surface_maps_are_parsed(void **state)
{
    temp_dir *fx = *state;
    temp_dir_write_text(fx, "m.mtl",
                        "newmtl blender\n"                    /* 1 */
                        "Kd 0.8 0.8 0.8\n"                    /* 2 */
                        "map_Bump -bm 0.5 maps\\normal.png\n" /* 3 */
                        "newmtl both\n"                       /* 4 */
                        "bump -bm 2 height.png\n"             /* 5 */
                        "norm -bm 0.25 n.png\n"               /* 6 */
                        "Ke 2 2 2\n"                          /* 7 */
                        "map_Ke glow.png\n"                   /* 8 */
                        "newmtl glow\n"                       /* 9 */
                        "map_Ke glow.png\n");                 /* 10 */
    const char *text = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl blender\nf 1 2 3\n"
                       "usemtl both\nf 1 3 2\nusemtl glow\nf 2 1 3\n";
    vkrt_model m = load_ok(temp_dir_write_text(fx, "maps.obj", text));
    const vkrt_material *blender = &m.materials[m.meshes[0].material[0]];
    const vkrt_material *both = &m.materials[m.meshes[0].material[1]];
    const vkrt_material *glow = &m.materials[m.meshes[0].material[2]];
    char want[600];
    snprintf(want, sizeof want, "%s/maps/normal.png", fx->dir);
    assert_string_equal(blender->maps[VKRT_MAP_DETAIL].path, want);
    assert_int_equal(blender->maps[VKRT_MAP_DETAIL].line, 3);
    assert_int_equal(blender->maps[VKRT_MAP_DETAIL].space, VKRT_TEXTURE_DATA);
    assert_int_equal(blender->detail_kind, VKRT_DETAIL_BY_IMAGE);
    assert_close(blender->detail_scale, 0.5f);
    assert_null(blender->maps[VKRT_MAP_EMISSION].path);
    snprintf(want, sizeof want, "%s/n.png", fx->dir);
    assert_string_equal(both->maps[VKRT_MAP_DETAIL].path, want);
    assert_int_equal(both->maps[VKRT_MAP_DETAIL].line, 6);
    assert_int_equal(both->detail_kind, VKRT_DETAIL_NORMAL);
    assert_close(both->detail_scale, 0.25f);
    snprintf(want, sizeof want, "%s/glow.png", fx->dir);
    assert_string_equal(both->maps[VKRT_MAP_EMISSION].path, want);
    assert_int_equal(both->maps[VKRT_MAP_EMISSION].line, 8);
    assert_int_equal(both->maps[VKRT_MAP_EMISSION].space, VKRT_TEXTURE_COLOUR);
    assert_vec3(both->emission, 2, 2, 2);
    assert_string_equal(glow->maps[VKRT_MAP_EMISSION].path, want);
    assert_vec3(glow->emission, 1, 1, 1); /* no Ke: the map is the emission */
    assert_close(glow->detail_scale, 1);
    vkrt_model_free(&m);
}

/* One .mtl block `newmtl m` with `line` as its line 2, read through an OBJ whose one face uses it. */
static const char *write_mtl_case(temp_dir *fx, const char *line)
{
    char mtl[300];
    snprintf(mtl, sizeof mtl, "newmtl m\n%s\n", line);
    temp_dir_write_text(fx, "n.mtl", mtl);
    return temp_dir_write_text(fx, "n.obj", "mtllib n.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n");
}

/* Every number an .mtl gives that vkrt reads is finite and in the range its meaning allows, or an
 * error naming the .mtl's line (tinyobjloader reads "nan", "abc" and "inf" as 0, 1e39 as inf, and
 * keeps a negative colour); a value that only needs clamping is a warning that says what was used.
 * The one-number colours are grey, as the MTL format says (tinyobjloader reads "Kd 0.5" as
 * 0.5 0 0). */
static void mtl_numbers_are_checked(void **state)
{
    temp_dir *fx = *state;
    static const struct {
        const char *line, *error;
    } errors[] = {
        {"Ke -1 -1 -1", "material 'm': Ke -1 is negative (an emitted radiance is 0 or more)"},
        {"Kd -0.5 0.5 0.5", "material 'm': Kd -0.5 is negative (a reflectance lies in [0, 1])"},
        {"Ke nan 1 1", "material 'm': Ke nan is not finite"},
        {"Ke inf 1 1", "material 'm': Ke inf is not finite"},
        {"Ke 1e39 1 1", "material 'm': Ke 1e39 is not finite (too large for a float)"},
        {"Kd abc 1 1", "material 'm': Kd 'abc' is not a number"},
        {"Kd nan 0.5 0.5", "material 'm': Kd nan is not finite"},
        {"Kd 0.5 0.5 0.5x", "material 'm': Kd '0.5x' is not a number"},
        {"Kd 0.5 0.5", "material 'm': Kd needs 1 or 3 numbers, found 2"},
        {"Kd spectral ident.rfl", "material 'm': Kd spectral is not supported; write Kd r g b"},
        {"Ni -1.5", "material 'm': Ni -1.5 is negative (an index of refraction is above 0, or 0 for the default)"},
        {"Ns -10", "material 'm': Ns -10 is negative"},
        {"Tf 0.5 -0.1 1", "material 'm': Tf -0.1 is negative"},
        {"d 1.#IND", "material 'm': d 1.#IND is not finite"},
        {"Pr 1e-2147483649", "material 'm': Pr 1e-2147483649 has an exponent of more than 9 digits"},
        {"illum 12", "material 'm': illum 12 is not an illumination model (0 to 10)"},
        {"illum 2.5", "material 'm': illum 2.5 is not an illumination model"},
        {"illum two", "material 'm': illum 'two' is not a number"},
    };
    for (size_t i = 0; i < sizeof errors / sizeof errors[0]; i++) {
        const char *obj = write_mtl_case(fx, errors[i].line);
        vkrt_model m;
        vkrt_error err = {{0}};
        assert_false(vkrt_obj_load(obj, &m, &err));
        char want[600];
        snprintf(want, sizeof want, "%s/n.mtl:2: %s", fx->dir, errors[i].error);
        if (strncmp(err.msg, want, strlen(want)) != 0)
            fail_msg("%s: error \"%s\" does not read \"%s...\"", errors[i].line, err.msg, want);
    }

    /* clamped, with a warning that says what was used */
    static const struct {
        const char *line, *warning;
        float kd, opacity, roughness, metallic;
    } clamped[] = {
        {"Pr 5", "Pr 5 is outside [0, 1] (used 1)", 0.8f, 1, 1, 0},
        {"Pm -1", "Pm -1 is outside [0, 1] (used 0)", 0.8f, 1, 1, 0},
        {"d -1", "d -1 is outside [0, 1] (used 0)", 0.8f, 0, 1, 0},
        {"d 1.5", "d 1.5 is outside [0, 1] (used 1)", 0.8f, 1, 1, 0},
        {"Tr 2", "Tr 2 is outside [0, 1] (used 1)", 0.8f, 0, 1, 0},
        {"Kd 1.5 0.5 0.5", "Kd 1.5 0.5 0.5 is outside [0, 1] (used 1 0.5 0.5)", 1, 1, 1, 0},
        {"Kd 0.5 0.5 0.5 1", "Kd has 4 numbers (used the first 3)", 0.5f, 1, 1, 0},
    };
    for (size_t i = 0; i < sizeof clamped / sizeof clamped[0]; i++) {
        vkrt_model m = load_ok(write_mtl_case(fx, clamped[i].line));
        char want[600];
        snprintf(want, sizeof want, "%s/n.mtl:2: warning: material 'm': %s", fx->dir, clamped[i].warning);
        if (strcmp(m.warnings, want) != 0)
            fail_msg("%s: warning \"%s\", want \"%s\"", clamped[i].line, m.warnings, want);
        assert_close(m.materials[0].base_colour[0], clamped[i].kd);
        assert_close(m.materials[0].opacity, clamped[i].opacity);
        if (strncmp(clamped[i].line, "Pr", 2) == 0 || strncmp(clamped[i].line, "Pm", 2) == 0) {
            assert_close(m.materials[0].roughness, clamped[i].roughness);
            assert_close(m.materials[0].metallic, clamped[i].metallic);
        }
        vkrt_model_free(&m);
    }

    /* the one-number forms are grey; in range, comments and the real files' Ni 0, Ns 0 and d 0
     * load without a word */
    temp_dir_write_text(fx, "grey.mtl",
                        "newmtl g\nKd 0.5\nKs 0.25\nKe 2\nTf 0.75\nKa 0.1\nNi 0\nNs 0\nd 0\n"
                        "newmtl c\nKa 0.63 0.065 0.05 # Red\nKd 0.25 0.5 1\nillum 2.0\n");
    vkrt_model m = load_ok(temp_dir_write_text(
        fx, "grey.obj", "mtllib grey.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl g\nf 1 2 3\nusemtl c\nf 1 3 2\n"));
    assert_string_equal(m.warnings, "");
    const vkrt_material *g = &m.materials[m.meshes[0].material[0]];
    assert_vec3(g->base_colour, 0.5f, 0.5f, 0.5f);
    assert_vec3(g->specular, 0.25f, 0.25f, 0.25f);
    assert_vec3(g->emission, 2, 2, 2);
    assert_vec3(g->transmission_filter, 0.75f, 0.75f, 0.75f);
    assert_close(g->ior, 0);
    assert_close(g->opacity, 0);
    assert_vec3(m.materials[m.meshes[0].material[1]].base_colour, 0.25f, 0.5f, 1);
    vkrt_model_free(&m);

    /* clamped numbers of one file fold into one line with their lines */
    temp_dir_write_text(fx, "many.mtl", "newmtl a\nPr 2\nnewmtl b\nPm 3\nnewmtl c\nd 4\nPs 5\n");
    m = load_ok(temp_dir_write_text(fx, "many.obj", "mtllib many.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n"));
    char want[600];
    snprintf(want, sizeof want, "%s/many.mtl: warning: 4 numbers changed to fit their range (lines 2, 4, 6, ...)",
             fx->dir);
    assert_string_equal(m.warnings, want);
    vkrt_model_free(&m);
}

/* The fields texture errors need (which .mtl, which line), map_d (a coverage texture) and Tf,
 * over two .mtl files. */
static void mtl_texture_lines_and_tf(void **state)
{
    temp_dir *fx = *state;
    char m_mtl[600], other_mtl[600], want[700];
    temp_dir_write_text(fx, "m.mtl",
                        "# map_Kd commented.png\r\n"     /* 1 */
                        "newmtl glass\r\n"               /* 2 */
                        "  Tf 0.5 0.25 1\r\n"            /* 3 */
                        "\tmap_Kd first.png\r\n"         /* 4 */
                        "map_d maps\\alpha.png\r\n"      /* 5: Windows separator */
                        "\r\n"                           /* 6 */
                        "map_Kd -s 2 2 1 second.png\r\n" /* 7: the last one wins */
                        "newmtl plain\r\n"               /* 8 */
                        "Kd 0.5 0.5 0.5\r\n");           /* 9 */
    snprintf(m_mtl, sizeof m_mtl, "%s", fx->path);
    temp_dir_write_text(fx, "other.mtl",
                        "newmtl leaves\n"       /* 1 */
                        "Kt 0.1 0.2 0.3\n"      /* 2: tinyobjloader reads Kt as Tf */
                        "map_d leaves_a.png\n"); /* 3 */
    snprintf(other_mtl, sizeof other_mtl, "%s", fx->path);
    const char *text = "mtllib m.mtl\nmtllib other.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"
                       "usemtl glass\nf 1 2 3\nusemtl plain\nf 1 3 2\nusemtl leaves\nf 2 1 3\n";
    vkrt_model m = load_ok(temp_dir_write_text(fx, "tex.obj", text));
    assert_int_equal(m.material_count, 3);
    const vkrt_material *glass = &m.materials[m.meshes[0].material[0]];
    const vkrt_material *plain = &m.materials[m.meshes[0].material[1]];
    const vkrt_material *leaves = &m.materials[m.meshes[0].material[2]];
    assert_string_equal(glass->name, "glass");
    assert_string_equal(glass->file, m_mtl);
    assert_vec3(glass->transmission_filter, 0.5f, 0.25f, 1.0f);
    snprintf(want, sizeof want, "%s/second.png", fx->dir);
    assert_string_equal(glass->maps[VKRT_MAP_BASE_COLOUR].path, want);
    assert_int_equal(glass->maps[VKRT_MAP_BASE_COLOUR].line, 7);
    snprintf(want, sizeof want, "%s/maps/alpha.png", fx->dir);
    assert_string_equal(glass->maps[VKRT_MAP_COVERAGE].path, want);
    assert_int_equal(glass->maps[VKRT_MAP_COVERAGE].line, 5);
    assert_int_equal(glass->maps[VKRT_MAP_COVERAGE].space, VKRT_TEXTURE_ALPHA);

    assert_string_equal(plain->file, m_mtl);
    assert_vec3(plain->transmission_filter, 1, 1, 1); /* absent: mtl.h's default, not tinyobjloader's 0 */
    assert_null(plain->maps[VKRT_MAP_BASE_COLOUR].path);
    assert_null(plain->maps[VKRT_MAP_COVERAGE].path);
    assert_int_equal(plain->maps[VKRT_MAP_BASE_COLOUR].line, 0);
    assert_int_equal(plain->maps[VKRT_MAP_COVERAGE].line, 0);

    assert_string_equal(leaves->file, other_mtl);
    assert_vec3(leaves->transmission_filter, 0.1f, 0.2f, 0.3f);
    assert_null(leaves->maps[VKRT_MAP_BASE_COLOUR].path);
    snprintf(want, sizeof want, "%s/leaves_a.png", fx->dir);
    assert_string_equal(leaves->maps[VKRT_MAP_COVERAGE].path, want);
    assert_int_equal(leaves->maps[VKRT_MAP_COVERAGE].line, 3);
    vkrt_model_free(&m);


    /* without .mtl files (vkrt_obj_parse with no base folder) nothing of the kind is set */
    vkrt_error err = {{0}};
    assert_true(vkrt_obj_parse(text, strlen(text), "mem.obj", NULL, &m, &err));
    assert_int_equal(m.material_count, 0);
    vkrt_model_free(&m);
}

/* ------------------------------------------------------------------------ shared scenes */

typedef struct path_list {
    char **items;
    size_t count, cap;
} path_list;

static void path_list_add(path_list *l, const char *p)
{
    if (l->count == l->cap) {
        l->cap = l->cap ? 2 * l->cap : 64;
        l->items = realloc(l->items, l->cap * sizeof *l->items);
        assert_non_null(l->items);
    }
    l->items[l->count] = strdup(p);
    assert_non_null(l->items[l->count]);
    l->count++;
}

static void path_list_free(path_list *l)
{
    for (size_t i = 0; i < l->count; i++)
        free(l->items[i]);
    free(l->items);
}

static int ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), k = strlen(suffix);
    return n >= k && strcmp(s + n - k, suffix) == 0;
}

static void find_objs(const char *dir, path_list *out)
{
    DIR *d = opendir(dir);
    assert_non_null(d);
    struct dirent *e;
    while ((e = readdir(d))) {
        if (e->d_name[0] == '.')
            continue;
        char p[1024];
        snprintf(p, sizeof p, "%s/%s", dir, e->d_name);
        struct stat st;
        if (stat(p, &st) != 0)
            continue;
        if (S_ISDIR(st.st_mode))
            find_objs(p, out);
        else if (ends_with(p, ".obj"))
            path_list_add(out, p);
    }
    closedir(d);
}

/* From SOURCE.txt: "  models/x.obj  (N bytes)" is followed by "    triangles (fan): N".
 * Returns -1 when the file is not listed. */
static long expected_triangles(const char *suite, const char *relative)
{
    char source[1024], line[2048];
    snprintf(source, sizeof source, "%s/SOURCE.txt", suite);
    FILE *f = fopen(source, "r");
    assert_non_null(f);
    long found = -1;
    int in_entry = 0;
    while (found < 0 && fgets(line, sizeof line, f)) {
        const char *mark = strstr(line, ".obj  (");
        if (line[0] == ' ' && line[1] == ' ' && line[2] != ' ' && mark) {
            size_t n = (size_t)(mark + 4 - (line + 2));
            in_entry = n == strlen(relative) && strncmp(line + 2, relative, n) == 0;
        } else if (in_entry && strstr(line, "triangles (fan): ")) {
            found = strtol(strstr(line, "): ") + 3, NULL, 10);
        }
    }
    fclose(f);
    return found;
}

/* Files that must fail, and why; every other file must load with SOURCE.txt's count or fail
 * for a reason in this list. */
typedef struct expected_failure {
    const char *file;    /* path relative to the suite */
    const char *message; /* part of the error */
} expected_failure;

static const expected_failure EXPECTED_FAILURES[] = {
    {"models/test-nan.obj", "vertex coordinate is not finite"},            /* nan/inf/1.#IND */
    {"models/invalid-face-definition.obj", "no triangles"},                /* faces of 1 and 2 corners */
    {"models/invalid-relative-texture-index.obj", "out of range"},         /* no v records at all */
    {"models/invalid-relative-vertex-index.obj", "out of range"},          /* f -4 -3 -2 without v */
    {"models/issue-140-zero-face-idx.obj", "face index 0 is not valid"},   /* index 0 is invalid OBJ */
    {"models/issue-356-leading-spaces-newmtl.obj", "no triangles"},        /* only a usemtl */
    {"models/line-prim.obj", "no triangles"},                              /* lines only */
    {"models/points-prim.obj", "no triangles"},                            /* points only */
    {"test/models/OBJ/box_UTF16BE.obj", "UTF-16"},                         /* UTF-16 with BOM */
    {"test/models/OBJ/number_formats.obj", "is not a number"},             /* "3.1+e2" */
    {"test/models/OBJ/point_cloud.obj", "no triangles"},
    {"test/models/OBJ/testline.obj", "no triangles"},
    {"test/models/OBJ/testpoints.obj", "no triangles"},
};

static const expected_failure *expected_failure_of(const char *relative)
{
    for (size_t i = 0; i < sizeof EXPECTED_FAILURES / sizeof EXPECTED_FAILURES[0]; i++)
        if (strcmp(EXPECTED_FAILURES[i].file, relative) == 0)
            return &EXPECTED_FAILURES[i];
    return NULL;
}

/* Loads one suite file; returns 1 if it loaded. */
static int check_suite_file(const char *suite, const char *path)
{
    const char *relative = path + strlen(suite) + 1;
    const expected_failure *xf = expected_failure_of(relative);
    vkrt_model m;
    vkrt_error err = {{0}};
    check_split_file(path);
    if (!vkrt_obj_load(path, &m, &err)) {
        if (strncmp(err.msg, path, strlen(path)) != 0)
            fail_msg("error for %s does not start with its path: %s", path, err.msg);
        if (!xf || !strstr(err.msg, xf->message))
            fail_msg("unexpected failure: %s", err.msg);
        printf("  error (expected): %s\n", err.msg);
        return 0;
    }
    if (xf)
        fail_msg("%s loaded but should fail with \"%s\"", path, xf->message);
    assert_warning_lines(m.warnings, suite);
    assert_warning_lines(m.warnings_all, suite);
    long want = expected_triangles(suite, relative);
    if (want < 0)
        fail_msg("%s is not listed in %s/SOURCE.txt", relative, suite);
    /* SOURCE.txt counts the fans' triangles; those of zero area are dropped, with a warning */
    const char *zero = m.warnings_all ? strstr(m.warnings_all, ": warning: ") : NULL;
    long dropped = 0;
    for (; zero; zero = strstr(zero + 1, ": warning: ")) {
        long n = strtol(zero + 11, NULL, 10);
        const char *rest = strchr(zero + 11, ' ');
        if (n > 0 && rest && (strncmp(rest, " triangles have zero area", 25) == 0 ||
                              strncmp(rest, " triangle has zero area", 23) == 0))
            dropped += n;
    }
    if ((long)m.triangle_count + dropped != want)
        fail_msg("%s: %u triangles and %ld of zero area, SOURCE.txt says %ld", path, m.triangle_count,
                 dropped, want);
    vkrt_model_free(&m);
    return 1;
}

static void run_suite(const char *name)
{
    const char *dir = shared_scenes_dir();
    if (!dir)
        skip();
    char suite[1024];
    snprintf(suite, sizeof suite, "%s/%s", dir, name);
    path_list files = {0};
    find_objs(suite, &files);
    assert_true(files.count > 0);
    int ok = 0;
    for (size_t i = 0; i < files.count; i++)
        ok += check_suite_file(suite, files.items[i]);
    printf("%s: %zu OBJ files, %d loaded ok, %zu errored\n", name, files.count, ok, files.count - (size_t)ok);
    path_list_free(&files);
}

static void tinyobjloader_suite(void **state)
{
    (void)state;
    run_suite("tinyobjloader-parser-tests");
}

static void assimp_suite(void **state)
{
    (void)state;
    run_suite("assimp-obj-parser-tests");
}

static int material_named(const vkrt_model *m, const char *name)
{
    for (uint32_t i = 0; i < m->material_count; i++)
        if (strcmp(m->materials[i].name, name) == 0)
            return (int)i;
    return -1;
}

static void cornell_box(void **state)
{
    (void)state;
    const char *dir = shared_scenes_dir();
    if (!dir)
        skip();
    char path[1024];
    snprintf(path, sizeof path, "%s/cornell-box/CornellBox-Original.obj", dir);
    vkrt_model m = load_ok(path);
    assert_int_equal(m.triangle_count, 36);
    const char *names[] = {"leftWall", "rightWall", "floor", "ceiling", "backWall", "shortBox", "tallBox", "light"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
        if (material_named(&m, names[i]) < 0)
            fail_msg("material %s missing", names[i]);
    const vkrt_material *light = &m.materials[material_named(&m, "light")];
    assert_vec3(light->emission, 17, 12, 4);
    assert_vec3(m.materials[material_named(&m, "leftWall")].base_colour, 0.63f, 0.065f, 0.05f);
    int light_triangles = 0;
    for (uint32_t t = 0; t < m.triangle_count; t++) {
        assert_true(m.meshes[0].material[t] >= 0);
        light_triangles += m.meshes[0].material[t] == material_named(&m, "light");
    }
    assert_int_equal(light_triangles, 2);
    vkrt_model_free(&m);
}

static void stanford_bunny(void **state)
{
    (void)state;
    const char *dir = shared_scenes_dir();
    if (!dir)
        skip();
    char path[1024];
    snprintf(path, sizeof path, "%s/stanford-bunny/stanford-bunny.obj", dir);
    vkrt_model m = load_ok(path);
    assert_int_equal(m.triangle_count, 69451);
    assert_bounds_of_positions(&m, path); /* its faces span two of the loader's write tasks */
    assert_null(m.meshes[0].normals);
    for (size_t i = 0; i < (size_t)m.triangle_count * 9; i++)
        assert_true(isfinite(m.meshes[0].positions[i]));
    vkrt_model_free(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        temp_dir_test(quad_becomes_fan),
        temp_dir_test(big_polygon_keeps_all_corners),
        temp_dir_test(negative_indices),
        temp_dir_test(geometric_normal_for_faces_without),
        temp_dir_test(unusable_file_normal_becomes_geometric),
        temp_dir_test(references_to_absent_normals_are_dropped),
        temp_dir_test(crlf_line_endings),
        temp_dir_test(non_finite_vertex_names_line),
        temp_dir_test(vertex_beyond_coordinate_limit_names_line),
        temp_dir_test(out_of_range_index_names_line),
        temp_dir_test(empty_and_triangle_free_files_fail),
        temp_dir_test(refused_face_index_names_line_and_index),
        temp_dir_test(binary_formats_are_named),
        temp_dir_test(binary_garbage_fails_cleanly),
        temp_dir_test(utf8_bom_is_skipped),
        temp_dir_test(missing_mtl_is_a_warning),
        temp_dir_test(warnings_are_ours_and_folded),
        temp_dir_test(material_names_are_trimmed),
        temp_dir_test(mtl_fields_are_parsed),
        temp_dir_test(mtl_numbers_are_checked),
        temp_dir_test(zero_area_faces),
        temp_dir_test(mtl_texture_lines_and_tf),
        temp_dir_test(mtl_pbr_fields_are_parsed),
        temp_dir_test(split_parse_matches_serial),
        temp_dir_test(mtl_surface_maps_are_parsed),
        cmocka_unit_test(tinyobjloader_suite),
        cmocka_unit_test(assimp_suite),
        cmocka_unit_test(cornell_box),
        cmocka_unit_test(stanford_bunny),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
