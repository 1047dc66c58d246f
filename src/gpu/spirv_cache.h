/*
 * spirv_cache.h: compiled kernels kept on disk, so that a second start skips glslang.
 *
 * glslang is most of vkrt's start-up on small scenes, and every start compiles the same kernels
 * from the same text.
 * So each compiled kernel is stored under a key that hashes everything its SPIR-V depends on:
 * the whole text glslang reads (the kernel with its includes expanded, the generated material
 * module and the device's preamble), the stage and SPIR-V version, vkrt's version and glslang's.
 * A changed kernel, material or device has another key; nothing is ever invalidated by hand.
 *
 * Where: the cache directory of cache_file.h ($VKRT_CACHE_DIR, else $XDG_CACHE_HOME/vkrt, else
 * $HOME/.cache/vkrt, as Mesa's shader cache and Dr.Jit's kernel cache keep theirs), shared with
 * the scene and structure caches. The cache is a convenience: a directory that cannot be made or
 * written, a file that is short, corrupt or of another format, are all a miss and the kernel is
 * compiled as without a cache. Files are written whole under a temporary name and renamed, so
 * two vkrt processes sharing the directory never read a half-written kernel.
 */
#ifndef VKRT_GPU_SPIRV_CACHE_H
#define VKRT_GPU_SPIRV_CACHE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* A kernel's key: 128 bits, two independent 64-bit hashes of what its SPIR-V depends on. */
typedef struct gpu_spirv_key {
    uint64_t h[2];
} gpu_spirv_key;

/* The key of the given text compiled for `target` (any number that names the stage and SPIR-V
 * version; the glslang and vkrt versions are added here). */
gpu_spirv_key gpu_spirv_key_of(const char *text, uint32_t target);

/* Turns the cache off for the rest of the process (--no-cache): vkrt_cache_disable, so the scene
 * and structure caches too. */
void gpu_spirv_cache_disable(void);

/* The cache directory as above, written into dir (dir_size bytes); false when there is none
 * (turned off, VKRT_CACHE_DIR empty, or no HOME) or it does not fit. Does not create it. */
bool gpu_spirv_cache_dir(char *dir, size_t dir_size);

/* The kernel stored under key, if there is a whole, valid one: *spirv is then malloc'd with
 * *word_count words (a SPIR-V module: its magic number checked). False on any miss. */
bool gpu_spirv_cache_load(const gpu_spirv_key *key, uint32_t **spirv, size_t *word_count);

/* Stores a kernel under key, best effort: creates the directory if needed; a failure leaves no
 * file behind and is otherwise ignored (the next start compiles again). Returns whether the
 * entry was stored (false for a directory that is a file, read-only, or full). */
bool gpu_spirv_cache_store(const gpu_spirv_key *key, const uint32_t *spirv, size_t word_count);

/* The driver's own compiled form of a pipeline (a VkPipelineCache's data, pipeline.c) is kept
 * beside the kernels, under a key of what it depends on (gpu_spirv_key_of_bytes over the SPIR-V,
 * the specialization, and the driver's identity), in the same way: whole, with a hash of its
 * bytes; a short or damaged file is a miss. store is best effort, as for kernels, and says
 * whether the entry was stored. */
gpu_spirv_key gpu_spirv_key_of_bytes(const void *data, size_t size);
bool gpu_spirv_cache_load_bytes(const gpu_spirv_key *key, void **data, size_t *size);
bool gpu_spirv_cache_store_bytes(const gpu_spirv_key *key, const void *data, size_t size);

/* How many kernels this process took from the cache, how many it compiled and how many of those
 * it stored there, for --verbose. */
void gpu_spirv_cache_counts(uint32_t *loaded, uint32_t *compiled, uint32_t *stored);

/* Counts one compiled kernel (gpu_shader_compile_stage calls it). */
void gpu_spirv_cache_count_compiled(void);

#endif
