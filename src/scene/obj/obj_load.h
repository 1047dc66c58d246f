/*
 * obj_load.h: Wavefront OBJ (and its .mtl) loading into the scene model (model.h), through
 * tinyobjloader.
 *
 * The loader (obj_load.cpp, with its pre-scan in obj_scan.cpp, the parallel read of the geometry
 * in obj_geometry.cpp and the .mtl reading in mtl_read.cpp) wraps tinyobjloader behind this C
 * interface; the geometry is read on every core. An OBJ is one mesh and one identity instance of
 * it; its .mtl materials become the model's physically based records (mtl.h says how).
 * The mesh is de-indexed, one record per triangle corner, which is what the kernels read:
 * polygons become triangle fans, negative indices are resolved, faces without normals get their
 * geometric normal, and non-finite coordinates or out-of-range indices are errors naming the
 * file and line. tinyobjloader's own messages never reach the user as it words them: they are
 * translated into vkrt's ("file:LINE: what is wrong", warnings with "warning:").
 * The model's inputs are the .mtl files read; inputs_missing says an mtllib named one not found.
 */
#ifndef VKRT_OBJ_LOAD_H
#define VKRT_OBJ_LOAD_H

#include <stdbool.h>
#include <stddef.h>

#include "../../error.h"
#include "../model.h"

/* Loads the OBJ at path with the .mtl files it names. On failure returns false with err set to
 * "path:LINE: message" where a line is known ("path: message" otherwise) and *model left empty.
 * A file with no triangles is an error. */
bool vkrt_obj_load(const char *path, vkrt_model *model, vkrt_error *err);

/* Parses OBJ text already in memory (size bytes; NUL bytes among them are an error, as in a file),
 * with the same checks, messages and contract as vkrt_obj_load. name stands for the path in
 * messages (NULL: "(obj)"). base_dir is the folder mtllib names are resolved against ("" for the
 * current folder); NULL means no .mtl is read at all: mtllib lines are ignored and every triangle
 * gets the default material, so the parse touches no file (what a fuzzer wants). */
bool vkrt_obj_parse(const char *text, size_t size, const char *name, const char *base_dir,
                    vkrt_model *model, vkrt_error *err);

/* vkrt_obj_parse with the geometry read in chunks of about chunk_bytes (each ends at a line end)
 * on up to `threads` threads; 0 for either is the default vkrt_obj_load uses (a few MiB, one
 * thread per core). The result does not depend on them: tests cut the text at every line. */
bool vkrt_obj_parse_split(const char *text, size_t size, const char *name, const char *base_dir,
                          size_t chunk_bytes, unsigned threads, vkrt_model *model,
                          vkrt_error *err);

#endif
