/*
 * scene_cache.c: a loaded scene model kept in the cache directory (scene_cache.h).
 *
 * An entry "<key>.<where>.mesh" (where: a hash of the scene file's path, shared by its versions, of
 * which the cache keeps the latest) is a header (magic, key, counts, the world box, each section's
 * size and hash, and a hash of the header itself), then its sections in order: the text (the
 * loader's other inputs with their identities, the materials' strings, the warnings), the
 * materials' records (vkrt_material with its pointers zeroed), the instances, lights and cameras,
 * the embedded images (each its name and its encoded bytes), the meshes' table (counts, boxes, and each array's size and hash), then every mesh's arrays
 * exactly as vkrt_mesh holds them. The file's size must be the sum the header and the table
 * give: a truncated entry is found before an array is read.
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

/* "VKRTMDL" and the layout's version: a new layout gets a new number (it is in the key too), so
 * an entry of an older layout is never found, and is replaced by the next store. */
static const uint64_t MODEL_MAGIC = 0x334C444D54524B56ull; /* "VKRTMDL3", little-endian */
enum { LAYOUT_VERSION = 3 };

/* A scene file smaller than this whose model is smaller too loads in milliseconds: the cache
 * would only fill the disk. (A small .gltf may name buffers of a million triangles.) */
static const uint64_t MIN_SCENE_BYTES = 1u << 20;

enum { SECTION_TEXT, SECTION_MATERIALS, SECTION_INSTANCES, SECTION_LIGHTS, SECTION_CAMERAS,
       SECTION_IMAGES, SECTION_MESHES, SECTION_COUNT };

/* A mesh's arrays, in the order the entry holds them. */
enum { ARRAY_POSITIONS, ARRAY_NORMALS, ARRAY_TEXCOORDS, ARRAY_TANGENTS, ARRAY_MATERIAL,
       ARRAY_COUNT };

typedef struct model_header {
    uint64_t magic;
    uint64_t key[2];
    uint32_t mesh_count, instance_count, material_count, light_count, camera_count;
    uint32_t triangle_count, image_count, padding; /* padding: zero, the header is hashed */
    float bounds_min[3], bounds_max[3];
    uint64_t bytes[SECTION_COUNT];
    uint64_t hash[SECTION_COUNT];
    uint64_t header_hash; /* of everything above */
} model_header;

/* One mesh of the table section. */
typedef struct mesh_record {
    uint32_t triangle_count, padding;
    float bounds_min[3], bounds_max[3];
    uint64_t bytes[ARRAY_COUNT];
    uint64_t hash[ARRAY_COUNT];
} mesh_record;

/* The strings of a vkrt_material, in the order the text section holds them. */
enum { MATERIAL_STRINGS = 2 + VKRT_MAP_COUNT };
static void material_strings(vkrt_material *m, char **out[MATERIAL_STRINGS])
{
    out[0] = &m->name;
    out[1] = &m->file;
    for (int k = 0; k < VKRT_MAP_COUNT; ++k)
        out[2 + k] = &m->maps[k].path;
}

/* mesh's arrays and their sizes. */
static void mesh_arrays(vkrt_mesh *mesh, void **arrays[ARRAY_COUNT])
{
    arrays[ARRAY_POSITIONS] = (void **)&mesh->positions;
    arrays[ARRAY_NORMALS] = (void **)&mesh->normals;
    arrays[ARRAY_TEXCOORDS] = (void **)&mesh->texcoords;
    arrays[ARRAY_TANGENTS] = (void **)&mesh->tangents;
    arrays[ARRAY_MATERIAL] = (void **)&mesh->material;
}

