/*
 * cache_file.c: the cache directory, entries written whole and renamed, and the hashes that name
 * and check them (cache_file.h).
 */
#define _POSIX_C_SOURCE 200809L
#include "cache_file.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static atomic_bool disabled;

void vkrt_cache_disable(void)
{
    atomic_store(&disabled, true);
}

bool vkrt_cache_dir(vkrt_cache_kind kind, char *dir, size_t dir_size)
{
    const char *scenes = getenv("VKRT_SCENE_CACHE_DIR");
    if (kind == VKRT_CACHE_SCENES && scenes && !atomic_load(&disabled)) {
        int n = scenes[0] ? snprintf(dir, dir_size, "%s", scenes) : -1;
        return n > 0 && (size_t)n < dir_size;
    }
    const char *set = getenv("VKRT_CACHE_DIR");
    const char *xdg = getenv("XDG_CACHE_HOME");
    const char *home = getenv("HOME");
    int n;
    if (atomic_load(&disabled))
        n = -1;
    else if (set)
        n = set[0] ? snprintf(dir, dir_size, "%s", set) : -1;
    else if (xdg && xdg[0] == '/')
        n = snprintf(dir, dir_size, "%s/vkrt", xdg);
    else if (home && home[0])
        n = snprintf(dir, dir_size, "%s/.cache/vkrt", home);
    else
        n = -1;
    return n > 0 && (size_t)n < dir_size;
}

bool vkrt_cache_entry_path(vkrt_cache_kind kind, const uint64_t key[2], const char *ext,
                           char *path, size_t size)
{
    char dir[4096];
    if (!vkrt_cache_dir(kind, dir, sizeof dir))
        return false;
    int n = snprintf(path, size, "%s/%016llx%016llx%s", dir, (unsigned long long)key[0],
                     (unsigned long long)key[1], ext);
    return n > 0 && (size_t)n < size;
}

/* ---------------------------------------------------------------- hashing */

/* XXH64's primes: odd, with well-spread bits; any such constants would do. */
static const uint64_t P1 = 0x9E3779B185EBCA87ull, P2 = 0xC2B2AE3D27D4EB4Full,
                      P3 = 0x165667B19E3779F9ull, P4 = 0x85EBCA77C2B2AE63ull,
                      P5 = 0x27D4EB2F165667C5ull;

static uint64_t rotl(uint64_t x, int r)
{
    return x << r | x >> (64 - r);
}

static uint64_t lane(uint64_t acc, uint64_t in)
{
    acc += in * P2;
    return rotl(acc, 31) * P1;
}

static uint64_t read64(const unsigned char *p)
{
    uint64_t v;
    memcpy(&v, p, sizeof v);
    return v;
}

uint64_t vkrt_hash64(const void *data, size_t size, uint64_t seed)
{
    const unsigned char *p = data, *end = p + size;
    uint64_t h = seed + P5;
    if (size >= 32) {
        /* Four lanes with no dependence between them: the multiplies overlap in the pipeline. */
        uint64_t a = seed + P1 + P2, b = seed + P2, c = seed, d = seed - P1;
        for (; end - p >= 32; p += 32) {
            a = lane(a, read64(p));
            b = lane(b, read64(p + 8));
            c = lane(c, read64(p + 16));
            d = lane(d, read64(p + 24));
        }
        h = rotl(a, 1) + rotl(b, 7) + rotl(c, 12) + rotl(d, 18);
        const uint64_t lanes[4] = {a, b, c, d};
        for (int i = 0; i < 4; ++i)
            h = (h ^ lane(0, lanes[i])) * P1 + P4;
    }
    h += size;
    for (; end - p >= 8; p += 8)
        h = rotl(h ^ lane(0, read64(p)), 27) * P1 + P4;
    for (; p < end; ++p)
        h = rotl(h ^ (*p * P5), 11) * P1;
    /* The avalanche: every input bit reaches every output bit. */
    h ^= h >> 33;
    h *= P2;
    h ^= h >> 29;
    h *= P3;
    h ^= h >> 32;
    return h;
}

/* Chunks of this size are hashed on their own (by any thread) and their hashes hashed in order:
 * large enough that a thread's overhead is nothing, small enough that 16 threads share a file of
 * a few hundred MB evenly. */
enum { HASH_CHUNK = 8u << 20, HASH_MAX_THREADS = 16 };

typedef struct hash_job {
    const unsigned char *data; /* the bytes, or NULL to read them from fd */
    int fd;
    unsigned char *dst;        /* where the bytes read go, or NULL for a buffer of each thread's */
    size_t offset;             /* of the bytes in fd */
    size_t size, chunks;
    uint64_t *hashes;
    atomic_size_t next;
    atomic_bool failed;
} hash_job;

static bool read_at(int fd, unsigned char *dst, size_t size, size_t offset)
{
    while (size > 0) {
        ssize_t got = pread(fd, dst, size, (off_t)offset);
        if (got < 0 && errno == EINTR)
            continue;
        if (got <= 0)
            return false;
        dst += got;
        offset += (size_t)got;
        size -= (size_t)got;
    }
    return true;
}

