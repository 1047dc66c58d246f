/*
 * spirv_cache.c: compiled kernels kept on disk (spirv_cache.h).
 *
 * A file is "<32 hex digits of the key>.spv": a header (the format's magic, the key again and the
 * word count), the SPIR-V words, then a 64-bit hash of those words, so that a truncated or
 * damaged file is a miss rather than a kernel the driver chokes on. The driver's pipeline cache
 * data (pipeline.c) is kept the same way in "<key>.vkpc": a header (its own magic, the key and the
 * byte count), the bytes, their hash.
 */
#define _POSIX_C_SOURCE 200809L
#include "spirv_cache.h"

#include "../cache_file.h"

#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <glslang/build_info.h>

#ifndef VKRT_VERSION
#define VKRT_VERSION "unknown"
#endif

/* "VKRTSPV" and the file format's version: a new layout gets a new number. */
static const uint64_t FILE_MAGIC = 0x31565053544B5256ull; /* "VKRTSPV1", little-endian */
static const uint32_t SPIRV_MAGIC = 0x07230203u;
/* Larger than any kernel vkrt compiles (the biggest are about 100k words), so a corrupt count
 * cannot ask for gigabytes. */
static const uint64_t MAX_WORDS = 1u << 24;

typedef struct file_header {
    uint64_t magic;
    uint64_t key[2];
    uint64_t word_count; /* bytes, in a .vkpc file */
} file_header;

/* "VKRTPCD" and its version; a pipeline cache bigger than MAX_BYTES is not kept. */
static const uint64_t BYTES_MAGIC = 0x3144435054524B56ull; /* "VKRTPCD1", little-endian */
static const uint64_t MAX_BYTES = 1u << 26;

static _Atomic uint32_t loaded_count, compiled_count, stored_count;

/* FNV-1a over bytes, from a given basis; 64 bits. */
static uint64_t fnv1a(const void *data, size_t size, uint64_t h)
{
    const unsigned char *p = data;
    for (size_t i = 0; i < size; ++i) {
        h ^= p[i];
        h *= 0x100000001B3ull;
    }
    return h;
}

/* A second, unrelated 64-bit hash: each 8-byte block mixed by the murmur3 finaliser and folded
 * in with a multiply-rotate, so that the two halves of a key do not fail together. */
static uint64_t mix64(uint64_t x)
{
    x ^= x >> 33;
    x *= 0xFF51AFD7ED558CCDull;
    x ^= x >> 33;
    x *= 0xC4CEB9FE1A85EC53ull;
    x ^= x >> 33;
    return x;
}

static uint64_t block_hash(const void *data, size_t size, uint64_t h)
{
    const unsigned char *p = data;
    for (size_t i = 0; i < size; i += 8) {
        uint64_t block = 0;
        size_t n = size - i < 8 ? size - i : 8;
        memcpy(&block, p + i, n);
        h = mix64(h ^ block ^ ((uint64_t)n << 56));
        h = (h << 27 | h >> 37) * 0x9E3779B97F4A7C15ull;
    }
    return mix64(h ^ size);
}

gpu_spirv_key gpu_spirv_key_of(const char *text, uint32_t target)
{
    char versions[128];
    int n = snprintf(versions, sizeof versions, "vkrt %s glslang %d.%d.%d%s target %u",
                     VKRT_VERSION, GLSLANG_VERSION_MAJOR, GLSLANG_VERSION_MINOR,
                     GLSLANG_VERSION_PATCH, GLSLANG_VERSION_FLAVOR, (unsigned)target);
    size_t length = strlen(text);
    gpu_spirv_key key;
    key.h[0] = fnv1a(text, length, fnv1a(versions, (size_t)n, 0xCBF29CE484222325ull));
    key.h[1] = block_hash(text, length, block_hash(versions, (size_t)n, 0x243F6A8885A308D3ull));
    return key;
}

void gpu_spirv_cache_disable(void)
{
    vkrt_cache_disable();
}

bool gpu_spirv_cache_dir(char *dir, size_t dir_size)
{
    return vkrt_cache_dir(VKRT_CACHE_KERNELS, dir, dir_size);
}

gpu_spirv_key gpu_spirv_key_of_bytes(const void *data, size_t size)
{
    gpu_spirv_key key = {
        {fnv1a(data, size, 0xCBF29CE484222325ull), block_hash(data, size, 0x243F6A8885A308D3ull)}};
    return key;
}