/* The bytes an array of triangles takes where it is there. */
static uint64_t array_bytes(int a, uint32_t triangles)
{
    static const uint64_t per_triangle[ARRAY_COUNT] = {
        [ARRAY_POSITIONS] = 9 * sizeof(float), [ARRAY_NORMALS] = 9 * sizeof(float),
        [ARRAY_TEXCOORDS] = 6 * sizeof(float), [ARRAY_TANGENTS] = 12 * sizeof(float),
        [ARRAY_MATERIAL] = sizeof(int32_t),
    };
    return (uint64_t)triangles * per_triangle[a];
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

/* The key of the scene file at path with identity id as loader reads it: two hashes of one
 * description of them. */
static void key_of(const vkrt_scene_loader *loader, const vkrt_load_options *options,
                   const char *path, const vkrt_file_identity *id, uint64_t key[2])
{
    char where[8400], text[8900];
    where_of(path, where, sizeof where);
    int n = snprintf(text, sizeof text,
                     "vkrt scene cache layout %d, vkrt_material %zu bytes, instance %zu, light "
                     "%zu, camera %zu, program %016llx; loader %s, fps %a; %s, %llu bytes, mtime "
                     "%lld, hash %016llx",
                     LAYOUT_VERSION, sizeof(vkrt_material), sizeof(vkrt_instance),
                     sizeof(vkrt_config_light), sizeof(vkrt_config_camera),
                     (unsigned long long)vkrt_cache_program_id(), loader->name,
                     (double)options->fps, where,
                     (unsigned long long)id->size, (long long)id->mtime_ns,
                     (unsigned long long)id->hash);
    size_t size = n < 0 ? 0 : (size_t)n < sizeof text ? (size_t)n : sizeof text - 1;
    key[0] = vkrt_hash64(text, size, 0x243F6A8885A308D3ull);
    key[1] = vkrt_hash64(text, size, 0x13198A2E03707344ull);
}

/* The entry's extension, ".<16 hex digits of where path leads>.mesh": one scene file's versions
 * share it, and storing one removes the others (vkrt_cache_remove_others). */
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

/* The text section of model: each other input with its identity, then every material's strings
 * and the warnings. False when an input cannot be read for its identity. */
static bool text_of(const vkrt_model *model, blob *b)
{
    const char *files = model->inputs ? model->inputs : "";
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
    for (uint32_t i = 0; i < model->material_count; ++i) {
        char **fields[MATERIAL_STRINGS];
        material_strings(&model->materials[i], fields);
        for (int k = 0; k < MATERIAL_STRINGS; ++k)
            blob_put_string(b, *fields[k]);
    }
    blob_put_string(b, model->warnings);
    blob_put_string(b, model->warnings_all);
    blob_put_string(b, model->inputs);
    return !b->failed;
}

/* Reads the text section back into model (whose materials are already there, their strings
 * NULL); false when it is malformed or an input it lists has changed (why says which). */
static bool read_text(cursor *c, vkrt_model *model, const char **why)
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
            *why = "a file the scene file names changed";
            return false;
        }
    }
    for (uint32_t i = 0; i < model->material_count; ++i) {
        char **fields[MATERIAL_STRINGS];
        material_strings(&model->materials[i], fields);
        for (int k = 0; k < MATERIAL_STRINGS; ++k)
            *fields[k] = cursor_string(c);
    }
    char *warnings = cursor_string(c);
    if (warnings && strlen(warnings) < sizeof model->warnings)
        memcpy(model->warnings, warnings, strlen(warnings) + 1);
    else
        c->failed = true;
    free(warnings);
    model->warnings_all = cursor_string(c);
    model->inputs = cursor_string(c);
    if (c->failed || c->at != c->size) {
        *why = "a damaged entry";
        return false;
    }
    return true;
}

/* ---------------------------------------------------------------- the images section */

/* Each embedded image as its name (a string) and its bytes' count (uint64) and bytes. */
static bool images_of(const vkrt_model *model, blob *b)
{
    for (uint32_t i = 0; i < model->image_count; ++i) {
        const vkrt_image_blob *image = &model->images[i];
        uint64_t size = image->size;
        blob_put_string(b, image->name);
        blob_put(b, &size, sizeof size);
        blob_put(b, image->bytes, image->size);
    }
    return !b->failed;
}

/* Reads count images back into model->images; false when the section is malformed. */
static bool read_images(cursor *c, uint32_t count, vkrt_model *model)
{
    model->images = count ? calloc(count, sizeof *model->images) : NULL;
    if (count && !model->images)
        return false;
    model->image_count = count;
    for (uint32_t i = 0; i < count && !c->failed; ++i) {
        vkrt_image_blob *image = &model->images[i];
        uint64_t size = 0;
        image->name = cursor_string(c);
        cursor_get(c, &size, sizeof size);
        if (c->failed || !image->name || size == 0 || size > c->size - c->at)
            return false;
        image->bytes = malloc((size_t)size);
        if (!image->bytes)
            return false;
        cursor_get(c, image->bytes, (size_t)size);
        image->size = (size_t)size;
    }
    return !c->failed && c->at == c->size;
}

/* ---------------------------------------------------------------- load and store */

/* The bytes of each fixed section the header's counts imply (the text's and the images' aside;
 * the table is one record per mesh). */
