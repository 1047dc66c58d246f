/*
 * accel_cache.c: built structures kept in the cache directory (accel_cache.h).
 *
 * An entry "<key>.<family>.accel" (accel_cache.h: the latest of one scene file's structures
 * under one set of settings) is a header (magic, key, the arrays' sizes, the frame, the statistics,
 * each array's hash and a hash of the header itself), then the nodes, the references and the
 * triangle order, exactly as vkrt_accel_arrays holds them. The file's size must be the header's
 * sum: a truncated entry is found before anything is read. A two-level BVH's entry also holds its
 * instance map (accel_gpu.h vkrt_instance_map), after the triangle order.
 */
#define _POSIX_C_SOURCE 200809L
#include "accel_cache.h"

#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../cache_file.h"
#include "../clock.h"

/* "VKRTACC" and the layout's version: a new layout gets a new number (it is in the key too). */
static const uint64_t ACCEL_MAGIC = 0x3143434154524B56ull; /* "VKRTACC1", little-endian */
enum { LAYOUT_VERSION = 2 };

/* A structure over fewer triangles builds in milliseconds: storing it would only fill the disk. */
static const uint32_t MIN_TRIANGLES = 20000;

enum {
    ARRAY_NODES,
    ARRAY_REFS,
    ARRAY_ORDER,
    ARRAY_INSTANCE_FIRST,
    ARRAY_INSTANCE_MESH_BASE,
    ARRAY_INSTANCE_FLAT_FIRST,
    ARRAY_COUNT
};

typedef struct accel_header {
    uint64_t magic;
    uint64_t key[2];
    uint64_t node_size, node_count, ref_count;
    uint64_t triangle_count, has_order;
    uint64_t instance_count; /* 0: one flat structure */
    GridInfo info;
    vkrt_accel_stats stats;
    uint64_t hash[ARRAY_COUNT];
    uint64_t header_hash; /* of everything above */
} accel_header;

static atomic_bool disabled;

void vkrt_accel_cache_disable(void)
{
    atomic_store(&disabled, true);
}

/* The name of a structure under desc whose geometry geometry_text describes (counts and
 * hashes); what (e.g. "flat") keeps one kind of structure's family from another's. */
static bool name_of(const vkrt_accel_desc *desc, const char *what, const char *geometry_text,
                    vkrt_accel_cache_name *name)
{
    /* Every field of desc by name, floats exactly (%a): padding never enters the key. */
    char settings[1024], text[1400];
    int n = snprintf(
        settings, sizeof settings,
        "vkrt structure layout %d, program %016llx, nodes %zu %zu %zu, stats %zu; %s; kind %d, "
        "splits %d, grid density %a, BVH width %u, leaf %u, node cost %a, spatial budget %a, "
        "kd-tree cost %a, grid competes %d, kd-tree competes %d",
        LAYOUT_VERSION, (unsigned long long)vkrt_cache_program_id(), sizeof(BvhPair),
        sizeof(BvhQuad), sizeof(KdNode), sizeof(vkrt_accel_stats), what, (int)desc->kind,
        (int)desc->bvh_splits, (double)desc->grid_density, desc->bvh_width, desc->bvh_max_leaf,
        (double)desc->bvh_traversal_cost, (double)desc->bvh_spatial_budget,
        (double)desc->kd_traversal_cost, (int)desc->grid_competes, (int)desc->kdtree_competes);
    if (n < 0 || (size_t)n >= sizeof settings)
        return false;
    int m = snprintf(text, sizeof text, "%s; %s", settings, geometry_text);
    if (m < 0 || (size_t)m >= sizeof text)
        return false;
    name->key[0] = vkrt_hash64(text, (size_t)m, 0x243F6A8885A308D3ull);
    name->key[1] = vkrt_hash64(text, (size_t)m, 0x13198A2E03707344ull);
    if (!desc->source) {
        snprintf(name->ext, sizeof name->ext, ".accel");
        return true;
    }
    char cwd[4096] = "";
    if (desc->source[0] != '/' && !getcwd(cwd, sizeof cwd))
        cwd[0] = '\0';
    uint64_t family = vkrt_hash64(settings, (size_t)n,
                                  vkrt_hash64(desc->source, strlen(desc->source),
                                              vkrt_hash64(cwd, strlen(cwd), 0)));
    snprintf(name->ext, sizeof name->ext, ".%016llx.accel", (unsigned long long)family);
    return true;
}