static void *hash_chunks(void *arg)
{
    hash_job *job = arg;
    bool buffered = !job->data && !job->dst;
    unsigned char *buffer = buffered ? malloc(HASH_CHUNK) : NULL;
    if (buffered && !buffer) {
        atomic_store(&job->failed, true);
        return NULL;
    }
    for (;;) {
        size_t i = atomic_fetch_add(&job->next, 1);
        if (i >= job->chunks || atomic_load(&job->failed))
            break;
        size_t offset = i * (size_t)HASH_CHUNK;
        size_t bytes = job->size - offset < HASH_CHUNK ? job->size - offset : HASH_CHUNK;
        unsigned char *target = job->dst ? job->dst + offset : buffer;
        const unsigned char *chunk = job->data ? job->data + offset : target;
        if (!job->data && !read_at(job->fd, target, bytes, job->offset + offset)) {
            atomic_store(&job->failed, true);
            break;
        }
        job->hashes[i] = vkrt_hash64(chunk, bytes, i);
    }
    free(buffer);
    return NULL;
}

/* The chunks' hashes folded in order into one. */
static uint64_t fold(uint64_t h, uint64_t chunk_hash)
{
    return rotl(h ^ lane(0, chunk_hash), 29) * P1 + P4;
}

static uint64_t finish(uint64_t h, size_t size)
{
    return vkrt_hash64(&h, sizeof h, size);
}

/* Hashes job's chunks on up to HASH_MAX_THREADS threads; a thread that cannot start leaves its
 * share to the others. Returns false when a read or an allocation failed. */
static bool hash_parallel(hash_job *job, uint64_t *out)
{
    job->chunks = job->size / HASH_CHUNK + (job->size % HASH_CHUNK != 0);
    uint64_t none = 0;
    job->hashes = job->chunks ? malloc(job->chunks * sizeof *job->hashes) : &none;
    if (!job->hashes)
        return false;
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    size_t threads = cores < 1 ? 1 : (size_t)cores;
    threads = threads > HASH_MAX_THREADS ? HASH_MAX_THREADS : threads;
    threads = threads > job->chunks ? job->chunks : threads;
    pthread_t ids[HASH_MAX_THREADS];
    bool started[HASH_MAX_THREADS] = {false};
    for (size_t t = 1; t < threads; ++t)
        started[t] = pthread_create(&ids[t], NULL, hash_chunks, job) == 0;
    hash_chunks(job);
    for (size_t t = 1; t < threads; ++t)
        if (started[t])
            pthread_join(ids[t], NULL);
    bool ok = !atomic_load(&job->failed);
    uint64_t h = P5;
    for (size_t i = 0; ok && i < job->chunks; ++i)
        h = fold(h, job->hashes[i]);
    *out = finish(h, job->size);
    if (job->chunks)
        free(job->hashes);
    return ok;
}

uint64_t vkrt_hash64_parallel(const void *data, size_t size)
{
    hash_job job = {.data = data, .fd = -1, .size = size};
    uint64_t h = 0;
    if (hash_parallel(&job, &h))
        return h;
    /* Only the chunks' hashes' allocation can fail in memory: then the same chunks here. */
    h = P5;
    for (size_t offset = 0; offset < size; offset += HASH_CHUNK) {
        size_t bytes = size - offset < HASH_CHUNK ? size - offset : HASH_CHUNK;
        h = fold(h, vkrt_hash64((const unsigned char *)data + offset, bytes, offset / HASH_CHUNK));
    }
    return finish(h, size);
}

bool vkrt_file_identity_of(const char *path, vkrt_file_identity *id)
{
    memset(id, 0, sizeof *id);
    int fd = open(path, O_RDONLY);
    if (fd < 0)
        return false;
    struct stat st;
    bool ok = fstat(fd, &st) == 0 && S_ISREG(st.st_mode);
    if (ok) {
        id->size = (uint64_t)st.st_size;
        id->mtime_ns = (int64_t)st.st_mtim.tv_sec * 1000000000 + st.st_mtim.tv_nsec;
        hash_job job = {.fd = fd, .size = (size_t)st.st_size};
        ok = hash_parallel(&job, &id->hash);
    }
    close(fd);
    return ok;
}

uint64_t vkrt_cache_program_id(void)
{
    struct stat st;
    if (stat("/proc/self/exe", &st) != 0)
        return 0;
    uint64_t fields[5] = {(uint64_t)st.st_dev, (uint64_t)st.st_ino, (uint64_t)st.st_size,
                          (uint64_t)st.st_mtim.tv_sec, (uint64_t)st.st_mtim.tv_nsec};
    return vkrt_hash64(fields, sizeof fields, 0);
}

/* ---------------------------------------------------------------- writing and reading entries */

