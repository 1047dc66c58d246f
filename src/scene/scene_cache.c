/*
 * scene_cache.c: an OBJ's mesh kept in the cache directory (scene_cache.h).
 *
 * An entry "<key>.<where>.mesh" (where: a hash of the OBJ's path, shared by its versions, of which
 * the cache keeps the latest) is a header (magic, key, counts, bounds, each section's size and hash,
 * and a hash of the header itself), then its sections in order: the text (the .mtl files read
 * with their identities, the materials' strings, the warnings), the materials' records (vkrt_mtl
 * with its pointers zeroed), then the per-triangle arrays exactly as vkrt_mesh holds them. The
 * file's size must be the header's sum: a truncated entry is found before anything is read.
 */
#define _POSIX_C_SOURCE 200809L
#include "scene_cache.h"

#include <pthread.h>

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "../cache_file.h"
#include "../clock.h"

/* "VKRTMSH" and the layout's version: a new layout gets a new number (it is in the key too). */
static const uint64_t MESH_MAGIC = 0x3148534D54524B56ull; /* "VKRTMSH1", little-endian */
enum { LAYOUT_VERSION = 1 };

/* An OBJ smaller than this parses in milliseconds: the cache would only fill the disk. */
static const uint64_t MIN_OBJ_BYTES = 1u << 20;

enum { SECTION_TEXT, SECTION_MATERIALS, SECTION_POSITIONS, SECTION_NORMALS, SECTION_TEXCOORDS,
       SECTION_MATERIAL, SECTION_COUNT };

typedef struct mesh_header {
    uint64_t magic;
    uint64_t key[2];
    uint32_t triangle_count, material_count;
    uint32_t has_normals, has_texcoords;
    float bounds_min[3], bounds_max[3];
    uint64_t bytes[SECTION_COUNT];
    uint64_t hash[SECTION_COUNT];
    uint64_t header_hash; /* of everything above */
} mesh_header;

/* The strings of a vkrt_mtl, in the order the text section holds them. */
enum { MTL_STRINGS = 9 };
static void mtl_strings(vkrt_mtl *m, char **out[MTL_STRINGS])
{
    char **fields[MTL_STRINGS] = {&m->name,   &m->map_kd, &m->map_d,    &m->mtl_path, &m->map_pr,
                                  &m->map_pm, &m->norm,   &m->map_bump, &m->map_ke};
    memcpy(out, fields, sizeof fields);
}

/* ---------------------------------------------------------------- the key */

/* Where path leads: the path, and the working folder when it is relative (texture paths are
 * resolved against it). */
static void where_of(const char *path, char *text, size_t size)
{
    char cwd[4096] = "";
    if (path[0] != '/' && !getcwd(cwd, sizeof cwd))
        cwd[0] = '\0';
    snprintf(text, size, "in %s: %s", cwd, path);
}

/* The key of the OBJ at path with identity id: two hashes of one description of it. */
static void key_of(const char *path, const vkrt_file_identity *id, uint64_t key[2])
{
    char where[8400], text[8800];
    where_of(path, where, sizeof where);
    int n = snprintf(text, sizeof text,
                     "vkrt mesh layout %d, vkrt_mtl %zu bytes, program %016llx; %s, %llu bytes, "
                     "mtime %lld, hash %016llx",
                     LAYOUT_VERSION, sizeof(vkrt_mtl), (unsigned long long)vkrt_cache_program_id(),
                     where, (unsigned long long)id->size, (long long)id->mtime_ns,
                     (unsigned long long)id->hash);
    size_t size = n < 0 ? 0 : (size_t)n < sizeof text ? (size_t)n : sizeof text - 1;
    key[0] = vkrt_hash64(text, size, 0x243F6A8885A308D3ull);
    key[1] = vkrt_hash64(text, size, 0x13198A2E03707344ull);
}

/* The entry's extension, ".<16 hex digits of where path leads>.mesh": one OBJ's versions share
 * it, and storing one removes the others (vkrt_cache_remove_others). */
