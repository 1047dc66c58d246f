/*
 * test_accel_cache.c: built structures kept on disk (src/render/accel_cache.h) and the hashes
 * that key them (src/cache_file.h). No device needed.
 *
 * What must hold: the structure read back is the one built, array for array (BVH 2 and 4 wide,
 * with spatial splits, the kd-tree, the grid); a triangle moved by one ulp or any field of the
 * description changed gives another key; a damaged, truncated or foreign entry is a miss; a new
 * version of one source's structure replaces the old entry, not another source's; small
 * scenes and a turned-off cache have no key; a file's hash, read in chunks on several threads,
 * is the hash of its bytes in memory. A two-level BVH (src/render/accel_instanced.h) reads back
 * with its instance map, and moving one instance by one ulp gives another key.
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
#include <unistd.h>

#include "cache_file.h"
#include "render/accel_cache.h"
#include "temp_dir.h"

enum { TRIANGLES = 30000 };

/* Small triangles scattered in a box (a fixed LCG: the same scene every run). */
static float *scene(void)
{
    float *p = malloc(TRIANGLES * 9 * sizeof *p);
    uint32_t state = 12345;
    for (size_t t = 0; t < TRIANGLES; ++t) {
        float centre[3];
        for (int k = 0; k < 3; ++k) {
            state = state * 1664525u + 1013904223u;
            centre[k] = (float)(state >> 8) / 16777216.0f * 10.0f;
        }
        for (int v = 0; v < 3; ++v)
            for (int k = 0; k < 3; ++k) {
                state = state * 1664525u + 1013904223u;
                p[9 * t + 3 * v + k] = centre[k] + (float)(state >> 8) / 16777216.0f * 0.2f;
            }
    }
    return p;
}

static void use_cache(temp_dir *fx)
{
    setenv("VKRT_CACHE_DIR", temp_dir_path(fx, "cache"), 1);
}

static void assert_same_arrays(const vkrt_accel_arrays *a, const vkrt_accel_arrays *b)
{
    assert_memory_equal(&a->info, &b->info, sizeof a->info);
    assert_int_equal(a->node_size, b->node_size);
    assert_int_equal(a->node_count, b->node_count);
    assert_true(a->node_count > 0);
    assert_memory_equal(a->nodes, b->nodes, a->node_size * a->node_count);
    assert_int_equal(a->ref_count, b->ref_count);
    if (a->ref_count)
        assert_memory_equal(a->refs, b->refs, a->ref_count * sizeof *a->refs);
    assert_int_equal(a->triangle_count, b->triangle_count);
    assert_int_equal(a->prim_order != NULL, b->prim_order != NULL);
    if (a->prim_order)
        assert_memory_equal(a->prim_order, b->prim_order,
                            a->triangle_count * sizeof *a->prim_order);
    assert_int_equal(a->stats.kind, b->stats.kind);
    assert_int_equal(a->stats.nodes, b->stats.nodes);
    assert_int_equal(a->stats.leaves, b->stats.leaves);
    assert_int_equal(a->stats.references, b->stats.references);
    assert_true(a->stats.sah_cost == b->stats.sah_cost);
    assert_string_equal(a->stats.reason, b->stats.reason);
}

/* Builds desc's structure, stores it, reads it back: the same arrays. */
static void round_trip(const vkrt_accel_desc *desc, const float *positions)
{
    vkrt_accel_arrays built, back;
    vkrt_error err = {{0}};
    assert_true(vkrt_accel_build(desc, positions, TRIANGLES, &built, &err));
    vkrt_accel_cache_name name;
    assert_true(vkrt_accel_cache_name_of(desc, positions, TRIANGLES, &name));
    assert_false(vkrt_accel_cache_load(&name, &back));
    vkrt_accel_cache_store(&name, &built);
    assert_true(vkrt_accel_cache_load(&name, &back));
    assert_true(back.stats.from_cache);
    assert_false(built.stats.from_cache);
    assert_same_arrays(&built, &back);
    vkrt_accel_arrays_free(&built);
    vkrt_accel_arrays_free(&back);
}

