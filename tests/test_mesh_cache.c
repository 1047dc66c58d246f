/*
 * test_mesh_cache.c: a scene file's model kept on disk (src/scene/scene_cache.h). No device
 * needed.
 *
 * What must hold: the model read back is the one parsed, array for array, with its instances,
 * material records, bounds and warnings; the OBJ's bytes changed under the same size and time, or
 * its .mtl changed, is parsed again; a damaged or truncated entry is parsed again; an OBJ under
 * 1 MiB, and one whose mtllib names a missing file, are not stored.
 */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h> /* cmocka needs these before its header */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <dirent.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "scene/obj/obj_load.h"
#include "scene/scene_cache.h"
#include "temp_dir.h"

/* A grid of 2 x 150 x 150 triangles (about 1.4 MiB of text), half of them red and half textured
 * blue, with normals and texture coordinates, and a face of two corners (a warning).
 * `colour` names the second material ("blue" or "bluf": the same size). */
static char *grid_obj(const char *mtllib, const char *colour, size_t *size)
{
    size_t capacity = 4u << 20, n = 0;
    char *text = malloc(capacity);
    enum { M = 150 };
    n += (size_t)snprintf(text + n, capacity - n, "mtllib %s\nvn 0 0 1\n", mtllib);
    for (int j = 0; j <= M; ++j)
        for (int i = 0; i <= M; ++i)
            n += (size_t)snprintf(text + n, capacity - n, "v %.5f %.5f %.5f\nvt %.4f %.4f\n",
                                  i / (double)M, j / (double)M, 0.01 * ((i * 7 + j * 3) % 11),
                                  i / (double)M, j / (double)M);
    for (int j = 0; j < M; ++j) {
        n += (size_t)snprintf(text + n, capacity - n, "usemtl %s\n", j < M / 2 ? "red" : colour);
        for (int i = 0; i < M; ++i) {
            int a = j * (M + 1) + i + 1, b = a + 1, c = a + M + 2, d = a + M + 1;
            n += (size_t)snprintf(text + n, capacity - n,
                                  "f %d/%d/1 %d/%d/1 %d/%d/1\nf %d/%d/1 %d/%d/1 %d/%d/1\n", a, a,
                                  b, b, c, c, a, a, c, c, d, d);
        }
    }
    n += (size_t)snprintf(text + n, capacity - n, "f 1 2\n");
    *size = n;
    return text;
}

static const char *MTL = "newmtl red\nKd 0.8 0.1 0.1\n"
                         "newmtl blue\nKd 0.1 0.1 0.8\nmap_Kd blue.png\n"
                         "newmtl bluf\nKd 0.1 0.8 0.1\n";

/* Writes grid.obj (grid_obj) and returns its path, which stays valid while fx does (fx->path
 * names whatever was written last). */
static const char *write_grid(temp_dir *fx, const char *mtllib, const char *colour)
{
    static char path[600];
    size_t size;
    char *text = grid_obj(mtllib, colour, &size);
    assert_true(size > (1u << 20));
    snprintf(path, sizeof path, "%s", temp_dir_write(fx, "grid.obj", text, size));
    free(text);
    return path;
}

static void use_cache(temp_dir *fx)
{
    char dir[600];
    snprintf(dir, sizeof dir, "%s/cache", fx->dir);
    setenv("VKRT_CACHE_DIR", dir, 1);
    unsetenv("VKRT_SCENE_CACHE_DIR");
}

static void load(const char *path, vkrt_model *model, vkrt_scene_cache_report *report)
{
    vkrt_error err = {{0}};
    bool ok = vkrt_scene_cache_load(vkrt_scene_loader_for(path), path, NULL, model, report,
                                    &err);
    /* The entry is written on a thread: the report is complete once it is done. */
    vkrt_scene_cache_finish(report);
    if (!ok)
        print_error("load failed: %s\n", err.msg);
    assert_true(ok);
}

static void assert_strings_equal(const char *a, const char *b)
{
    assert_int_equal(a == NULL, b == NULL);
    if (a)
        assert_string_equal(a, b);
}