static void section_bytes(const model_header *h, uint64_t bytes[SECTION_COUNT])
{
    bytes[SECTION_MATERIALS] = (uint64_t)h->material_count * sizeof(vkrt_material);
    bytes[SECTION_INSTANCES] = (uint64_t)h->instance_count * sizeof(vkrt_instance);
    bytes[SECTION_LIGHTS] = (uint64_t)h->light_count * sizeof(vkrt_config_light);
    bytes[SECTION_CAMERAS] = (uint64_t)h->camera_count * sizeof(vkrt_config_camera);
    bytes[SECTION_MESHES] = (uint64_t)h->mesh_count * sizeof(mesh_record);
}

/* Section s of h, the next in r, read and checked (vkrt_cache_reader_array). */
static void *read_section(vkrt_cache_reader *r, const model_header *h, int s)
{
    return vkrt_cache_reader_array(r, h->bytes[s], h->hash[s]);
}

/* Whether the mesh table's records are sound and, with the sections, make up exactly `size`
 * bytes of file. */
static bool table_ok(const model_header *h, const mesh_record *table, uint64_t size)
{
    uint64_t total = sizeof *h, triangles = 0;
    for (int s = 0; s < SECTION_COUNT; ++s)
        total += h->bytes[s];
    for (uint32_t i = 0; i < h->mesh_count; ++i) {
        const mesh_record *m = &table[i];
        if (m->triangle_count > UINT32_MAX / 9)
            return false;
        for (int a = 0; a < ARRAY_COUNT; ++a) {
            bool required = a == ARRAY_POSITIONS || a == ARRAY_MATERIAL;
            uint64_t want = array_bytes(a, m->triangle_count);
            if (m->bytes[a] != want && (required || m->bytes[a] != 0))
                return false;
            total += m->bytes[a];
        }
        triangles += m->triangle_count;
    }
    return triangles > 0 && total == size;
}

/* Fills *model from key's entry; false on any miss (why says what was wrong with an entry that
 * was there), with *model left empty. */
static bool load_entry(const uint64_t key[2], const char *ext, vkrt_model *model, const char **why)
{
    vkrt_cache_reader r;
    if (!vkrt_cache_reader_open(&r, VKRT_CACHE_SCENES, key, ext))
        return false;
    const char *reason = "a damaged entry";
    model_header h;
    uint64_t expected[SECTION_COUNT];
    vkrt_cache_reader_get(&r, &h, sizeof h);
    r.ok = r.ok && h.magic == MODEL_MAGIC && h.key[0] == key[0] && h.key[1] == key[1] &&
           vkrt_hash64(&h, offsetof(model_header, header_hash), 0) == h.header_hash &&
           h.mesh_count > 0 && h.instance_count > 0 && h.triangle_count > 0;
    if (r.ok) {
        section_bytes(&h, expected);
        for (int s = SECTION_MATERIALS; s < SECTION_COUNT; ++s)
            r.ok = r.ok && (s == SECTION_IMAGES || h.bytes[s] == expected[s]);
        r.ok = r.ok && h.bytes[SECTION_TEXT] < (1u << 30) &&
               h.bytes[SECTION_IMAGES] < (UINT64_C(1) << 36);
    }
    char *text = read_section(&r, &h, SECTION_TEXT);
    model->materials = read_section(&r, &h, SECTION_MATERIALS);
    if (r.ok) {
        model->material_count = h.material_count;
        for (uint32_t i = 0; i < model->material_count; ++i) {
            char **fields[MATERIAL_STRINGS];
            material_strings(&model->materials[i], fields);
            for (int k = 0; k < MATERIAL_STRINGS; ++k)
                *fields[k] = NULL;
        }
        cursor c = {text, (size_t)h.bytes[SECTION_TEXT], 0, false};
        r.ok = read_text(&c, model, &reason);
    }
    free(text);
    model->instances = read_section(&r, &h, SECTION_INSTANCES);
    model->lights = read_section(&r, &h, SECTION_LIGHTS);
    model->cameras = read_section(&r, &h, SECTION_CAMERAS);
    char *images = read_section(&r, &h, SECTION_IMAGES);
    if (r.ok) {
        cursor c = {images, (size_t)h.bytes[SECTION_IMAGES], 0, false};
        r.ok = read_images(&c, h.image_count, model);
    }
    free(images);
    mesh_record *table = read_section(&r, &h, SECTION_MESHES);
    r.ok = r.ok && table_ok(&h, table, r.size);
    if (r.ok) {
        model->meshes = calloc(h.mesh_count, sizeof *model->meshes);
        r.ok = model->meshes != NULL;
    }
    if (r.ok)
        model->mesh_count = h.mesh_count;
    /* The arrays last: a stale input is found before hundreds of MB are read. */
    for (uint32_t i = 0; r.ok && i < h.mesh_count; ++i) {
        vkrt_mesh *mesh = &model->meshes[i];
        void **arrays[ARRAY_COUNT];
        mesh_arrays(mesh, arrays);
        for (int a = 0; a < ARRAY_COUNT; ++a)
            *arrays[a] = vkrt_cache_reader_array(&r, table[i].bytes[a], table[i].hash[a]);
        mesh->triangle_count = table[i].triangle_count;
        memcpy(mesh->bounds_min, table[i].bounds_min, sizeof mesh->bounds_min);
        memcpy(mesh->bounds_max, table[i].bounds_max, sizeof mesh->bounds_max);
    }
    free(table);
    vkrt_cache_reader_close(&r);
    if (r.ok) {
        model->instance_count = h.instance_count;
        model->light_count = h.light_count;
        model->camera_count = h.camera_count;
        vkrt_error err = {{0}};
        r.ok = vkrt_model_finish(model, &err) && model->triangle_count == h.triangle_count &&
               memcmp(model->bounds_min, h.bounds_min, sizeof h.bounds_min) == 0 &&
               memcmp(model->bounds_max, h.bounds_max, sizeof h.bounds_max) == 0;
    }
    if (!r.ok) {
        *why = reason;
        vkrt_model_free(model);
        return false;
    }
    return true;
}

