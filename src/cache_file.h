/*
 * cache_file.h: files kept in vkrt's cache directory, and the hashes that name and check them.
 *
 * The kernel cache (gpu/spirv_cache.h), the scene cache (scene/scene_cache.h) and the structure
 * cache (render/accel_cache.h) share one directory and one discipline: an entry is named by a
 * 128-bit key of everything it depends on, written whole under a temporary name and renamed (so a
 * reader never sees half an entry, and concurrent writers of one key each leave a whole one),
 * and read back only after its own checks; anything short, damaged or foreign is a miss.
 *
 * Where: $VKRT_CACHE_DIR if set (empty: no cache), else $XDG_CACHE_HOME/vkrt, else
 * $HOME/.cache/vkrt (the XDG base directory convention). Meshes and structures, up to gigabytes
 * an entry where kernels take kilobytes, go to $VKRT_SCENE_CACHE_DIR where it is set (empty:
 * none kept, the kernels still are), else beside the kernels. `--no-cache` turns all off.
 */
#ifndef VKRT_CACHE_FILE_H
#define VKRT_CACHE_FILE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/* Turns every cache off for the rest of the process (--no-cache). */
void vkrt_cache_disable(void);

/* What an entry holds, which decides its directory. */
typedef enum vkrt_cache_kind {
    VKRT_CACHE_KERNELS, /* compiled kernels and the driver's pipeline data */
    VKRT_CACHE_SCENES,  /* meshes and structures */
} vkrt_cache_kind;

/* The cache directory of kind as above, written into dir (dir_size bytes); false when there is
 * none (turned off, the variable empty, or no HOME) or it does not fit. Does not create it. */
bool vkrt_cache_dir(vkrt_cache_kind kind, char *dir, size_t dir_size);

/* The path of the entry of key with extension ext (".spv") in kind's directory; false when
 * there is no directory or the path does not fit. */
bool vkrt_cache_entry_path(vkrt_cache_kind kind, const uint64_t key[2], const char *ext,
                           char *path, size_t size);

/* A 64-bit hash of the running program's file (its device, inode, size and modification time):
 * in a key, it keeps a rebuilt vkrt, whose loader or builder may give other results, from
 * reading what an older build stored. 0 where /proc/self/exe cannot be read. */
uint64_t vkrt_cache_program_id(void);

/* A 64-bit hash of size bytes from seed: four independent multiply-rotate lanes over 32-byte
 * stripes (the structure of XXH64), several GB/s on one core. For naming and checking entries,
 * not against an adversary. */
uint64_t vkrt_hash64(const void *data, size_t size, uint64_t seed);

/* The same kind of hash of a large array, cut into fixed 8 MiB chunks hashed on every core (up to
 * 16 threads); the value depends on the bytes alone, never on the thread count. */
uint64_t vkrt_hash64_parallel(const void *data, size_t size);

/* What identifies a file's contents: its size, its modification time (ns) and vkrt_hash64_parallel's
 * hash of its bytes (read in chunks on every core). */
typedef struct vkrt_file_identity {
    uint64_t size;
    int64_t mtime_ns;
    uint64_t hash;
} vkrt_file_identity;

/* Reads path's identity; false when it cannot be opened or read whole. */
bool vkrt_file_identity_of(const char *path, vkrt_file_identity *id);

/* An entry being written: under a temporary name until vkrt_cache_writer_commit renames it. */
typedef struct vkrt_cache_writer {
    FILE *file;
    vkrt_cache_kind kind;
    const char *what; /* named in warnings ("scene cache"), or NULL to stay silent */
    char path[4200], temp[4300];
    int error_number; /* the first write's errno, 0 while all went well */
} vkrt_cache_writer;

/* Opens the temporary file of key's entry (creating the cache directory if needed); false when
 * there is no cache or it cannot be written (then nothing is left behind, and unless what is
 * NULL a warning says why: vkrt_cache_warn). */
bool vkrt_cache_writer_open(vkrt_cache_writer *w, vkrt_cache_kind kind, const char *what,
                            const uint64_t key[2], const char *ext);

/* Appends size bytes; a failure is remembered and reported by commit. */
void vkrt_cache_writer_put(vkrt_cache_writer *w, const void *data, size_t size);

/* Closes the file and renames it to the entry, or removes it (and warns, as open does) when any
 * write failed; returns whether the entry was stored. */
bool vkrt_cache_writer_commit(vkrt_cache_writer *w);

/* Removes the files of kind's directory whose names end with suffix (".0123456789abcdef.mesh"),
 * but keep (a path): an entry replacing its older versions, so that re-exporting a big scene
 * does not leave a copy of every version behind. Best effort; a reader that has one of them
 * open reads on (POSIX unlink). */
void vkrt_cache_remove_others(vkrt_cache_kind kind, const char *suffix, const char *keep);

/* An entry being read: its file, its size, where the next read starts, and whether every read
 * so far went well (once false, later reads do nothing). */
typedef struct vkrt_cache_reader {
    int fd;
    uint64_t size, at;
    bool ok;
} vkrt_cache_reader;

/* Opens key's entry with extension ext in kind's directory; false (nothing to close) when there is none. */
bool vkrt_cache_reader_open(vkrt_cache_reader *r, vkrt_cache_kind kind, const uint64_t key[2],
                            const char *ext);

/* Reads the next size bytes into dst (zeroed on a failure, which clears r->ok). */
void vkrt_cache_reader_get(vkrt_cache_reader *r, void *dst, size_t size);

/* Reads the next bytes bytes into a new allocation, in 8 MiB chunks on every core, each chunk
 * read straight into its place and hashed there, and checks them against hash
 * (vkrt_hash64_parallel's value): the array, or NULL for none (bytes 0, or r->ok already false)
 * or on a failure, which clears r->ok. */
void *vkrt_cache_reader_array(vkrt_cache_reader *r, uint64_t bytes, uint64_t hash);

/* Closes the file. */
void vkrt_cache_reader_close(vkrt_cache_reader *r);

/* Prints "vkrt: warning: what: cannot write PATH: reason" once per process, for a cache
 * that cannot be written: a full disk or an unwritable directory costs the next start time, not
 * this one its result. */
void vkrt_cache_warn(const char *what, const char *path, int error_number);

#endif