static void assert_same_model(const vkrt_model *ma, const vkrt_model *mb)
{
    assert_int_equal(ma->mesh_count, 1);
    assert_int_equal(mb->mesh_count, 1);
    assert_int_equal(ma->instance_count, mb->instance_count);
    assert_memory_equal(ma->instances, mb->instances, ma->instance_count * sizeof(vkrt_instance));
    const vkrt_mesh *a = &ma->meshes[0], *b = &mb->meshes[0];
    size_t n = a->triangle_count;
    assert_int_equal(a->triangle_count, b->triangle_count);
    assert_int_equal(ma->triangle_count, mb->triangle_count);
    assert_memory_equal(a->positions, b->positions, n * 9 * sizeof(float));
    assert_non_null(a->normals);
    assert_memory_equal(a->normals, b->normals, n * 9 * sizeof(float));
    assert_non_null(a->texcoords);
    assert_memory_equal(a->texcoords, b->texcoords, n * 6 * sizeof(float));
    assert_null(b->tangents);
    assert_memory_equal(a->material, b->material, n * sizeof(int32_t));
    assert_memory_equal(a->bounds_min, b->bounds_min, sizeof a->bounds_min);
    assert_memory_equal(a->bounds_max, b->bounds_max, sizeof a->bounds_max);
    assert_memory_equal(ma->bounds_min, mb->bounds_min, sizeof ma->bounds_min);
    assert_memory_equal(ma->bounds_max, mb->bounds_max, sizeof ma->bounds_max);
    assert_int_equal(ma->material_count, mb->material_count);
    for (uint32_t i = 0; i < ma->material_count; ++i) {
        const vkrt_material *x = &ma->materials[i], *y = &mb->materials[i];
        assert_string_equal(x->name, y->name);
        assert_string_equal(x->file, y->file);
        assert_int_equal(x->bsdf, y->bsdf);
        assert_memory_equal(x->base_colour, y->base_colour, sizeof x->base_colour);
        assert_float_equal(x->roughness, y->roughness, 0);
        for (int k = 0; k < VKRT_MAP_COUNT; ++k) {
            assert_strings_equal(x->maps[k].path, y->maps[k].path);
            assert_int_equal(x->maps[k].line, y->maps[k].line);
            assert_int_equal(x->maps[k].space, y->maps[k].space);
        }
    }
    assert_string_equal(ma->warnings, mb->warnings);
    assert_strings_equal(ma->warnings_all, mb->warnings_all);
    assert_strings_equal(ma->inputs, mb->inputs);
}

/* The grid and its .mtl written in a fresh cache, loaded (parsed and stored) into *parsed;
 * returns the OBJ's path. */
static const char *stored_grid(temp_dir *fx, vkrt_model *parsed)
{
    use_cache(fx);
    temp_dir_write_text(fx, "grid.mtl", MTL);
    const char *path = write_grid(fx, "grid.mtl", "blue");
    vkrt_scene_cache_report report;
    load(path, parsed, &report);
    assert_int_equal(report.outcome, VKRT_SCENE_CACHE_STORED);
    return path;
}

static void read_back_equals_parsed(void **state)
{
    temp_dir *fx = *state;
    vkrt_model parsed, back;
    vkrt_scene_cache_report report;
    const char *path = stored_grid(fx, &parsed);
    assert_int_equal(parsed.triangle_count, 2 * 150 * 150);
    assert_non_null(strstr(parsed.warnings, "warning"));
    assert_int_equal(parsed.material_count, 3);
    load(path, &back, &report);
    assert_int_equal(report.outcome, VKRT_SCENE_CACHE_HIT);
    assert_same_model(&parsed, &back);
    /* And the parse itself, without the cache, is what both hold. */
    vkrt_model plain;
    vkrt_error err = {{0}};
    assert_true(vkrt_obj_load(path, &plain, &err));
    assert_same_model(&plain, &back);
    vkrt_model_free(&plain);
    vkrt_model_free(&parsed);
    vkrt_model_free(&back);
}

/* Sets path's modification time to `when` (seconds), as `touch -d` would. */
static void set_mtime(const char *path, time_t when)
{
    struct timespec times[2] = {{when, 0}, {when, 0}};
    assert_int_equal(utimensat(AT_FDCWD, path, times, 0), 0);
}

