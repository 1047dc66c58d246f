/*
 * test_material_file.c: unit tests for src/scene/material_file.c, the material file parser.
 *
 * As for scene.cfg (test_config.c), the well-formed tests check every value that reaches a
 * vkrt_material_def, and the malformed tests check the message, line number first, and that a
 * failure leaves the struct zeroed (callers free nothing after a failure). The parser must never
 * touch the file system while parsing: paths name files that do not exist here.
 */
#define _POSIX_C_SOURCE 200809L

#include <setjmp.h> /* cmocka needs these before its header */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "scene/material_file.h"

/* ---------------------------------------------------------------------------------------------
 * Helpers
 * ------------------------------------------------------------------------------------------- */

static void assert_zeroed(const vkrt_material_file *file)
{
    static const vkrt_material_file zero;
    assert_memory_equal(file, &zero, sizeof zero);
}

static void parse_ok(const char *text, const char *base_dir, vkrt_material_file *file)
{
    vkrt_error err = {{0}};
    bool ok = vkrt_material_file_parse(text, strlen(text), "t.mat", base_dir, file, &err);
    if (!ok)
        print_error("unexpected failure: %s\n", err.msg);
    assert_true(ok);
}

/* Parses text of size bytes, expecting failure: the message must start with prefix and contain
 * phrase, and file (filled with garbage first) must come back zeroed. */
static void parse_fails(const char *text, size_t size, const char *prefix, const char *phrase)
{
    vkrt_material_file file;
    memset(&file, 0xAB, sizeof file);
    vkrt_error err = {{0}};
    bool ok = vkrt_material_file_parse(text, size, "t.mat", "base", &file, &err);
    if (ok) {
        print_error("parse of \"%s\" succeeded, expected \"%s ... %s\"\n", text, prefix, phrase);
        vkrt_material_file_free(&file);
        fail();
    }
    if (strncmp(err.msg, prefix, strlen(prefix)) != 0 || !strstr(err.msg, phrase)) {
        print_error("message \"%s\"\n   expected prefix \"%s\" and phrase \"%s\"\n", err.msg,
                    prefix, phrase);
        fail();
    }
    assert_zeroed(&file);
}

static void assert_params(const vkrt_material_def *d, uint32_t count, const float *want)
{
    assert_int_equal(d->param_count, count);
    for (uint32_t i = 0; i < VKRT_MATERIAL_FILE_MAX_PARAMS; i++)
        assert_float_equal(d->params[i], i < count ? want[i] : 0.0f, 0);
}

/* ---------------------------------------------------------------------------------------------
 * Well-formed files
 * ------------------------------------------------------------------------------------------- */

static void test_the_three_examples(void **state)
{
    (void)state;
    /* The examples of docs/material-file.md. */
    vkrt_material_file file;
    parse_ok("gold 0 gold.glsl 1.0 0.78 0.34\n"
             "floor 1 tiles.png @checker 0.9 0.9 0.9 0 0.1 0.1 0.1 0 8\n"
             "environment 1 sky.hdr sky.glsl 2.0\n",
             "scenes/demo", &file);
    assert_string_equal(file.path, "t.mat");
    assert_int_equal(file.count, 3);

    const vkrt_material_def *gold = &file.defs[0];
    assert_string_equal(gold->name, "gold");
    assert_int_equal(gold->texture_count, 0);
    assert_null(gold->textures);
    assert_string_equal(gold->shader, "scenes/demo/gold.glsl");
    assert_params(gold, 3, (const float[]){1.0f, 0.78f, 0.34f});
    assert_int_equal(gold->line, 1);

    const vkrt_material_def *floor_ = &file.defs[1];
    assert_string_equal(floor_->name, "floor");
    assert_int_equal(floor_->texture_count, 1);
    assert_string_equal(floor_->textures[0], "scenes/demo/tiles.png");
    assert_string_equal(floor_->shader, "@checker"); /* built-ins are kept as written */
    assert_params(floor_, 9, (const float[]){0.9f, 0.9f, 0.9f, 0, 0.1f, 0.1f, 0.1f, 0, 8});
    assert_int_equal(floor_->line, 2);

    const vkrt_material_def *env = vkrt_material_file_find(&file, "environment");
    assert_ptr_equal(env, &file.defs[2]);
    assert_string_equal(env->textures[0], "scenes/demo/sky.hdr");
    assert_string_equal(env->shader, "scenes/demo/sky.glsl");
    assert_params(env, 1, (const float[]){2.0f});
    assert_int_equal(env->line, 3);

    assert_ptr_equal(vkrt_material_file_find(&file, "gold"), gold);
    assert_null(vkrt_material_file_find(&file, "Gold"));
    assert_null(vkrt_material_file_find(&file, "silver"));
    assert_null(vkrt_material_file_find(NULL, "gold"));

    vkrt_material_file_free(&file);
    assert_zeroed(&file);
}