/* Writes model under key, in place of the scene file's older versions; false (with why) when it
 * is not stored. */
static bool store_entry(const uint64_t key[2], const char *ext, const vkrt_model *model,
                        const char **why)
{
    blob text = {0}, images = {0};
    if (!text_of(model, &text) || !images_of(model, &images)) {
        *why = text.failed || images.failed ? "out of memory"
                                            : "a file the scene file names could not be read again";
        free(text.data);
        free(images.data);
        return false;
    }
    size_t material_bytes = (size_t)model->material_count * sizeof(vkrt_material);
    vkrt_material *records = material_bytes ? malloc(material_bytes) : NULL;
    mesh_record *table = calloc(model->mesh_count ? model->mesh_count : 1, sizeof *table);
    if ((material_bytes && !records) || !table) {
        free(records);
        free(table);
        free(text.data);
        free(images.data);
        *why = "out of memory";
        return false;
    }
    for (uint32_t i = 0; i < model->material_count; ++i) {
        /* Byte for byte, padding included (zeroed by vkrt_material_defaults): the entry's hash
         * covers it. */
        memcpy(&records[i], &model->materials[i], sizeof records[i]);
        char **fields[MATERIAL_STRINGS];
        material_strings(&records[i], fields);
        for (int k = 0; k < MATERIAL_STRINGS; ++k)
            *fields[k] = NULL;
    }
    for (uint32_t i = 0; i < model->mesh_count; ++i) {
        vkrt_mesh *mesh = &model->meshes[i];
        void **arrays[ARRAY_COUNT];
        mesh_arrays(mesh, arrays);
        table[i].triangle_count = mesh->triangle_count;
        memcpy(table[i].bounds_min, mesh->bounds_min, sizeof mesh->bounds_min);
        memcpy(table[i].bounds_max, mesh->bounds_max, sizeof mesh->bounds_max);
        for (int a = 0; a < ARRAY_COUNT; ++a) {
            table[i].bytes[a] = *arrays[a] ? array_bytes(a, mesh->triangle_count) : 0;
            table[i].hash[a] =
                table[i].bytes[a] ? vkrt_hash64_parallel(*arrays[a], table[i].bytes[a]) : 0;
        }
    }
    const void *sections[SECTION_COUNT] = {text.data,      records,     model->instances,
                                           model->lights,  model->cameras, images.data,
                                           table};
    model_header h = {
        .magic = MODEL_MAGIC,
        .key = {key[0], key[1]},
        .mesh_count = model->mesh_count,
        .instance_count = model->instance_count,
        .material_count = model->material_count,
        .light_count = model->light_count,
        .camera_count = model->camera_count,
        .triangle_count = model->triangle_count,
        .image_count = model->image_count,
    };
    memcpy(h.bounds_min, model->bounds_min, sizeof h.bounds_min);
    memcpy(h.bounds_max, model->bounds_max, sizeof h.bounds_max);
    section_bytes(&h, h.bytes);
    h.bytes[SECTION_TEXT] = text.size;
    h.bytes[SECTION_IMAGES] = images.size;
    for (int s = 0; s < SECTION_COUNT; ++s)
        h.hash[s] = h.bytes[s] ? vkrt_hash64_parallel(sections[s], (size_t)h.bytes[s]) : 0;
    h.header_hash = vkrt_hash64(&h, offsetof(model_header, header_hash), 0);
    vkrt_cache_writer w;
    bool stored = false;
    if (vkrt_cache_writer_open(&w, VKRT_CACHE_SCENES, "scene cache", key, ext)) {
        vkrt_cache_writer_put(&w, &h, sizeof h);
        for (int s = 0; s < SECTION_COUNT; ++s)
            vkrt_cache_writer_put(&w, sections[s], (size_t)h.bytes[s]);
        for (uint32_t i = 0; i < model->mesh_count; ++i) {
            void **arrays[ARRAY_COUNT];
            mesh_arrays(&model->meshes[i], arrays);
            for (int a = 0; a < ARRAY_COUNT; ++a)
                vkrt_cache_writer_put(&w, *arrays[a], (size_t)table[i].bytes[a]);
        }
        stored = vkrt_cache_writer_commit(&w);
    }
    if (stored)
        vkrt_cache_remove_others(VKRT_CACHE_SCENES, ext, w.path);
    if (!stored)
        *why = "the cache could not be written";
    free(records);
    free(table);
    free(text.data);
    free(images.data);
    return stored;
}

