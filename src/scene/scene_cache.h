/*
 * scene_cache.h: a loaded scene model kept in the cache directory (cache_file.h), so that a second
 * start reads the arrays instead of parsing the scene file's text.
 *
 * A big scene file takes seconds to parse; reading back the arrays its model holds from the page
 * cache takes a fraction of that (docs/performance.md has the figures). An entry holds everything
 * the loader gives: every mesh's arrays (read straight into the model's own arrays, in chunks on
 * every core, no conversion), the instances, the material records, lights, cameras, the box and
 * the warnings, which a warm start prints exactly as the parse did.
 *
 * Its key names the loader and its inputs: the loader's name and options, the scene file's path (and the
 * working folder when the path is relative: the materials' texture paths are resolved against
 * it), size, modification time and a hash of its bytes (read on every core), the layout's version
 * and the vkrt program's own identity. The other files the load read (an OBJ's .mtl files) are
 * listed in the entry with their size, time and hash, and checked before it is used. Size and
 * time alone would miss a file rewritten within the clock's resolution, or a copy that keeps its
 * time (cp -p, rsync -t, tar): then the cache would render the old scene, so the contents are
 * hashed. Each array's hash is checked too: a short, damaged, foreign or older-layout entry is a
 * miss and the scene file is parsed again. A scene file under 1 MiB whose model (mesh arrays)
 * is under 1 MiB too is parsed in milliseconds and is not stored (a .gltf of a few KiB may name
 * buffers of a million triangles: that one is); nor is one that names a file not found (that file appearing later would go
 * unnoticed). The cache keeps one version per scene file path: storing a new one removes the
 * older.
 */
#ifndef VKRT_SCENE_CACHE_H
#define VKRT_SCENE_CACHE_H

#include <stdbool.h>

#include "../error.h"
#include "loader.h"
#include "model.h"

/* What the cache did for a load, for --verbose. */
typedef enum vkrt_scene_cache_outcome {
    VKRT_SCENE_CACHE_OFF,     /* no cache directory (--no-cache, VKRT_CACHE_DIR empty) */
    VKRT_SCENE_CACHE_HIT,     /* the model was read from the cache */
    VKRT_SCENE_CACHE_STORING, /* parsed, and being stored on a thread (vkrt_scene_cache_finish) */
    VKRT_SCENE_CACHE_STORED,  /* parsed, and stored for the next start */
    VKRT_SCENE_CACHE_SKIPPED, /* parsed, not stored: see why */
} vkrt_scene_cache_outcome;

typedef struct vkrt_scene_cache_report {
    vkrt_scene_cache_outcome outcome;
    double hash_ms;  /* hashing the scene file's bytes for the key */
    double read_ms;  /* reading (and checking) the entry, on a hit */
    double store_ms; /* writing the entry, when stored */
    const char *why;      /* why not stored ("" when stored or off) */
    const char *rejected; /* why an entry found under the key was not used ("" when none was) */
    struct scene_cache_store *store; /* the thread storing the entry, while STORING */
} vkrt_scene_cache_report;

/* Loads the scene file at path into *model with loader's contract under options (NULL: the
 * defaults), taking the model from the cache when a valid entry has the file's key (which holds
 * the options), else loading it and storing it (best effort: a cache that cannot be written warns
 * once and the load goes on). report (may be NULL) says which.
 * With a report, the entry is written on a thread while the caller goes on: the model must then
 * stay unchanged and alive until vkrt_scene_cache_finish(report), which vkrt_scene_free calls. */
bool vkrt_scene_cache_load(const vkrt_scene_loader *loader, const char *path,
                           const vkrt_load_options *options, vkrt_model *model,
                           vkrt_scene_cache_report *report, vkrt_error *err);

/* Waits for the entry being stored, if any, and completes the report (outcome, store_ms, why).
 * Call it before forking (a child has no such thread) and before reading the report. */
void vkrt_scene_cache_finish(vkrt_scene_cache_report *report);

#endif