static void read_back_equals_built(void **state)
{
    use_cache(*state);
    float *p = scene();
    const vkrt_accel_desc descs[] = {
        {.kind = VKRT_ACCEL_BVH, .bvh_width = 2, .bvh_splits = VKRT_BVH_SPLITS_OFF},
        {.kind = VKRT_ACCEL_BVH, .bvh_width = 4, .bvh_max_leaf = 4},
        {.kind = VKRT_ACCEL_BVH, .bvh_width = 4, .bvh_splits = VKRT_BVH_SPLITS_ON},
        {.kind = VKRT_ACCEL_KDTREE},
        {.kind = VKRT_ACCEL_GRID},
        {.kind = VKRT_ACCEL_AUTO, .bvh_width = 4, .grid_competes = true},
    };
    for (size_t i = 0; i < sizeof descs / sizeof *descs; ++i)
        round_trip(&descs[i], p);
    free(p);
}

static void keys_follow_every_input(void **state)
{
    use_cache(*state);
    float *p = scene();
    const vkrt_accel_desc base = {.kind = VKRT_ACCEL_BVH, .bvh_width = 4};
    vkrt_accel_cache_name n0, n;
    assert_true(vkrt_accel_cache_name_of(&base, p, TRIANGLES, &n0));
    assert_true(vkrt_accel_cache_name_of(&base, p, TRIANGLES, &n));
    assert_memory_equal(n0.key, n.key, sizeof n.key);
    vkrt_accel_desc changed[] = {base, base, base, base, base, base, base, base, base};
    changed[0].bvh_width = 2;
    changed[1].bvh_max_leaf = 3;
    changed[2].bvh_traversal_cost = 0.75f;
    changed[3].bvh_splits = VKRT_BVH_SPLITS_ON;
    changed[4].bvh_spatial_budget = 0.5f;
    changed[5].kind = VKRT_ACCEL_AUTO;
    changed[6].grid_density = 2.0f;
    changed[7].kd_traversal_cost = 1.5f;
    changed[8].kdtree_competes = true;
    for (size_t i = 0; i < sizeof changed / sizeof *changed; ++i) {
        assert_true(vkrt_accel_cache_name_of(&changed[i], p, TRIANGLES, &n));
        assert_memory_not_equal(n0.key, n.key, sizeof n.key);
    }
    /* The source names the entry's family, never the structure: the same key. */
    vkrt_accel_desc sourced = base;
    sourced.source = "scene.obj";
    assert_true(vkrt_accel_cache_name_of(&sourced, p, TRIANGLES, &n));
    assert_memory_equal(n0.key, n.key, sizeof n.key);
    assert_string_equal(n0.ext, ".accel");
    assert_string_not_equal(n.ext, ".accel");
    p[9 * 1234 + 4] = nextafterf(p[9 * 1234 + 4], INFINITY);
    assert_true(vkrt_accel_cache_name_of(&base, p, TRIANGLES, &n));
    assert_memory_not_equal(n0.key, n.key, sizeof n.key);
    /* Too small to be worth storing, and no cache at all: no name. */
    assert_false(vkrt_accel_cache_name_of(&base, p, 1000, &n));
    setenv("VKRT_CACHE_DIR", "", 1);
    assert_false(vkrt_accel_cache_name_of(&base, p, TRIANGLES, &n));
    free(p);
}

/* The named entry's file, into path. */
static void entry_path(const vkrt_accel_cache_name *name, char *path, size_t size)
{
    assert_true(vkrt_cache_entry_path(VKRT_CACHE_SCENES, name->key, name->ext, path, size));
}

static long file_size(const char *path)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    fseek(f, 0, SEEK_END);
    long size = ftell(f);
    fclose(f);
    return size;
}

