/*
 * accel_cache.h: built acceleration structures kept in the cache directory (cache_file.h), in the
 * form the upload takes (vkrt_accel_arrays), so that a second start skips the build.
 *
 * A BVH over ten million triangles takes seconds to build; its nodes read back in a fraction of
 * that (docs/performance.md has the figures). The key is a hash of the triangles' positions
 * (on every core: the structure depends on nothing else of the scene), their count, every field
 * of the vkrt_accel_desc the tuning resolved (kind, BVH width, leaf size, node cost, spatial
 * splits and their budget, grid density, kd-tree cost, which structures auto weighs), the
 * layout's version and the vkrt program's identity. The build's thread count is not in it: the
 * builders give the same structure on any number of threads. Each array's hash is checked on
 * reading; anything short, damaged or foreign is a miss and the structure is built again.
 * Structures of fewer than 20000 triangles build in milliseconds and are not stored.
 */
#ifndef VKRT_ACCEL_CACHE_H
#define VKRT_ACCEL_CACHE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "../scene/model.h"
#include "accel_gpu.h"
#include "accel_instanced.h"

/* Turns the structure cache alone off for the rest of the process: `vkrt bench`, whose build
 * times must be builds'. */
void vkrt_accel_cache_disable(void);

/* Where a structure is kept: its key, and the entry's extension ".<16 hex digits>.accel", a hash
 * of the description's source and every other input but the positions, shared by the versions of
 * one scene file's structure under one set of settings, of which the cache keeps the latest (".accel"
 * alone when the description names no source: nothing is replaced). */
typedef struct vkrt_accel_cache_name {
    uint64_t key[2];
    char ext[32];
} vkrt_accel_cache_name;

/* The name of the structure desc asks for over positions (9 floats per triangle); false when
 * there is nothing to gain (no cache directory, the cache turned off, or fewer triangles than
 * are worth storing). */
bool vkrt_accel_cache_name_of(const vkrt_accel_desc *desc, const float *positions,
                              uint32_t triangle_count, vkrt_accel_cache_name *name);

/* The name of the two-level BVH (accel_instanced.h) desc asks for over model's instances of the
 * unique meshes u: the key hashes u's positions, where each mesh begins in them, and every
 * instance's mesh and transform. False as vkrt_accel_cache_name_of, counting the unique
 * triangles and the instances as the work. */
bool vkrt_accel_cache_name_of_instanced(const vkrt_accel_desc *desc, const vkrt_model *model,
                                        const vkrt_unique_meshes *u, vkrt_accel_cache_name *name);

/* Fills *a from the named entry; false on any miss, with *a zeroed. stats.from_cache is set. */
bool vkrt_accel_cache_load(const vkrt_accel_cache_name *name, vkrt_accel_arrays *a);

/* Stores a under name, in place of older versions of the same source and settings; best
 * effort: a cache that cannot be written warns once. */
void vkrt_accel_cache_store(const vkrt_accel_cache_name *name, const vkrt_accel_arrays *a);

#endif