static void test_limits_accepted(void **state)
{
    (void)state;
    vkrt_material_file file;
    parse_ok("full 8 a.png b.png c.png d.png e.png f.png g.png h.png @phong "
             "0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 -1.5e38\n"
             "bare 0 @diffuse\n"
             "padded 03 a b c @x_1\n",
             NULL, &file);
    assert_int_equal(file.count, 3);
    const vkrt_material_def *d = &file.defs[0];
    assert_int_equal(d->texture_count, 8);
    assert_string_equal(d->textures[0], "a.png");
    assert_string_equal(d->textures[7], "h.png");
    assert_params(d, 16, (const float[]){0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14,
                                         -1.5e38f});
    assert_params(&file.defs[1], 0, NULL);
    assert_int_equal(file.defs[2].texture_count, 3);
    assert_string_equal(file.defs[2].shader, "@x_1");
    vkrt_material_file_free(&file);
}

static void test_names(void **state)
{
    (void)state;
    /* Whatever an OBJ's usemtl can name: any token without spaces or '#'. */
    vkrt_material_file file;
    parse_ok("Material.001 0 @diffuse\n"
             "wood-dark_2 0 @diffuse\n"
             "(null) 0 @diffuse\n"
             "mat:01/\xC3\xA9t\xC3\xA9 0 @diffuse\n"
             "1.0 0 @diffuse\n"
             "@diffuse 0 @diffuse\n",
             NULL, &file);
    assert_int_equal(file.count, 6);
    assert_non_null(vkrt_material_file_find(&file, "Material.001"));
    assert_non_null(vkrt_material_file_find(&file, "(null)"));
    assert_non_null(vkrt_material_file_find(&file, "mat:01/\xC3\xA9t\xC3\xA9"));
    assert_non_null(vkrt_material_file_find(&file, "1.0"));
    assert_string_equal(vkrt_material_file_find(&file, "@diffuse")->shader, "@diffuse");
    vkrt_material_file_free(&file);
}

static void test_path_resolution(void **state)
{
    (void)state;
    vkrt_material_file file;
    parse_ok("a 2 /abs/t.png ../tex/u.hdr sub/s.GLSL\n"
             "b 0 /abs/s.glsl\n"
             "c 1 o'brien.png @diffuse\n",
             "scenes/x/", &file);
    assert_string_equal(file.defs[0].textures[0], "/abs/t.png");            /* absolute: kept */
    assert_string_equal(file.defs[0].textures[1], "scenes/x/../tex/u.hdr"); /* no doubled '/' */
    assert_string_equal(file.defs[0].shader, "scenes/x/sub/s.GLSL");
    assert_string_equal(file.defs[1].shader, "/abs/s.glsl");
    assert_string_equal(file.defs[2].textures[0], "scenes/x/o'brien.png");
    vkrt_material_file_free(&file);

    parse_ok("a 1 t.png s.glsl\n", "", &file);
    assert_string_equal(file.defs[0].textures[0], "t.png");
    assert_string_equal(file.defs[0].shader, "s.glsl");
    vkrt_material_file_free(&file);

    parse_ok("a 1 t.png s.glsl\n", "/", &file);
    assert_string_equal(file.defs[0].textures[0], "/t.png");
    vkrt_material_file_free(&file);

    /* Unlike scene.cfg's output, nothing here is a frame pattern: '%' stays single. */
    parse_ok("a 1 t.png @diffuse\n", "100%done", &file);
    assert_string_equal(file.defs[0].textures[0], "100%done/t.png");
    vkrt_material_file_free(&file);
}

static void test_comments_crlf_and_blanks(void **state)
{
    (void)state;
    vkrt_material_file file;
    parse_ok("\xEF\xBB\xBF# materials for the demo\r\n"
             "\r\n"
             "   # indented comment\r\n"
             "\tgold\t0   gold.glsl 1 0.5 0.25   # trailing comment\r\n"
             "red 0 @diffuse 0.8#no space before the comment\r\n"
             "# café, and not UTF-8: \xE9\r\n"
             "   \t \r\n"
             "blue 0 @diffuse 0 0 1", /* no final newline */
             "d", &file);
    assert_int_equal(file.count, 3);
    assert_string_equal(file.defs[0].name, "gold");
    assert_string_equal(file.defs[0].shader, "d/gold.glsl");
    assert_params(&file.defs[0], 3, (const float[]){1, 0.5f, 0.25f});
    assert_int_equal(file.defs[0].line, 4);
    assert_params(&file.defs[1], 1, (const float[]){0.8f});
    assert_int_equal(file.defs[1].line, 5);
    assert_params(&file.defs[2], 3, (const float[]){0, 0, 1});
    assert_int_equal(file.defs[2].line, 8);
    vkrt_material_file_free(&file);
}