static void changed_files_are_parsed_again(void **state)
{
    temp_dir *fx = *state;
    use_cache(fx);
    temp_dir_write_text(fx, "grid.mtl", MTL);
    const char *path = write_grid(fx, "grid.mtl", "blue");
    set_mtime(path, 1000000000);
    vkrt_model mesh;
    vkrt_scene_cache_report report;
    load(path, &mesh, &report);
    int32_t blue = mesh.meshes[0].material[mesh.triangle_count - 1];
    vkrt_model_free(&mesh);
    /* Other bytes, the same size and time: the content hash tells. */
    path = write_grid(fx, "grid.mtl", "bluf");
    set_mtime(path, 1000000000);
    load(path, &mesh, &report);
    assert_int_equal(report.outcome, VKRT_SCENE_CACHE_STORED);
    assert_int_not_equal(mesh.meshes[0].material[mesh.triangle_count - 1], blue);
    vkrt_model_free(&mesh);
    load(path, &mesh, &report);
    assert_int_equal(report.outcome, VKRT_SCENE_CACHE_HIT);
    vkrt_model_free(&mesh);
    /* A changed .mtl. */
    temp_dir_write_text(fx, "grid.mtl", "newmtl red\nKd 0.8 0.1 0.1\nnewmtl bluf\nKd 0.9 0.9 0.1\n");
    load(path, &mesh, &report);
    assert_int_equal(report.outcome, VKRT_SCENE_CACHE_STORED);
    assert_string_equal(report.rejected, "a file the scene file names changed");
    assert_true(mesh.materials[mesh.meshes[0].material[mesh.triangle_count - 1]].base_colour[0] > 0.85f);
    vkrt_model_free(&mesh);
}

/* The one .mesh file of the cache, into path. */
static void entry(temp_dir *fx, char *path, size_t size)
{
    char dir[600];
    snprintf(dir, sizeof dir, "%s/cache", fx->dir);
    DIR *d = opendir(dir);
    assert_non_null(d);
    int found = 0;
    for (struct dirent *e; (e = readdir(d));)
        if (strstr(e->d_name, ".mesh")) {
            snprintf(path, size, "%s/%s", dir, e->d_name);
            ++found;
        }
    closedir(d);
    assert_int_equal(found, 1);
}

static void damaged_and_truncated_entries_are_parsed_again(void **state)
{
    temp_dir *fx = *state;
    vkrt_model parsed, mesh;
    vkrt_scene_cache_report report;
    const char *path = stored_grid(fx, &parsed);
    char file[1200];
    entry(fx, file, sizeof file);
    struct stat st;
    assert_int_equal(stat(file, &st), 0);
    /* One bit of the header, of the text, of the positions, of the last array. */
    const long at[] = {20, 300, (long)st.st_size / 2, (long)st.st_size - 1};
    for (size_t i = 0; i < sizeof at / sizeof *at; ++i) {
        FILE *f = fopen(file, "r+b");
        fseek(f, at[i], SEEK_SET);
        int c = fgetc(f);
        fseek(f, at[i], SEEK_SET);
        fputc(c ^ 0x04, f);
        fclose(f);
        load(path, &mesh, &report);
        assert_int_equal(report.outcome, VKRT_SCENE_CACHE_STORED);
        assert_string_equal(report.rejected, "a damaged entry");
        assert_same_model(&parsed, &mesh);
        vkrt_model_free(&mesh);
    }
    assert_int_equal(truncate(file, st.st_size - 8), 0);
    load(path, &mesh, &report);
    assert_int_equal(report.outcome, VKRT_SCENE_CACHE_STORED);
    assert_same_model(&parsed, &mesh);
    vkrt_model_free(&mesh);
    load(path, &mesh, &report);
    assert_int_equal(report.outcome, VKRT_SCENE_CACHE_HIT);
    vkrt_model_free(&mesh);
    vkrt_model_free(&parsed);
}

static void small_and_incomplete_scenes_are_not_stored(void **state)
{
    temp_dir *fx = *state;
    use_cache(fx);
    vkrt_model mesh;
    vkrt_scene_cache_report report;
    load(temp_dir_write_text(fx, "small.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"), &mesh,
         &report);
    assert_int_equal(report.outcome, VKRT_SCENE_CACHE_SKIPPED);
    assert_string_equal(report.why, "a scene file under 1 MiB");
    vkrt_model_free(&mesh);
    load(write_grid(fx, "absent.mtl", "blue"), &mesh, &report);
    assert_int_equal(report.outcome, VKRT_SCENE_CACHE_SKIPPED);
    assert_string_equal(report.why, "the scene file names a file not found");
    vkrt_model_free(&mesh);
    /* No cache: parsed, nothing said. */
    setenv("VKRT_SCENE_CACHE_DIR", "", 1);
    temp_dir_write_text(fx, "grid.mtl", MTL);
    load(write_grid(fx, "grid.mtl", "blue"), &mesh, &report);
    assert_int_equal(report.outcome, VKRT_SCENE_CACHE_OFF);
    vkrt_model_free(&mesh);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        temp_dir_test(read_back_equals_parsed),
        temp_dir_test(changed_files_are_parsed_again),
        temp_dir_test(damaged_and_truncated_entries_are_parsed_again),
        temp_dir_test(small_and_incomplete_scenes_are_not_stored),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