/* Whether a structure over this much is worth storing at all. */
static bool worth_storing(uint64_t work)
{
    char dir[4096];
    return work >= MIN_TRIANGLES && !atomic_load(&disabled) &&
           vkrt_cache_dir(VKRT_CACHE_SCENES, dir, sizeof dir);
}

bool vkrt_accel_cache_name_of(const vkrt_accel_desc *desc, const float *positions,
                              uint32_t triangle_count, vkrt_accel_cache_name *name)
{
    memset(name, 0, sizeof *name);
    if (!worth_storing(triangle_count))
        return false;
    uint64_t positions_hash =
        vkrt_hash64_parallel(positions, (size_t)triangle_count * 9 * sizeof *positions);
    char geometry[128];
    snprintf(geometry, sizeof geometry, "%u triangles, positions %016llx", triangle_count,
             (unsigned long long)positions_hash);
    return name_of(desc, "flat", geometry, name);
}

bool vkrt_accel_cache_name_of_instanced(const vkrt_accel_desc *desc, const vkrt_model *model,
                                        const vkrt_unique_meshes *u, vkrt_accel_cache_name *name)
{
    memset(name, 0, sizeof *name);
    /* The top level's build grows with the instances, the bottom levels' with the triangles. */
    if (!worth_storing((uint64_t)u->mesh.triangle_count + model->instance_count))
        return false;
    uint64_t positions_hash = vkrt_hash64_parallel(
        u->mesh.positions, (size_t)u->mesh.triangle_count * 9 * sizeof *u->mesh.positions);
    /* Each instance's mesh and transform, field by field (no padding enters), and where each
     * mesh's triangles begin among the unique ones. */
    uint64_t instances_hash = 0x452821E638D01377ull;
    for (uint32_t i = 0; i < model->instance_count; ++i) {
        const vkrt_instance *in = &model->instances[i];
        instances_hash = vkrt_hash64(&in->mesh, sizeof in->mesh, instances_hash);
        instances_hash = vkrt_hash64(in->transform, sizeof in->transform, instances_hash);
    }
    uint64_t bases_hash =
        vkrt_hash64(u->mesh_base, (size_t)model->mesh_count * sizeof *u->mesh_base, 0);
    char geometry[256];
    snprintf(geometry, sizeof geometry,
             "%u unique triangles, positions %016llx; %u meshes, bases %016llx; %u instances "
             "%016llx",
             u->mesh.triangle_count, (unsigned long long)positions_hash, model->mesh_count,
             (unsigned long long)bases_hash, model->instance_count,
             (unsigned long long)instances_hash);
    return name_of(desc, "two-level", geometry, name);
}

/* The bytes of each array a header describes. */
static void array_bytes(const accel_header *h, uint64_t bytes[ARRAY_COUNT])
{
    bytes[ARRAY_NODES] = h->node_size * h->node_count;
    bytes[ARRAY_REFS] = h->ref_count * sizeof(uint32_t);
    bytes[ARRAY_ORDER] = h->has_order ? h->triangle_count * sizeof(uint32_t) : 0;
    bytes[ARRAY_INSTANCE_FIRST] = h->instance_count * sizeof(uint32_t);
    bytes[ARRAY_INSTANCE_MESH_BASE] = h->instance_count * sizeof(uint32_t);
    bytes[ARRAY_INSTANCE_FLAT_FIRST] = h->instance_count * sizeof(uint64_t);
}

/* Whether a header's counts are ones a build could give (before any size is trusted). */
static bool plausible(const accel_header *h)
{
    const vkrt_accel_stats *s = &h->stats;
    bool size_ok = h->node_size == sizeof(uint32_t) || h->node_size == sizeof(BvhPair) ||
                   h->node_size == sizeof(BvhQuad) || h->node_size == sizeof(KdNode);
    return size_ok && h->node_count < (1ull << 34) && h->ref_count < (1ull << 34) &&
           h->triangle_count <= UINT32_MAX && h->has_order <= 1 &&
           h->instance_count <= UINT32_MAX &&
           (h->instance_count == 0 || s->kind == VKRT_ACCEL_BVH) &&
           (s->kind == VKRT_ACCEL_GRID || s->kind == VKRT_ACCEL_BVH ||
            s->kind == VKRT_ACCEL_KDTREE) &&
           memchr(s->reason, '\0', sizeof s->reason) != NULL;
}