static bool same_file(const vkrt_file_identity *a, const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && (uint64_t)st.st_size == a->size &&
           (int64_t)st.st_mtim.tv_sec * 1000000000 + st.st_mtim.tv_nsec == a->mtime_ns;
}

/* An entry written on a thread (vkrt_scene_cache_load with a report). */
struct scene_cache_store {
    pthread_t thread;
    uint64_t key[2];
    char ext[32];
    const vkrt_model *model;
    bool stored;
    const char *why;
    double ms;
};

static void *store_thread(void *arg)
{
    struct scene_cache_store *st = arg;
    double start = vkrt_clock_ms();
    st->why = "";
    st->stored = store_entry(st->key, st->ext, st->model, &st->why);
    st->ms = vkrt_clock_ms() - start;
    return NULL;
}

/* Starts the store on a thread; false (nothing started) when no thread could be made. */
static bool store_in_background(const uint64_t key[2], const char *ext, const vkrt_model *model,
                                vkrt_scene_cache_report *report)
{
    struct scene_cache_store *st = calloc(1, sizeof *st);
    if (!st)
        return false;
    st->key[0] = key[0];
    st->key[1] = key[1];
    snprintf(st->ext, sizeof st->ext, "%s", ext);
    st->model = model;
    if (pthread_create(&st->thread, NULL, store_thread, st) != 0) {
        free(st);
        return false;
    }
    report->outcome = VKRT_SCENE_CACHE_STORING;
    report->store = st;
    return true;
}

bool vkrt_scene_cache_load(const vkrt_scene_loader *loader, const char *path,
                           const vkrt_load_options *options, vkrt_model *model,
                           vkrt_scene_cache_report *report, vkrt_error *err)
{
    vkrt_load_options resolved = vkrt_load_options_resolve(options);
    vkrt_scene_cache_report own;
    if (!report)
        report = &own;
    *report = (vkrt_scene_cache_report){.outcome = VKRT_SCENE_CACHE_OFF, .why = "", .rejected = ""};
    char dir[4096];
    vkrt_file_identity id;
    uint64_t key[2];
    char ext[32];
    double start = vkrt_clock_ms();
    bool cached = path && model && vkrt_cache_dir(VKRT_CACHE_SCENES, dir, sizeof dir) &&
                  vkrt_file_identity_of(path, &id);
    report->hash_ms = vkrt_clock_ms() - start;
    if (cached) {
        key_of(loader, &resolved, path, &id, key);
        extension_of(path, ext);
        memset(model, 0, sizeof *model);
        start = vkrt_clock_ms();
        if (load_entry(key, ext, model, &report->rejected)) {
            report->read_ms = vkrt_clock_ms() - start;
            report->outcome = VKRT_SCENE_CACHE_HIT;
            return true;
        }
    }
    if (!loader->load(path, &resolved, model, err))
        return false;
    if (!cached)
        return true;
    report->outcome = VKRT_SCENE_CACHE_SKIPPED;
    if (id.size < MIN_SCENE_BYTES && vkrt_model_host_bytes(model) < (double)MIN_SCENE_BYTES)
        report->why = "a scene file under 1 MiB";
    else if (model->inputs_missing)
        report->why = "the scene file names a file not found";
    else if (!same_file(&id, path))
        report->why = "the scene file changed while it was read";
    else if (report == &own || !store_in_background(key, ext, model, report)) {
        start = vkrt_clock_ms();
        if (store_entry(key, ext, model, &report->why))
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