static void extension_of(const char *path, char ext[32])
{
    char where[8400];
    where_of(path, where, sizeof where);
    snprintf(ext, 32, ".%016llx.mesh",
             (unsigned long long)vkrt_hash64(where, strlen(where), 0x452821E638D01377ull));
}

/* ---------------------------------------------------------------- the text section */

typedef struct blob {
    char *data;
    size_t size, capacity;
    bool failed;
} blob;

static void blob_put(blob *b, const void *data, size_t size)
{
    if (b->failed)
        return;
    if (b->size + size > b->capacity) {
        size_t capacity = (b->size + size) * 2 + 256;
        char *grown = realloc(b->data, capacity);
        if (!grown) {
            b->failed = true;
            return;
        }
        b->data = grown;
        b->capacity = capacity;
    }
    memcpy(b->data + b->size, data, size);
    b->size += size;
}

/* A string as its length (UINT32_MAX for NULL) and its bytes. */
static void blob_put_string(blob *b, const char *s)
{
    uint32_t length = s ? (uint32_t)strlen(s) : UINT32_MAX;
    blob_put(b, &length, sizeof length);
    if (s)
        blob_put(b, s, length);
}

/* A cursor over a text section read back; any read past its end sets failed. */
typedef struct cursor {
    const char *data;
    size_t size, at;
    bool failed;
} cursor;

static void cursor_get(cursor *c, void *dst, size_t size)
{
    if (c->failed || size > c->size - c->at) {
        c->failed = true;
        memset(dst, 0, size);
        return;
    }
    memcpy(dst, c->data + c->at, size);
    c->at += size;
}

/* The next string, malloc'd (NULL for a stored NULL, or on failure). */
static char *cursor_string(cursor *c)
{
    uint32_t length;
    cursor_get(c, &length, sizeof length);
    if (c->failed || length == UINT32_MAX)
        return NULL;
    if (length > c->size - c->at) {
        c->failed = true;
        return NULL;
    }
    char *s = malloc((size_t)length + 1);
    if (!s) {
        c->failed = true;
        return NULL;
    }
    memcpy(s, c->data + c->at, length);
    s[length] = '\0';
    c->at += length;
    return s;
}

/* The text section of mesh: each .mtl file read with its identity, then every material's strings
 * and the warnings. False when a .mtl cannot be read for its identity. */
static bool text_of(const vkrt_mesh *mesh, blob *b)
{
    const char *files = mesh->mtl_files ? mesh->mtl_files : "";
    uint32_t file_count = 0;
    for (const char *p = files; *p; p = strchr(p, '\n') + 1)
        ++file_count;
    blob_put(b, &file_count, sizeof file_count);
    for (const char *p = files; *p; p = strchr(p, '\n') + 1) {
        char path[4096];
        size_t length = strcspn(p, "\n");
        if (length >= sizeof path)
            return false;
        memcpy(path, p, length);
        path[length] = '\0';
        vkrt_file_identity id;
        if (!vkrt_file_identity_of(path, &id))
            return false;
        blob_put_string(b, path);
        blob_put(b, &id, sizeof id);
    }
    for (uint32_t i = 0; i < mesh->material_count; ++i) {
        char **fields[MTL_STRINGS];
        mtl_strings(&mesh->materials[i], fields);
        for (int k = 0; k < MTL_STRINGS; ++k)
            blob_put_string(b, *fields[k]);
    }
    blob_put_string(b, mesh->warnings);
    blob_put_string(b, mesh->warnings_all);
    blob_put_string(b, mesh->mtl_files);
    return !b->failed;
}

/* Reads the text section back into mesh (whose materials are already there, their strings
 * NULL); false when it is malformed or a .mtl it lists has changed (why says which). */
