/*
 * obj_geometry.h: an OBJ's geometry records read in parallel (internal to obj_load.cpp).
 *
 * The text is split into chunks at line ends and each chunk is read on its own thread: the
 * pre-scan of obj_scan.h (checks, line numbers, the corners of every face as written, and the
 * numbers of its v, vt and vn records read as tinyobjloader's own number parser reads them,
 * obj_number.h), so every coordinate is the float tinyobjloader's LoadObj gives. What
 * crosses chunks is put together afterwards: line numbers and record counts are summed over the
 * chunks before (a prefix sum), relative indices are resolved against the counts before their
 * face in the whole file, and each face's material is that of the last usemtl before it.
 * Everything else (usemtl, mtllib, g, o, s, l, p, faces tinyobjloader refuses or drops) is left
 * to tinyobjloader, which reads those lines afterwards in file order (obj_load.cpp). C++ only.
 */
#ifndef VKRT_OBJ_GEOMETRY_H
#define VKRT_OBJ_GEOMETRY_H

#include <cstddef>
#include <cstdint>
#include <vector>

extern "C" {
#include "../../error.h"
}
#include "obj_scan.h"

namespace obj_geometry {

/* One chunk of the text: its bytes [begin, end) and what the pre-scan found there (line numbers of
 * the whole file; v_before, vt_before, vn_before and usemtl_before counted over the whole file once
 * parse_geometry returns; its numbers moved to Geometry's arrays). */
struct Chunk {
    size_t begin = 0, end = 0;
    uint32_t lines_before = 0, lines = 0;
    uint32_t v_before = 0, vt_before = 0, vn_before = 0, usemtl_before = 0;
    obj_scan::ObjScan scan;
    bool failed = false;
    vkrt_error err = {{0}};
};

/* The geometry of a whole file. */
struct Geometry {
    std::vector<Chunk> chunks;
    /* Over the whole file, in order: usemtl, mtllib and short-face lines, the lines tinyobjloader
     * reads (other), and whether each vn is usable; v_line, vt_line, vn_line and faces stay in
     * their chunks. */
    obj_scan::ObjScan summary;
    size_t v_count = 0, vt_count = 0, vn_count = 0;
    std::vector<float> vertices, texcoords, normals; /* of the whole file: 3, 2 and 3 per record */
};

/* How the text is cut and how many threads read it; zero means the default (chunks of a few
 * MiB, one thread per core). The result never depends on either: the tests cut at every line. */
struct Split {
    size_t chunk_bytes;
    unsigned threads;
};

/* Reads text[start, size) into *out. Fails with the first pre-scan error of the
 * file in err ("path:LINE: ..."), as a serial pre-scan would. The corners of the faces come back
 * 0-based as rc10's fixIndex makes them (relative ones against the records before the face in
 * the whole file), -1 where a texture coordinate or normal is not given. */
bool parse_geometry(const char *path, const char *text, size_t start, size_t size, Split split,
                    Geometry *out, vkrt_error *err);

/* The line of record `index` (0-based over the file) of v (kind 0), vt (1) or vn (2). */
uint32_t record_line(const Geometry &g, int kind, size_t index);

/* Runs body(i) for i in [0, count) on up to `threads` threads (0: one per core). An exception in
 * body is rethrown here after every thread has finished. */
void run_parallel(size_t count, unsigned threads, void (*body)(void *context, size_t i), void *context);

} // namespace obj_geometry

#endif