static void damaged_truncated_and_foreign_are_misses(void **state)
{
    use_cache(*state);
    float *p = scene();
    const vkrt_accel_desc desc = {.kind = VKRT_ACCEL_BVH, .bvh_width = 2};
    vkrt_accel_arrays built, back;
    vkrt_error err = {{0}};
    assert_true(vkrt_accel_build(&desc, p, TRIANGLES, &built, &err));
    vkrt_accel_cache_name name;
    assert_true(vkrt_accel_cache_name_of(&desc, p, TRIANGLES, &name));
    char path[4200];
    entry_path(&name, path, sizeof path);
    long size;
    /* One bit of the nodes (the middle), of the triangle order (the end), of the header's
     * statistics (byte 200: the reason's text). */
    for (int i = 0; i < 3; ++i) {
        vkrt_accel_cache_store(&name, &built);
        size = file_size(path);
        long at = i == 0 ? size / 2 : i == 1 ? size - 2 : 200;
        FILE *f = fopen(path, "r+b");
        fseek(f, at, SEEK_SET);
        int c = fgetc(f);
        fseek(f, at, SEEK_SET);
        fputc(c ^ 0x10, f);
        fclose(f);
        assert_false(vkrt_accel_cache_load(&name, &back));
    }
    /* Truncated by one byte. */
    vkrt_accel_cache_store(&name, &built);
    size = file_size(path);
    assert_int_equal(truncate(path, size - 1), 0);
    assert_false(vkrt_accel_cache_load(&name, &back));
    /* Another structure's entry under this key's name. */
    const vkrt_accel_desc other = {.kind = VKRT_ACCEL_BVH, .bvh_width = 4};
    vkrt_accel_arrays built4;
    assert_true(vkrt_accel_build(&other, p, TRIANGLES, &built4, &err));
    vkrt_accel_cache_name name4;
    assert_true(vkrt_accel_cache_name_of(&other, p, TRIANGLES, &name4));
    vkrt_accel_cache_store(&name4, &built4);
    char path4[4200];
    entry_path(&name4, path4, sizeof path4);
    assert_int_equal(rename(path4, path), 0);
    assert_false(vkrt_accel_cache_load(&name, &back));
    /* And whole again: a hit. */
    vkrt_accel_cache_store(&name, &built);
    assert_true(vkrt_accel_cache_load(&name, &back));
    assert_same_arrays(&built, &back);
    vkrt_accel_arrays_free(&back);
    vkrt_accel_arrays_free(&built);
    vkrt_accel_arrays_free(&built4);
    free(p);
}

static bool exists(const char *path)
{
    return access(path, F_OK) == 0;
}

/* A new version of one source's structure replaces the old one; another source's stays. */
static void newer_versions_replace_older(void **state)
{
    use_cache(*state);
    float *p = scene();
    vkrt_accel_desc desc = {.kind = VKRT_ACCEL_GRID, .source = "/scenes/a.obj"};
    vkrt_accel_arrays built;
    vkrt_error err = {{0}};
    assert_true(vkrt_accel_build(&desc, p, TRIANGLES, &built, &err));
    vkrt_accel_cache_name a1, b1, a2;
    char path_a1[4200], path_b1[4200], path_a2[4200];
    assert_true(vkrt_accel_cache_name_of(&desc, p, TRIANGLES, &a1));
    vkrt_accel_cache_store(&a1, &built);
    desc.source = "/scenes/b.obj";
    assert_true(vkrt_accel_cache_name_of(&desc, p, TRIANGLES, &b1));
    vkrt_accel_cache_store(&b1, &built);
    /* a.obj edited: one vertex moved. (The arrays stored need not match: only names matter.) */
    p[5] = nextafterf(p[5], INFINITY);
    desc.source = "/scenes/a.obj";
    assert_true(vkrt_accel_cache_name_of(&desc, p, TRIANGLES, &a2));
    assert_string_equal(a1.ext, a2.ext);
    vkrt_accel_cache_store(&a2, &built);
    entry_path(&a1, path_a1, sizeof path_a1);
    entry_path(&b1, path_b1, sizeof path_b1);
    entry_path(&a2, path_a2, sizeof path_a2);
    assert_false(exists(path_a1));
    assert_true(exists(path_b1));
    assert_true(exists(path_a2));
    vkrt_accel_arrays_free(&built);
    free(p);
}

static void file_hash_is_the_bytes_hash(void **state)
{
    temp_dir *fx = *state;
    /* Three chunks and a part of one, hashed by several threads. */
    size_t size = (size_t)3 * (8u << 20) + 12345;
    unsigned char *bytes = malloc(size);
    for (size_t i = 0; i < size; ++i)
        bytes[i] = (unsigned char)(i * 2654435761u >> 13);
    const char *path = temp_dir_write(fx, "data", bytes, size);
    vkrt_file_identity id;
    assert_true(vkrt_file_identity_of(path, &id));
    assert_int_equal(id.size, size);
    assert_true(id.hash == vkrt_hash64_parallel(bytes, size));
    bytes[size - 1] ^= 1;
    assert_true(id.hash != vkrt_hash64_parallel(bytes, size));
    assert_false(vkrt_file_identity_of(temp_dir_path(fx, "absent"), &id));
    free(bytes);
}

/* Two meshes (the scene's triangles split 2:1) placed 40 times, tilted and scaled by a fixed LCG;
 * a zeroed model on entry. */