/* Reads key's file with extension ext: its header (magic, the key, count units of unit bytes,
 * 0 < count <= max) and data, whose hash must match. *data is malloc'd; false on any miss. */
static bool load_entry(const gpu_spirv_key *key, const char *ext, uint64_t magic, size_t unit,
                       uint64_t max, void **data, uint64_t *count)
{
    *data = NULL;
    *count = 0;
    char path[4200];
    if (!vkrt_cache_entry_path(VKRT_CACHE_KERNELS, key->h, ext, path, sizeof path))
        return false;
    FILE *f = fopen(path, "rb");
    if (!f)
        return false;
    file_header h;
    unsigned char *bytes = NULL;
    uint64_t stored_hash = 0;
    bool ok = fread(&h, sizeof h, 1, f) == 1 && h.magic == magic && h.key[0] == key->h[0] &&
              h.key[1] == key->h[1] && h.word_count > 0 && h.word_count <= max;
    size_t size = ok ? (size_t)h.word_count * unit : 0;
    if (ok) {
        bytes = malloc(size);
        ok = bytes && fread(bytes, 1, size, f) == size &&
             fread(&stored_hash, sizeof stored_hash, 1, f) == 1 && fgetc(f) == EOF &&
             block_hash(bytes, size, 0) == stored_hash;
    }
    fclose(f);
    if (!ok) {
        free(bytes);
        return false;
    }
    *data = bytes;
    *count = h.word_count;
    return true;
}

bool gpu_spirv_cache_load(const gpu_spirv_key *key, uint32_t **spirv, size_t *word_count)
{
    void *data;
    uint64_t count;
    *spirv = NULL;
    *word_count = 0;
    if (!load_entry(key, ".spv", FILE_MAGIC, sizeof **spirv, MAX_WORDS, &data, &count))
        return false;
    uint32_t *words = data;
    if (count <= 5 || words[0] != SPIRV_MAGIC) {
        free(data);
        return false;
    }
    *spirv = words;
    *word_count = (size_t)count;
    atomic_fetch_add(&loaded_count, 1u);
    return true;
}

/* Writes the header, size bytes of data and their hash to key's file with extension ext, whole
 * under a temporary name and then renamed; best effort, and silent: a kernel is small and
 * compiled again next time. Returns whether the entry is on disk. */
static bool store_entry(const gpu_spirv_key *key, const char *ext, const file_header *h,
                        const void *data, size_t size)
{
    vkrt_cache_writer w;
    if (!vkrt_cache_writer_open(&w, VKRT_CACHE_KERNELS, NULL, key->h, ext))
        return false;
    uint64_t hash = block_hash(data, size, 0);
    vkrt_cache_writer_put(&w, h, sizeof *h);
    vkrt_cache_writer_put(&w, data, size);
    vkrt_cache_writer_put(&w, &hash, sizeof hash);
    return vkrt_cache_writer_commit(&w);
}

bool gpu_spirv_cache_store(const gpu_spirv_key *key, const uint32_t *spirv, size_t word_count)
{
    if (word_count > MAX_WORDS)
        return false;
    file_header h = {FILE_MAGIC, {key->h[0], key->h[1]}, word_count};
    bool stored = store_entry(key, ".spv", &h, spirv, word_count * sizeof *spirv);
    if (stored)
        atomic_fetch_add(&stored_count, 1u);
    return stored;
}

bool gpu_spirv_cache_store_bytes(const gpu_spirv_key *key, const void *data, size_t size)
{
    if (size == 0 || size > MAX_BYTES)
        return false;
    file_header h = {BYTES_MAGIC, {key->h[0], key->h[1]}, size};
    return store_entry(key, ".vkpc", &h, data, size);
}

bool gpu_spirv_cache_load_bytes(const gpu_spirv_key *key, void **data, size_t *size)
{
    uint64_t count;
    bool ok = load_entry(key, ".vkpc", BYTES_MAGIC, 1, MAX_BYTES, data, &count);
    *size = ok ? (size_t)count : 0;
    return ok;
}

void gpu_spirv_cache_counts(uint32_t *loaded, uint32_t *compiled, uint32_t *stored)
{
    *loaded = atomic_load(&loaded_count);
    *compiled = atomic_load(&compiled_count);
    *stored = atomic_load(&stored_count);
}

void gpu_spirv_cache_count_compiled(void)
{
    atomic_fetch_add(&compiled_count, 1u);
}
