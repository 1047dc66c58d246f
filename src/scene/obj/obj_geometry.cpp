/*
 * obj_geometry.cpp: the parallel read of an OBJ's geometry (obj_geometry.h).
 *
 * Two passes over the chunks, each on every core: the pre-scan with line numbers counted from
 * the chunk's start, which also reads the numbers (as tinyobjloader reads them: obj_number.h) and
 * the face corners, then (after the counts of the chunks before each one are summed) the fix-up
 * of line numbers, the numbers moved to the whole file's arrays and the resolution of relative
 * indices. A chunk that fails its pre-scan is scanned again once the lines before it are known,
 * so its message names the file's line.
 */
#include "obj_geometry.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>

namespace obj_geometry {

namespace {

/* Big enough that a thread's start costs nothing against its chunk, small enough that 16 cores
 * share a 400 MB file evenly (chunks are handed out as threads come free). */
constexpr size_t DEFAULT_CHUNK_BYTES = size_t(4) << 20;

/* Chunks of about chunk_bytes, each ending just after a '\n' (so a "\r\n" stays whole) or at the
 * end of the text. A file whose lines end in a lone '\r' is one chunk. */
std::vector<Chunk> split_at_lines(const char *text, size_t start, size_t size, size_t chunk_bytes)
{
    std::vector<Chunk> chunks;
    size_t b = start;
    while (b < size || chunks.empty()) {
        size_t e = size - b > chunk_bytes ? b + chunk_bytes : size;
        while (e < size && text[e - 1] != '\n')
            e++;
        chunks.emplace_back();
        chunks.back().begin = b;
        chunks.back().end = e;
        b = e;
    }
    return chunks;
}

struct ScanPass {
    const char *path;
    const char *text;
    std::vector<Chunk> *chunks;
};

void scan_chunk(void *context, size_t i)
{
    ScanPass *pass = static_cast<ScanPass *>(context);
    Chunk *c = &(*pass->chunks)[i];
    if (!obj_scan::prescan(pass->path, pass->text, c->begin, c->end, 0, &c->scan, &c->lines, &c->err)) {
        c->failed = true;
        return;
    }
}

/* rc10's fixIndex: 1-based, or relative to the records before the face (-1 is "one back");
 * a texture coordinate or normal not given (0 as read) stays -1. */
int resolve(int written, uint32_t before)
{
    if (written > 0)
        return written - 1;
    if (written == 0)
        return -1;
    return static_cast<int>(static_cast<int64_t>(before) + written); /* as rc10's int sum */
}

/* Moves a chunk's numbers to their place in the whole file's arrays. */
void move_numbers(std::vector<float> *from, std::vector<float> *to, size_t first)
{
    std::copy(from->begin(), from->end(), to->begin() + static_cast<std::ptrdiff_t>(first));
    std::vector<float>().swap(*from);
}

void fix_up_chunk(void *context, size_t i)
{
    Geometry *g = static_cast<Geometry *>(context);
    Chunk *c = &g->chunks[i];
    obj_scan::ObjScan &s = c->scan;
    move_numbers(&s.v, &g->vertices, 3 * size_t(c->v_before));
    move_numbers(&s.vt, &g->texcoords, 2 * size_t(c->vt_before));
    move_numbers(&s.vn, &g->normals, 3 * size_t(c->vn_before));
    uint32_t lines = c->lines_before;
    for (std::vector<uint32_t> *v : {&s.v_line, &s.vt_line, &s.vn_line, &s.short_faces})
        for (uint32_t &line : *v)
            line += lines;
    for (obj_scan::NameLine &n : s.usemtl)
        n.line += lines;
    for (obj_scan::NameLine &n : s.mtllib)
        n.line += lines;
    for (obj_scan::OtherLine &o : s.other)
        o.line += lines;
    for (obj_scan::FaceLine &f : s.faces) {
        f.line += lines;
        f.v_before += c->v_before;
        f.vt_before += c->vt_before;
        f.vn_before += c->vn_before;
        f.usemtl_before += c->usemtl_before;
        for (size_t k = f.first_corner; k < f.first_corner + f.corners; k++) {
            obj_scan::Corner &corner = s.corners[k];
            corner.v = resolve(corner.v, f.v_before);
            corner.vt = resolve(corner.vt, f.vt_before);
            corner.vn = resolve(corner.vn, f.vn_before);
        }
    }
}

template <typename T> void append(std::vector<T> *to, const std::vector<T> &from)
{
    to->insert(to->end(), from.begin(), from.end());
}

} // namespace

void run_parallel(size_t count, unsigned threads, void (*body)(void *context, size_t i), void *context)
{
    if (threads == 0)
        threads = std::max(1u, std::thread::hardware_concurrency());
    threads = static_cast<unsigned>(std::min<size_t>(threads, count));
    std::atomic<size_t> next(0);
    std::exception_ptr failure;
    std::mutex failure_lock;
    auto work = [&]() {
        for (size_t i = next++; i < count; i = next++) {
            try {
                body(context, i);
            } catch (...) {
                std::lock_guard<std::mutex> hold(failure_lock);
                if (!failure)
                    failure = std::current_exception();
                next = count;
            }
        }
    };
    std::vector<std::thread> pool;
    try {
        for (unsigned t = 1; t < threads; t++)
            pool.emplace_back(work);
    } catch (...) { /* fewer threads than asked: the ones started and this one do the work */
    }
    work();
    for (std::thread &t : pool)
        t.join();
    if (failure)
        std::rethrow_exception(failure);
}

bool parse_geometry(const char *path, const char *text, size_t start, size_t size, Split split,
                    Geometry *out, vkrt_error *err)
{
    out->chunks = split_at_lines(text, start, size, split.chunk_bytes ? split.chunk_bytes : DEFAULT_CHUNK_BYTES);
    std::vector<Chunk> &chunks = out->chunks;
    ScanPass pass{path, text, &chunks};
    run_parallel(chunks.size(), split.threads, scan_chunk, &pass);

    uint32_t lines = 0, usemtl = 0;
    for (Chunk &c : chunks) {
        if (c.failed) { /* again, with the file's line numbers in its message */
            obj_scan::ObjScan again;
            uint32_t walked;
            if (!obj_scan::prescan(path, text, c.begin, c.end, lines, &again, &walked, err))
                return false;
            return vkrt_error_set(err, "%s: cannot load: the pre-scan of one piece of the file failed "
                                       "only once (%s)", path, c.err.msg);
        }
        c.lines_before = lines;
        c.v_before = static_cast<uint32_t>(out->v_count);
        c.vt_before = static_cast<uint32_t>(out->vt_count);
        c.vn_before = static_cast<uint32_t>(out->vn_count);
        c.usemtl_before = usemtl;
        lines += c.lines;
        usemtl += static_cast<uint32_t>(c.scan.usemtl.size());
        out->v_count += c.scan.v_line.size();
        out->vt_count += c.scan.vt_line.size();
        out->vn_count += c.scan.vn_line.size();
    }
    if (out->v_count > INT32_MAX || out->vt_count > INT32_MAX || out->vn_count > INT32_MAX)
        return vkrt_error_set(err, "%s: more than %d v, vt or vn records", path, INT32_MAX);
    out->vertices.resize(3 * out->v_count);
    out->texcoords.resize(2 * out->vt_count);
    out->normals.resize(3 * out->vn_count);
    run_parallel(chunks.size(), split.threads, fix_up_chunk, out);

    obj_scan::ObjScan &s = out->summary;
    for (const Chunk &c : chunks) {
        append(&s.usemtl, c.scan.usemtl);
        append(&s.mtllib, c.scan.mtllib);
        append(&s.short_faces, c.scan.short_faces);
        append(&s.other, c.scan.other);
        append(&s.vn_usable, c.scan.vn_usable);
        s.unusable_normals += c.scan.unusable_normals;
    }
    return true;
}

uint32_t record_line(const Geometry &g, int kind, size_t index)
{
    for (const Chunk &c : g.chunks) {
        const std::vector<uint32_t> &lines = kind == 0 ? c.scan.v_line : kind == 1 ? c.scan.vt_line : c.scan.vn_line;
        if (index < lines.size())
            return lines[index];
        index -= lines.size();
    }
    return 0;
}

} // namespace obj_geometry