static bool read_text(cursor *c, vkrt_mesh *mesh, const char **why)
{
    uint32_t file_count = 0;
    cursor_get(c, &file_count, sizeof file_count);
    for (uint32_t i = 0; i < file_count && !c->failed; ++i) {
        char *path = cursor_string(c);
        vkrt_file_identity stored, now;
        cursor_get(c, &stored, sizeof stored);
        bool same = path && !c->failed && vkrt_file_identity_of(path, &now) &&
                    now.size == stored.size && now.mtime_ns == stored.mtime_ns &&
                    now.hash == stored.hash;
        free(path);
        if (!c->failed && !same) {
            *why = "a .mtl file changed";
            return false;
        }
    }
    for (uint32_t i = 0; i < mesh->material_count; ++i) {
        char **fields[MTL_STRINGS];
        mtl_strings(&mesh->materials[i], fields);
        for (int k = 0; k < MTL_STRINGS; ++k)
            *fields[k] = cursor_string(c);
    }
    char *warnings = cursor_string(c);
    if (warnings && strlen(warnings) < sizeof mesh->warnings)
        memcpy(mesh->warnings, warnings, strlen(warnings) + 1);
    else
        c->failed = true;
    free(warnings);
    mesh->warnings_all = cursor_string(c);
    mesh->mtl_files = cursor_string(c);
    if (c->failed || c->at != c->size) {
        *why = "a damaged entry";
        return false;
    }
    return true;
}

/* ---------------------------------------------------------------- load and store */

/* The bytes of each section mesh's counts imply (the text's aside). */
static void array_bytes(uint32_t triangles, uint32_t materials, bool normals, bool texcoords,
                        uint64_t bytes[SECTION_COUNT])
{
    bytes[SECTION_MATERIALS] = (uint64_t)materials * sizeof(vkrt_mtl);
    bytes[SECTION_POSITIONS] = (uint64_t)triangles * 9 * sizeof(float);
    bytes[SECTION_NORMALS] = normals ? (uint64_t)triangles * 9 * sizeof(float) : 0;
    bytes[SECTION_TEXCOORDS] = texcoords ? (uint64_t)triangles * 6 * sizeof(float) : 0;
    bytes[SECTION_MATERIAL] = (uint64_t)triangles * sizeof(int32_t);
}

/* Section s of h, the next in r, read and checked (vkrt_cache_reader_array). */
static void *read_section(vkrt_cache_reader *r, const mesh_header *h, int s)
{
    return vkrt_cache_reader_array(r, h->bytes[s], h->hash[s]);
}

/* Fills *mesh from key's entry; false on any miss (why says what was wrong with an entry that
 * was there), with *mesh left empty. */
static bool load_entry(const uint64_t key[2], const char *ext, vkrt_mesh *mesh, const char **why)
{
    vkrt_cache_reader r;
    if (!vkrt_cache_reader_open(&r, VKRT_CACHE_SCENES, key, ext))
        return false;
    const char *reason = "a damaged entry";
    mesh_header h;
    uint64_t expected[SECTION_COUNT];
    vkrt_cache_reader_get(&r, &h, sizeof h);
    r.ok = r.ok && h.magic == MESH_MAGIC && h.key[0] == key[0] && h.key[1] == key[1] &&
           vkrt_hash64(&h, offsetof(mesh_header, header_hash), 0) == h.header_hash &&
           h.triangle_count > 0 && h.triangle_count <= UINT32_MAX / 9;
    if (r.ok) {
        array_bytes(h.triangle_count, h.material_count, h.has_normals, h.has_texcoords, expected);
        uint64_t total = sizeof h + h.bytes[SECTION_TEXT];
        for (int s = SECTION_MATERIALS; s < SECTION_COUNT; ++s) {
            r.ok = r.ok && h.bytes[s] == expected[s];
            total += h.bytes[s];
        }
        r.ok = r.ok && h.bytes[SECTION_TEXT] < (1u << 30) && total == r.size;
    }
    char *text = read_section(&r, &h, SECTION_TEXT);
    mesh->materials = read_section(&r, &h, SECTION_MATERIALS);
    if (r.ok) {
        mesh->material_count = h.material_count;
        for (uint32_t i = 0; i < mesh->material_count; ++i) {
            char **fields[MTL_STRINGS];
            mtl_strings(&mesh->materials[i], fields);
            for (int k = 0; k < MTL_STRINGS; ++k)
                *fields[k] = NULL;
        }
        cursor c = {text, (size_t)h.bytes[SECTION_TEXT], 0, false};
        r.ok = read_text(&c, mesh, &reason);
    }
    free(text);
    /* The arrays last: a stale .mtl is found before hundreds of MB are read. */
    mesh->positions = read_section(&r, &h, SECTION_POSITIONS);
    mesh->normals = read_section(&r, &h, SECTION_NORMALS);
    mesh->texcoords = read_section(&r, &h, SECTION_TEXCOORDS);
    mesh->material = read_section(&r, &h, SECTION_MATERIAL);
    vkrt_cache_reader_close(&r);
    if (!r.ok) {
        *why = reason;
        vkrt_mesh_free(mesh);
        return false;
    }
    mesh->triangle_count = h.triangle_count;
    memcpy(mesh->bounds_min, h.bounds_min, sizeof h.bounds_min);
    memcpy(mesh->bounds_max, h.bounds_max, sizeof h.bounds_max);
    return true;
}