static void test_empty_files(void **state)
{
    (void)state;
    static const char *const texts[] = {"", "\n\n", "# only a comment\n", "\xEF\xBB\xBF",
                                        " \t\r\n"};
    for (size_t i = 0; i < sizeof texts / sizeof texts[0]; i++) {
        vkrt_material_file file;
        parse_ok(texts[i], "d", &file);
        assert_int_equal(file.count, 0);
        assert_null(file.defs);
        assert_string_equal(file.path, "t.mat");
        assert_null(vkrt_material_file_find(&file, "environment"));
        vkrt_material_file_free(&file);
    }
    /* No text at all, and no name: the default name is kept as the path. */
    vkrt_material_file file;
    vkrt_error err = {{0}};
    assert_true(vkrt_material_file_parse(NULL, 0, NULL, NULL, &file, &err));
    assert_string_equal(file.path, "material file");
    vkrt_material_file_free(&file);
}

static void test_many_materials(void **state)
{
    (void)state;
    /* Enough for the definitions and the duplicate check's table to grow several times. */
    enum { N = 3000 };
    size_t cap = (size_t)N * 48;
    char *text = malloc(cap);
    assert_non_null(text);
    size_t n = 0;
    for (int i = 0; i < N; i++)
        n += (size_t)snprintf(text + n, cap - n, "m%d 1 t%d.png @textured %d\n", i, i, i);
    vkrt_material_file file;
    parse_ok(text, NULL, &file);
    assert_int_equal(file.count, N);
    for (int i = 0; i < N; i += 97) {
        char name[16];
        snprintf(name, sizeof name, "m%d", i);
        const vkrt_material_def *d = vkrt_material_file_find(&file, name);
        assert_ptr_equal(d, &file.defs[i]);
        assert_int_equal(d->line, i + 1);
        assert_float_equal(d->params[0], (float)i, 0);
    }
    vkrt_material_file_free(&file);

    /* A duplicate at the end is still found, with the first definition's line. */
    n += (size_t)snprintf(text + n, cap - n, "m1234 0 @diffuse\n");
    parse_fails(text, n, "t.mat:3001: ", "material 'm1234' is defined twice (first on line 1235)");
    free(text);
}

static void test_free_zeroed_struct(void **state)
{
    (void)state;
    vkrt_material_file file;
    memset(&file, 0, sizeof file);
    vkrt_material_file_free(&file);
    vkrt_material_file_free(NULL);
    assert_zeroed(&file);
}

/* ---------------------------------------------------------------------------------------------
 * Malformed files
 * ------------------------------------------------------------------------------------------- */

typedef struct bad_case {
    const char *text;
    const char *prefix;
    const char *phrase;
} bad_case;

#define OK "ok 0 @diffuse\n"