enum { INSTANCES = 40, FIRST_MESH = 20000 };
static void instanced_model(vkrt_model *m, float *positions)
{
    m->meshes = calloc(2, sizeof *m->meshes);
    m->instances = calloc(INSTANCES, sizeof *m->instances);
    assert_true(m->meshes && m->instances);
    m->mesh_count = 2;
    m->meshes[0] = (vkrt_mesh){.triangle_count = FIRST_MESH, .positions = positions};
    m->meshes[1] = (vkrt_mesh){.triangle_count = TRIANGLES - FIRST_MESH,
                               .positions = positions + 9 * FIRST_MESH};
    m->instance_count = INSTANCES;
    uint32_t state = 777;
    for (uint32_t i = 0; i < INSTANCES; ++i) {
        state = state * 1664525u + 1013904223u;
        float a = (float)(state >> 8) / 16777216.0f * 6.2831853f, s = 0.5f + (float)(i % 3);
        const float t[12] = {s * cosf(a), 0, s * sinf(a), 12.0f * (float)(i % 8),
                             0, s, 0, 0.5f * (float)i,
                             -s * sinf(a), 0, s * cosf(a), 12.0f * (float)(i / 8)};
        m->instances[i].mesh = i % 2;
        memcpy(m->instances[i].transform, t, sizeof t);
    }
    vkrt_error err = {{0}};
    assert_true(vkrt_model_finish(m, &err));
}

static void two_level_reads_back_with_its_instances(void **state)
{
    use_cache(*state);
    float *p = scene();
    vkrt_model m = {0};
    instanced_model(&m, p);
    uint32_t *material = calloc(TRIANGLES, sizeof *material);
    const uint32_t material_first[2] = {0, FIRST_MESH};
    vkrt_unique_meshes u;
    vkrt_error err = {{0}};
    assert_non_null(material);
    assert_true(vkrt_unique_meshes_make(&m, material, material_first, &u, &err));
    const vkrt_accel_desc desc = {.kind = VKRT_ACCEL_BVH, .bvh_width = 4};
    vkrt_accel_arrays built, back;
    assert_true(vkrt_accel_build_instanced(&desc, &m, &u, &built, &err));
    assert_int_equal(built.instances.count, INSTANCES);
    vkrt_accel_cache_name name, moved;
    assert_true(vkrt_accel_cache_name_of_instanced(&desc, &m, &u, &name));
    assert_false(vkrt_accel_cache_load(&name, &back));
    vkrt_accel_cache_store(&name, &built);
    assert_true(vkrt_accel_cache_load(&name, &back));
    assert_same_arrays(&built, &back);
    assert_int_equal(back.instances.count, INSTANCES);
    assert_memory_equal(built.instances.first, back.instances.first,
                        INSTANCES * sizeof *built.instances.first);
    assert_memory_equal(built.instances.mesh_base, back.instances.mesh_base,
                        INSTANCES * sizeof *built.instances.mesh_base);
    assert_memory_equal(built.instances.flat_first, back.instances.flat_first,
                        INSTANCES * sizeof *built.instances.flat_first);
    /* The flat structure over the same unique triangles is another entry. */
    vkrt_accel_cache_name flat;
    assert_true(vkrt_accel_cache_name_of(&desc, u.mesh.positions, u.mesh.triangle_count, &flat));
    assert_false(flat.key[0] == name.key[0] && flat.key[1] == name.key[1]);
    /* One instance moved by one ulp: another key, and a miss. */
    float *x = &m.instances[INSTANCES - 1].transform[3];
    *x = nextafterf(*x, INFINITY);
    assert_true(vkrt_accel_cache_name_of_instanced(&desc, &m, &u, &moved));
    assert_false(moved.key[0] == name.key[0] && moved.key[1] == name.key[1]);
    vkrt_accel_arrays miss;
    assert_false(vkrt_accel_cache_load(&moved, &miss));
    vkrt_accel_arrays_free(&built);
    vkrt_accel_arrays_free(&back);
    vkrt_unique_meshes_free(&u);
    free(material);
    /* The meshes point into p: the model owns neither. */
    free(m.meshes);
    free(m.instances);
    free(p);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        temp_dir_test(read_back_equals_built),
        temp_dir_test(keys_follow_every_input),
        temp_dir_test(damaged_truncated_and_foreign_are_misses),
        temp_dir_test(newer_versions_replace_older),
        temp_dir_test(file_hash_is_the_bytes_hash),
        temp_dir_test(two_level_reads_back_with_its_instances),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