bool vkrt_accel_cache_load(const vkrt_accel_cache_name *name, vkrt_accel_arrays *a)
{
    memset(a, 0, sizeof *a);
    double start = vkrt_clock_ms();
    vkrt_cache_reader r;
    const uint64_t *key = name->key;
    if (!vkrt_cache_reader_open(&r, VKRT_CACHE_SCENES, key, name->ext))
        return false;
    accel_header h;
    uint64_t bytes[ARRAY_COUNT] = {0};
    vkrt_cache_reader_get(&r, &h, sizeof h);
    r.ok = r.ok && h.magic == ACCEL_MAGIC && h.key[0] == key[0] && h.key[1] == key[1] &&
           vkrt_hash64(&h, offsetof(accel_header, header_hash), 0) == h.header_hash &&
           plausible(&h);
    if (r.ok) {
        array_bytes(&h, bytes);
        uint64_t total = sizeof h;
        for (int i = 0; i < ARRAY_COUNT; ++i)
            total += bytes[i];
        r.ok = total == r.size;
    }
    a->nodes = vkrt_cache_reader_array(&r, bytes[ARRAY_NODES], h.hash[ARRAY_NODES]);
    a->refs = vkrt_cache_reader_array(&r, bytes[ARRAY_REFS], h.hash[ARRAY_REFS]);
    a->prim_order = vkrt_cache_reader_array(&r, bytes[ARRAY_ORDER], h.hash[ARRAY_ORDER]);
    vkrt_instance_map *m = &a->instances;
    m->first = vkrt_cache_reader_array(&r, bytes[ARRAY_INSTANCE_FIRST],
                                       h.hash[ARRAY_INSTANCE_FIRST]);
    m->mesh_base = vkrt_cache_reader_array(&r, bytes[ARRAY_INSTANCE_MESH_BASE],
                                           h.hash[ARRAY_INSTANCE_MESH_BASE]);
    m->flat_first = vkrt_cache_reader_array(&r, bytes[ARRAY_INSTANCE_FLAT_FIRST],
                                            h.hash[ARRAY_INSTANCE_FLAT_FIRST]);
    m->count = r.ok ? (uint32_t)h.instance_count : 0;
    vkrt_cache_reader_close(&r);
    if (!r.ok) {
        vkrt_accel_arrays_free(a);
        return false;
    }
    a->info = h.info;
    a->node_size = (size_t)h.node_size;
    a->node_count = (size_t)h.node_count;
    a->ref_count = (size_t)h.ref_count;
    a->triangle_count = (uint32_t)h.triangle_count;
    a->stats = h.stats;
    a->stats.from_cache = true;
    a->stats.choose_ms = 0;
    a->stats.build_ms = vkrt_clock_ms() - start;
    return true;
}

void vkrt_accel_cache_store(const vkrt_accel_cache_name *name, const vkrt_accel_arrays *a)
{
    const uint64_t *key = name->key;
    accel_header h;
    /* Zeroed first: the padding of the header and of its statistics is hashed and written. */
    memset(&h, 0, sizeof h);
    h.magic = ACCEL_MAGIC;
    h.key[0] = key[0];
    h.key[1] = key[1];
    h.node_size = a->node_size;
    h.node_count = a->node_count;
    h.ref_count = a->ref_count;
    h.triangle_count = a->triangle_count;
    h.has_order = a->prim_order != NULL;
    h.instance_count = a->instances.count;
    memcpy(&h.info, &a->info, sizeof h.info);
    memcpy(&h.stats, &a->stats, sizeof h.stats);
    const void *arrays[ARRAY_COUNT] = {a->nodes,           a->refs,
                                       a->prim_order,      a->instances.first,
                                       a->instances.mesh_base, a->instances.flat_first};
    uint64_t bytes[ARRAY_COUNT];
    array_bytes(&h, bytes);
    for (int i = 0; i < ARRAY_COUNT; ++i)
        h.hash[i] = bytes[i] ? vkrt_hash64_parallel(arrays[i], (size_t)bytes[i]) : 0;
    h.header_hash = vkrt_hash64(&h, offsetof(accel_header, header_hash), 0);
    vkrt_cache_writer w;
    if (!vkrt_cache_writer_open(&w, VKRT_CACHE_SCENES, "structure cache", key, name->ext))
        return;
    vkrt_cache_writer_put(&w, &h, sizeof h);
    for (int i = 0; i < ARRAY_COUNT; ++i)
        vkrt_cache_writer_put(&w, arrays[i], (size_t)bytes[i]);
    if (vkrt_cache_writer_commit(&w) && strcmp(name->ext, ".accel") != 0)
        vkrt_cache_remove_others(VKRT_CACHE_SCENES, name->ext, w.path);
}