static const bad_case bad_cases[] = {
    /* the texture count */
    {"gold\n", "t.mat:1: ", "expected a texture count (0..8) after the material name 'gold' (write: NAME TEXTURE-COUNT"},
    {OK "gold gold.glsl 1 0 0\n", "t.mat:2: ", "expected a texture count (0..8) after the material name 'gold', got 'gold.glsl'"},
    {"gold 9 a b c d e f g h i @diffuse\n", "t.mat:1: ", "expected a texture count (0..8) after the material name 'gold', got '9'"},
    {"gold -1 @diffuse\n", "t.mat:1: ", "got '-1'"},
    {"gold 1.0 a.png @diffuse\n", "t.mat:1: ", "got '1.0'"},
    {"gold 99999999999999999999 @diffuse\n", "t.mat:1: ", "got '99999999999999999999'"},
    /* the count disagrees with the files */
    {"floor 2 tiles.png @checker 1\n", "t.mat:1: ", "texture count says 2 but only 1 file name follows before the shader '@checker'"},
    {"floor 3 a.png b.png x.glsl\n", "t.mat:1: ", "texture count says 3 but only 2 file names follow before the shader 'x.glsl'"},
    {"floor 1 @checker 0.9\n", "t.mat:1: ", "texture count says 1 but no file name follows before the shader '@checker'"},
    {"floor 0 tiles.png @checker 0.9\n", "t.mat:1: ", "texture count says 0 but 1 file name follows before the shader '@checker'"},
    {"floor 1 a.png b.png c.glsl\n", "t.mat:1: ", "texture count says 1 but 2 file names follow before the shader 'c.glsl'"},
    {"floor 2 a.png\n", "t.mat:1: ", "texture count says 2 but the line ends after 1 file name, with no shader"},
    /* the shader */
    {"gold 0\n", "t.mat:1: ", "material 'gold' needs a shader after its texture count (a .glsl file or a built-in @name)"},
    {"floor 1 tiles.png\n", "t.mat:1: ", "material 'floor' needs a shader after its 1 texture"},
    {"gold 0 x.gls 1\n", "t.mat:1: ", "'x.gls' is not a shader: user shaders end in .glsl, built-ins start with @"},
    {"floor 1 tiles.png checker 0.9\n", "t.mat:1: ", "'checker' is not a shader"},
    {"gold 0 1.0 0.5 gold.glsl\n", "t.mat:1: ", "material 'gold' needs a shader before its numbers (a .glsl file or a built-in @name), got the number '1.0'"},
    {"gold 0 1.0\n", "t.mat:1: ", "needs a shader before its numbers"},
    {"gold 0 @Diffuse\n", "t.mat:1: ", "built-in shader '@Diffuse' is not a valid name: @ followed by a-z, 0-9 and _ only"},
    {"gold 0 @\n", "t.mat:1: ", "built-in shader '@' is not a valid name"},
    {"gold 0 @dif-fuse\n", "t.mat:1: ", "built-in shader '@dif-fuse' is not a valid name"},
    {"gold 0 @diffuse.glsl\n", "t.mat:1: ", "built-in shader '@diffuse.glsl' is not a valid name"},
    {"gold 0 \"my gold.glsl\"\n", "t.mat:1: ", "material 'gold': quotes are not supported; paths may not contain spaces"},
    {"gold 1 \"a b.png\" @diffuse\n", "t.mat:1: ", "quotes are not supported"},
    /* the numbers */
    {"gold 0 @diffuse 0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20 21\n", "t.mat:1: ", "material 'gold' has 22 numbers; at most 21 are allowed"},
    {"gold 0 @diffuse 0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20 21 22 23 24 25 26 27 28 29 30 31 32 33\n", "t.mat:1: ", "has 34 numbers; at most 21"},
    {"gold 0 @diffuse 1.0x\n", "t.mat:1: ", "material 'gold': param(0) '1.0x' is not a number"},
    {"gold 0 @diffuse 1 nan\n", "t.mat:1: ", "material 'gold': param(1) 'nan' is not a finite number"},
    {"gold 0 @diffuse 1 1 inf\n", "t.mat:1: ", "param(2) 'inf' is not a finite number"},
    {"gold 0 @diffuse -infinity\n", "t.mat:1: ", "param(0) '-infinity' is not a finite number"},
    {"gold 0 @diffuse 1e999\n", "t.mat:1: ", "param(0) '1e999' is not a finite number"},
    {"gold 0 @diffuse 1e39\n", "t.mat:1: ", "param(0) '1e39' is too large"},
    {"gold 0 @diffuse 0x\n", "t.mat:1: ", "param(0) '0x' is not a number"},
    {"gold 0 @diffuse 1 two\n", "t.mat:1: ", "param(1) 'two' is not a number"},
    /* duplicates, and the reserved name is no exception */
    {"gold 0 @diffuse\n# x\n\ngold 0 gold.glsl\n", "t.mat:4: ", "material 'gold' is defined twice (first on line 1)"},
    {"environment 0 @environment 1 1 1\nenvironment 0 sky.glsl\n", "t.mat:2: ", "material 'environment' is defined twice (first on line 1)"},
    /* not a text file */
    {OK "gold 0 @diffuse\x01\n", "t.mat:2: ", "not a text line (control character 0x01 at column 16)"},
    {OK "gold 0 @diff\xFFuse\n", "t.mat:2: ", "not a text line (invalid UTF-8 at column 13)"},
    /* the first error wins, and its line is counted across CRLF, blanks and comments */
    {"# c\r\n\r\n" OK "gold 0 @diffuse nan\r\nfoo\r\n", "t.mat:4: ", "param(0) 'nan'"},
};

static void test_malformed(void **state)
{
    (void)state;
    for (size_t i = 0; i < sizeof bad_cases / sizeof bad_cases[0]; i++)
        parse_fails(bad_cases[i].text, strlen(bad_cases[i].text), bad_cases[i].prefix,
                    bad_cases[i].phrase);
}