void vkrt_cache_warn(const char *what, const char *path, int error_number)
{
    /* Once: a full disk would otherwise warn for every entry. */
    static atomic_bool warned;
    if (atomic_exchange(&warned, true))
        return;
    fprintf(stderr, "vkrt: warning: %s: cannot write %s: %s (it is made again next time)\n", what,
            path, error_number ? strerror(error_number) : "write failed");
}

/* mkdir -p for the cache directory (and its parents, e.g. ~/.cache), private to the user. */
static bool make_dirs(char *path)
{
    for (char *p = path + 1; *p; ++p) {
        if (*p != '/')
            continue;
        *p = '\0';
        bool made = mkdir(path, 0700) == 0 || errno == EEXIST;
        *p = '/';
        if (!made)
            return false;
    }
    return mkdir(path, 0700) == 0 || errno == EEXIST;
}

bool vkrt_cache_writer_open(vkrt_cache_writer *w, vkrt_cache_kind kind, const char *what,
                            const uint64_t key[2], const char *ext)
{
    /* Entries written at once by threads of one process (the kernels are compiled on several,
     * render/renderer_kernels.c) get names of their own as well as the process's id. */
    static atomic_uint serial;
    memset(w, 0, sizeof *w);
    w->what = what;
    w->kind = kind;
    char dir[4096];
    if (!vkrt_cache_dir(kind, dir, sizeof dir) ||
        !vkrt_cache_entry_path(kind, key, ext, w->path, sizeof w->path))
        return false;
    int n = snprintf(w->temp, sizeof w->temp, "%s.%ld.%u.tmp", w->path, (long)getpid(),
                     atomic_fetch_add(&serial, 1u));
    if (n < 0 || (size_t)n >= sizeof w->temp)
        return false;
    if (make_dirs(dir))
        w->file = fopen(w->temp, "wb");
    if (!w->file && what)
        vkrt_cache_warn(what, dir, errno);
    return w->file != NULL;
}

void vkrt_cache_writer_put(vkrt_cache_writer *w, const void *data, size_t size)
{
    if (w->error_number == 0 && size > 0 && fwrite(data, 1, size, w->file) != size)
        w->error_number = errno ? errno : EIO;
}

bool vkrt_cache_writer_commit(vkrt_cache_writer *w)
{
    if (!w->file)
        return false;
    if (fclose(w->file) != 0 && w->error_number == 0)
        w->error_number = errno ? errno : EIO;
    w->file = NULL;
    if (w->error_number == 0 && rename(w->temp, w->path) != 0)
        w->error_number = errno ? errno : EIO;
    if (w->error_number == 0)
        return true;
    remove(w->temp);
    if (w->what)
        vkrt_cache_warn(w->what, w->path, w->error_number);
    return false;
}

void vkrt_cache_remove_others(vkrt_cache_kind kind, const char *suffix, const char *keep)
{
    char dir[4096], path[4400];
    if (!vkrt_cache_dir(kind, dir, sizeof dir))
        return;
    DIR *d = opendir(dir);
    if (!d)
        return;
    size_t suffix_length = strlen(suffix);
    for (struct dirent *e; (e = readdir(d));) {
        size_t length = strlen(e->d_name);
        if (length <= suffix_length || strcmp(e->d_name + length - suffix_length, suffix) != 0)
            continue;
        int n = snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        if (n > 0 && (size_t)n < sizeof path && strcmp(path, keep) != 0)
            remove(path);
    }
    closedir(d);
}

bool vkrt_cache_reader_open(vkrt_cache_reader *r, vkrt_cache_kind kind, const uint64_t key[2],
                            const char *ext)
{
    memset(r, 0, sizeof *r);
    char path[4200];
    if (!vkrt_cache_entry_path(kind, key, ext, path, sizeof path))
        return false;
    r->fd = open(path, O_RDONLY);
    if (r->fd < 0)
        return false;
    struct stat st;
    r->ok = fstat(r->fd, &st) == 0;
    r->size = r->ok ? (uint64_t)st.st_size : 0;
    return true;
}

void vkrt_cache_reader_get(vkrt_cache_reader *r, void *dst, size_t size)
{
    r->ok = r->ok && size <= r->size - r->at && read_at(r->fd, dst, size, (size_t)r->at);
    if (!r->ok)
        memset(dst, 0, size);
    r->at += size;
}

void *vkrt_cache_reader_array(vkrt_cache_reader *r, uint64_t bytes, uint64_t hash)
{
    if (!r->ok || bytes == 0)
        return NULL;
    unsigned char *data = bytes <= r->size - r->at ? malloc((size_t)bytes) : NULL;
    hash_job job = {.fd = r->fd, .dst = data, .offset = (size_t)r->at, .size = (size_t)bytes};
    uint64_t got = 0;
    r->ok = data && hash_parallel(&job, &got) && got == hash;
    r->at += bytes;
    if (!r->ok) {
        free(data);
        data = NULL;
    }
    return data;
}

void vkrt_cache_reader_close(vkrt_cache_reader *r)
{
    close(r->fd);
    r->fd = -1;
}