/* Writes mesh under key, in place of the OBJ's older versions; false (with why) when it is not
 * stored. */
static bool store_entry(const uint64_t key[2], const char *ext, const vkrt_mesh *mesh,
                        const char **why)
{
    blob text = {0};
    if (!text_of(mesh, &text)) {
        free(text.data);
        *why = "a .mtl file could not be read again";
        return false;
    }
    size_t material_bytes = (size_t)mesh->material_count * sizeof(vkrt_mtl);
    vkrt_mtl *records = material_bytes ? malloc(material_bytes) : NULL;
    if (material_bytes && !records) {
        free(text.data);
        *why = "out of memory";
        return false;
    }
    for (uint32_t i = 0; i < mesh->material_count; ++i) {
        /* Byte for byte, padding included (calloc'd by the loader): the entry's hash covers it. */
        memcpy(&records[i], &mesh->materials[i], sizeof records[i]);
        char **fields[MTL_STRINGS];
        mtl_strings(&records[i], fields);
        for (int k = 0; k < MTL_STRINGS; ++k)
            *fields[k] = NULL;
    }
    const void *sections[SECTION_COUNT] = {text.data,       records,         mesh->positions,
                                           mesh->normals,   mesh->texcoords, mesh->material};
    mesh_header h = {
        .magic = MESH_MAGIC,
        .key = {key[0], key[1]},
        .triangle_count = mesh->triangle_count,
        .material_count = mesh->material_count,
        .has_normals = mesh->normals != NULL,
        .has_texcoords = mesh->texcoords != NULL,
    };
    memcpy(h.bounds_min, mesh->bounds_min, sizeof h.bounds_min);
    memcpy(h.bounds_max, mesh->bounds_max, sizeof h.bounds_max);
    array_bytes(h.triangle_count, h.material_count, h.has_normals, h.has_texcoords, h.bytes);
    h.bytes[SECTION_TEXT] = text.size;
    for (int s = 0; s < SECTION_COUNT; ++s)
        h.hash[s] = h.bytes[s] ? vkrt_hash64_parallel(sections[s], (size_t)h.bytes[s]) : 0;
    h.header_hash = vkrt_hash64(&h, offsetof(mesh_header, header_hash), 0);
    vkrt_cache_writer w;
    bool stored = false;
    if (vkrt_cache_writer_open(&w, VKRT_CACHE_SCENES, "scene cache", key, ext)) {
        vkrt_cache_writer_put(&w, &h, sizeof h);
        for (int s = 0; s < SECTION_COUNT; ++s)
            vkrt_cache_writer_put(&w, sections[s], (size_t)h.bytes[s]);
        stored = vkrt_cache_writer_commit(&w);
    }
    if (stored)
        vkrt_cache_remove_others(VKRT_CACHE_SCENES, ext, w.path);
    if (!stored)
        *why = "the cache could not be written";
    free(records);
    free(text.data);
    return stored;
}