static void test_nul_and_long_lines(void **state)
{
    (void)state;
    static const char nul[] = "gold 0 @diffuse\nred 0 @dif\0fuse\n";
    parse_fails(nul, sizeof nul - 1, "t.mat:2: ",
                "not a text line (NUL byte at column 11); is this a material file?");
    /* A NUL in a comment is as wrong as anywhere else. */
    static const char nul_comment[] = "gold 0 @diffuse # \0\n";
    parse_fails(nul_comment, sizeof nul_comment - 1, "t.mat:1: ", "NUL byte at column 19");

    /* A line at the limit is fine; one byte over is not. */
    enum { LIMIT = 4096 };
    char *text = malloc(LIMIT + 2);
    assert_non_null(text);
    memset(text, ' ', LIMIT + 1);
    memcpy(text, "gold 0 @diffuse", 15);
    text[LIMIT] = '\n';
    vkrt_material_file file;
    vkrt_error err = {{0}};
    assert_true(vkrt_material_file_parse(text, LIMIT + 1, "t.mat", NULL, &file, &err));
    vkrt_material_file_free(&file);
    text[LIMIT] = ' ';
    text[LIMIT + 1] = '\n';
    parse_fails(text, LIMIT + 2, "t.mat:1: ", "line is longer than 4096 bytes");

    /* An absurdly long token is quoted cut short, so the message keeps its useful part. */
    memset(text, 'x', LIMIT);
    memcpy(text, "gold 0 @diffuse ", 16);
    text[LIMIT] = '\n';
    parse_fails(text, LIMIT + 1, "t.mat:1: ", "...' is not a number");
    free(text);
}

/* ---------------------------------------------------------------------------------------------
 * Loading from a file
 * ------------------------------------------------------------------------------------------- */

static void test_load_file(void **state)
{
    (void)state;
    char dir[] = "/tmp/vkrt-test-material-XXXXXX";
    assert_non_null(mkdtemp(dir));
    char path[256];
    snprintf(path, sizeof path, "%s/demo.mat", dir);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    fputs("gold 1 tex/g.png gold.glsl 1 0.8 0.3\nbad 0\n", f);
    fclose(f);

    vkrt_material_file file;
    memset(&file, 0xAB, sizeof file);
    vkrt_error err = {{0}};
    assert_false(vkrt_material_file_load(path, &file, &err));
    char want[512];
    snprintf(want, sizeof want, "%s:2: material 'bad' needs a shader", path);
    assert_memory_equal(err.msg, want, strlen(want));
    assert_zeroed(&file);

    f = fopen(path, "wb");
    assert_non_null(f);
    fputs("gold 1 tex/g.png gold.glsl 1 0.8 0.3\n", f);
    fclose(f);
    bool ok = vkrt_material_file_load(path, &file, &err);
    unlink(path);
    rmdir(dir);
    if (!ok)
        print_error("%s\n", err.msg);
    assert_true(ok);
    assert_string_equal(file.path, path);
    char want_texture[512], want_shader[512];
    snprintf(want_texture, sizeof want_texture, "%s/tex/g.png", dir);
    snprintf(want_shader, sizeof want_shader, "%s/gold.glsl", dir);
    assert_string_equal(file.defs[0].textures[0], want_texture);
    assert_string_equal(file.defs[0].shader, want_shader);
    vkrt_material_file_free(&file);
}

static void test_load_missing_file(void **state)
{
    (void)state;
    vkrt_material_file file;
    memset(&file, 0xAB, sizeof file);
    vkrt_error err = {{0}};
    assert_false(vkrt_material_file_load("/nonexistent/vkrt/x.mat", &file, &err));
    assert_string_equal(err.msg, "/nonexistent/vkrt/x.mat: cannot open: No such file or "
                                 "directory");
    assert_zeroed(&file);

    memset(&file, 0xAB, sizeof file);
    assert_false(vkrt_material_file_load(NULL, &file, &err));
    assert_string_equal(err.msg, "material file: no path given");
    assert_zeroed(&file);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_the_three_examples),
        cmocka_unit_test(test_limits_accepted),
        cmocka_unit_test(test_names),
        cmocka_unit_test(test_path_resolution),
        cmocka_unit_test(test_comments_crlf_and_blanks),
        cmocka_unit_test(test_empty_files),
        cmocka_unit_test(test_many_materials),
        cmocka_unit_test(test_free_zeroed_struct),
        cmocka_unit_test(test_malformed),
        cmocka_unit_test(test_nul_and_long_lines),
        cmocka_unit_test(test_load_file),
        cmocka_unit_test(test_load_missing_file),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