static bool same_file(const vkrt_file_identity *a, const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && (uint64_t)st.st_size == a->size &&
           (int64_t)st.st_mtim.tv_sec * 1000000000 + st.st_mtim.tv_nsec == a->mtime_ns;
}

/* An entry written on a thread (vkrt_scene_cache_obj_load with a report). */
struct scene_cache_store {
    pthread_t thread;
    uint64_t key[2];
    char ext[32];
    const vkrt_mesh *mesh;
    bool stored;
    const char *why;
    double ms;
};

static void *store_thread(void *arg)
{
    struct scene_cache_store *st = arg;
    double start = vkrt_clock_ms();
    st->why = "";
    st->stored = store_entry(st->key, st->ext, st->mesh, &st->why);
    st->ms = vkrt_clock_ms() - start;
    return NULL;
}

/* Starts the store on a thread; false (nothing started) when no thread could be made. */
static bool store_in_background(const uint64_t key[2], const char *ext, const vkrt_mesh *mesh,
                                vkrt_scene_cache_report *report)
{
    struct scene_cache_store *st = calloc(1, sizeof *st);
    if (!st)
        return false;
    st->key[0] = key[0];
    st->key[1] = key[1];
    snprintf(st->ext, sizeof st->ext, "%s", ext);
    st->mesh = mesh;
    if (pthread_create(&st->thread, NULL, store_thread, st) != 0) {
        free(st);
        return false;
    }
    report->outcome = VKRT_SCENE_CACHE_STORING;
    report->store = st;
    return true;
}

bool vkrt_scene_cache_obj_load(const char *path, vkrt_mesh *mesh,
                               vkrt_scene_cache_report *report, vkrt_error *err)
{
    vkrt_scene_cache_report own;
    if (!report)
        report = &own;
    *report = (vkrt_scene_cache_report){.outcome = VKRT_SCENE_CACHE_OFF, .why = "", .rejected = ""};
    char dir[4096];
    vkrt_file_identity id;
    uint64_t key[2];
    char ext[32];
    double start = vkrt_clock_ms();
    bool cached = path && mesh && vkrt_cache_dir(VKRT_CACHE_SCENES, dir, sizeof dir) &&
                  vkrt_file_identity_of(path, &id);
    report->hash_ms = vkrt_clock_ms() - start;
    if (cached) {
        key_of(path, &id, key);
        extension_of(path, ext);
        memset(mesh, 0, sizeof *mesh);
        start = vkrt_clock_ms();
        if (load_entry(key, ext, mesh, &report->rejected)) {
            report->read_ms = vkrt_clock_ms() - start;
            report->outcome = VKRT_SCENE_CACHE_HIT;
            return true;
        }
    }
    if (!vkrt_obj_load(path, mesh, err))
        return false;
    if (!cached)
        return true;
    report->outcome = VKRT_SCENE_CACHE_SKIPPED;
    if (id.size < MIN_OBJ_BYTES)
        report->why = "an OBJ under 1 MiB";
    else if (mesh->mtl_missing)
        report->why = "an mtllib names a file not found";
    else if (!same_file(&id, path))
        report->why = "the OBJ changed while it was read";
    else if (report == &own || !store_in_background(key, ext, mesh, report)) {
        start = vkrt_clock_ms();
        if (store_entry(key, ext, mesh, &report->why))
            report->outcome = VKRT_SCENE_CACHE_STORED;
        report->store_ms = vkrt_clock_ms() - start;
    }
    return true;
}

void vkrt_scene_cache_finish(vkrt_scene_cache_report *report)
{
    struct scene_cache_store *st = report->store;
    if (!st)
        return;
    pthread_join(st->thread, NULL);
    report->outcome = st->stored ? VKRT_SCENE_CACHE_STORED : VKRT_SCENE_CACHE_SKIPPED;
    report->why = st->why;
    report->store_ms = st->ms;
    report->store = NULL;
    free(st);
}
