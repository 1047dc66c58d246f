/*
 * obj_load.cpp: the C interface of obj_load.h over tinyobjloader (2.0.0rc10, float build).
 *
 * tinyobjloader defines what is accepted and how it reads (faces, negative indices, mtllib/usemtl,
 * the .mtl syntax), but it is lenient in ways a renderer cannot afford and it keeps no line
 * numbers, so this file wraps it, and reads the geometry itself as tinyobjloader reads it, in one
 * pass over the text with the checks:
 *
 *  1. The file is read once into memory and parsed from that buffer (vkrt_obj_parse: from the
 *     caller's text, not copied).
 *  2. The geometry is read in parallel (obj_geometry.h): the text is cut into chunks at line ends,
 *     and on every core the pre-scan of obj_scan.h walks a chunk's lines exactly as tinyobjloader
 *     does, checks the numbers of v/vt/vn records with a strict grammar (rc10 reads "nan" or "abc"
 *     as 0 without a word), records the line of every v, vn, vt and f record, reads the corners
 *     of every face as rc10's parseTriple does (atoi) and the v, vt and vn numbers as its
 *     tryParseDouble does (obj_number.h, the same operations in the same order), so each float and
 *     index is the one its LoadObj gives (tests/test_obj_number.cpp holds them to the library).
 *     Line numbers, record counts and relative indices are then put together over the chunks.
 *     UTF-16 and NUL bytes are refused first (a UTF-8 BOM is skipped). A vn that is not three
 *     finite numbers, or has zero length, is treated as absent: the triangles using it get their
 *     geometric normal and a warning is recorded. Records vkrt ignores and rc10 parses unsafely
 *     ("vw", "t") are skipped, so tinyobjloader never reads them.
 *  3. tinyobjloader's LoadObj reads the remaining lines (usemtl, mtllib, g, o, s, l, p, faces it
 *     refuses or drops) in file order, with a one-triangle face after each usemtl, whose material
 *     is the one that usemtl chose: the materials, the material of each face, the errors for
 *     an index of 0 and the warnings are its own, and their line numbers are put back to the
 *     file's. Faces of more than 255 corners keep them all (rc10 counts in an unsigned char).
 *  4. Every index is validated against the attribute sizes, and polygons become fans
 *     (v0, vi, vi+1), both on every core (the bounds too, per group of faces, merged in order). Out-of-range indices are "path:LINE: face index N
 *     out of range (...)", except that vt/vn references in a file with no vt/vn records at all
 *     are dropped with a warning.
 *
 * Materials are read by mtl_read.h and become the model's records by mtl.h's translation.
 *
 * tinyobjloader's own messages are never passed on as it words them: its errors (an index of 0)
 * become "path:LINE: ..." errors naming the index, and its warnings are translated into vkrt's
 * (obj_warnings.h: "file:LINE: warning: ...", lines taken from the scan, repeats folded), with
 * only an unrecognised one passed on after "file: warning:". Material names are trimmed, so
 * "newmtl  Name" is the material "usemtl Name" asks for.
 *
 * vkrt_obj_parse takes the same path from text in memory (vkrt_obj_load reads the file and hands
 * its bytes over). All C++ exceptions stop at those two entry points; all output arrays are malloc'ed for the C side.
 */
/* tinyobjloader comes through mtl_read.h: included once, so that a build that compiles the
 * library's implementation here (the fuzz build's TINYOBJLOADER_IMPLEMENTATION) gets it once. */
#include "mtl_read.h"

#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <istream>
#include <map>
#include <memory>
#include <new>
#include <streambuf>
#include <string>
#include <string_view>
#include <vector>

extern "C" {
#include "obj_load.h"
#include "../text_file.h"
}
#include "obj_geometry.h"
#include "obj_scan.h"
#include "obj_warnings.h"

namespace {

using obj_scan::check_encoding;
using obj_scan::Corner;
using obj_scan::FaceLine;
using obj_scan::has_keyword;
using obj_scan::is_blank;
using obj_scan::LineWalker;
using obj_scan::next_token;
using obj_scan::ObjScan;
using obj_scan::Span;
using mtl_read::copy_string;
using mtl_read::folder_of;
using mtl_read::MemoryBuffer;
using mtl_read::MtlReader;
using mtl_read::OBJ_MAX_FILE_BYTES;
using obj_warnings::number_after;
using obj_warnings::quoted;
using obj_warnings::starts_with;
using obj_warnings::Warnings;

/* ---------------------------------------------------------------------------- validation */

/* The file as read: its geometry (obj_geometry.h, every chunk's records and the numbers of the
 * whole file) and what tinyobjloader made of the other lines: the materials, and the material of
 * each usemtl record (usemtl_material, in file order). */
struct Parsed {
    obj_geometry::Geometry geometry;
    std::vector<tinyobj::material_t> materials;
    std::vector<int> usemtl_material;
    /* Each vn record as the triangles get it (unit_normals, 3 floats) and whether it is usable
     * (finite and not of zero length), computed once per record rather than per corner. */
    std::vector<float> unit_normals;
    std::vector<char> normal_usable;
};

/* One polygon after validation: its corners, 0-based (-1: not given). */
struct Face {
    const Corner *corners;
    uint32_t count;
    int32_t material;
};

/* The text of one index as written, for messages: corner `corner` of the f line, part 0/1/2. */
std::string written_index(std::string_view text, const FaceLine &face, uint32_t corner, int part)
{
    LineWalker walker(text.data() + face.offset, text.data() + text.size());
    Span line, token;
    walker.next(&line);
    while (line.b < line.e && is_blank(*line.b))
        line.b++;
    Span rest{line.b + 1, line.e};
    for (uint32_t i = 0; i <= corner; i++)
        if (!next_token(&rest, &token))
            return "?";
    std::string s(token.b, token.e);
    for (int i = 0; i < part; i++) {
        size_t slash = s.find('/');
        s = slash == std::string::npos ? std::string() : s.substr(slash + 1);
    }
    s = s.substr(0, s.find('/'));
    return quoted(s);
}

struct IndexKind {
    const char *what;  /* "face index" */
    const char *units; /* "vertices" */
    int part;          /* position in v/vt/vn */
};

const IndexKind VERTEX_INDEX = {"face index", "vertices", 0};
const IndexKind TEXCOORD_INDEX = {"face texture coordinate index", "texture coordinates", 1};
const IndexKind NORMAL_INDEX = {"face normal index", "normals", 2};

bool fail_index(const char *path, std::string_view text, const FaceLine &face, uint32_t corner,
                const IndexKind &kind, size_t total, uint32_t before, vkrt_error *err)
{
    std::string n = written_index(text, face, corner, kind.part);
    if (!n.empty() && n[0] == '-')
        return vkrt_error_set(err, "%s:%u: %s %s out of range (only %u %s before this line)", path,
                              face.line, kind.what, n.c_str(), before, kind.units);
    return vkrt_error_set(err, "%s:%u: %s %s out of range (file has %zu %s)", path, face.line,
                          kind.what, n.c_str(), total, kind.units);
}

/* tinyobjloader writes -1 for "not given"; a relative index resolving to exactly -1 looks the same
 * and is taken as absent (it cannot be told apart in rc10's output). */
bool index_ok(int index, size_t count, bool optional)
{
    if (index == -1 && optional)
        return true;
    return index >= 0 && static_cast<size_t>(index) < count;
}

bool validate_face(const char *path, std::string_view text, const Parsed &p, const FaceLine &face, const Corner *corners, vkrt_error *err)
{
    size_t nv = p.geometry.vertices.size() / 3, nt = p.geometry.texcoords.size() / 2, nn = p.geometry.normals.size() / 3;
    for (uint32_t c = 0; c < face.corners; c++) {
        if (!index_ok(corners[c].v, nv, false))
            return fail_index(path, text, face, c, VERTEX_INDEX, nv, face.v_before, err);
        if (!index_ok(corners[c].vt, nt, true))
            return fail_index(path, text, face, c, TEXCOORD_INDEX, nt, face.vt_before, err);
        if (!index_ok(corners[c].vn, nn, true))
            return fail_index(path, text, face, c, NORMAL_INDEX, nn, face.vn_before, err);
    }
    return true;
}

/* rc10's parseTriple refuses an f line at the first index that atoi reads as 0: a 0, an empty
 * field ("1/"), or no number at all. Walks the rest of the line (after "f ") exactly as it does and
 * returns that field, the corner it is in, and which index it is; false if none is refused. */
bool refused_face_index(const std::string &rest, std::string *corner, std::string *field,
                        const IndexKind **kind)
{
    const char *t = rest.c_str();
    const char *c = t;
    auto refuses = [&](const IndexKind &k) {
        if (atoi(t) != 0)
            return false;
        *corner = std::string(c, strcspn(c, " \t"));
        *field = std::string(t, strcspn(t, "/ \t\r"));
        *kind = &k;
        return true;
    };
    t += strspn(t, " \t");
    while (*t && *t != '\r' && *t != '\n') {
        c = t;
        if (refuses(VERTEX_INDEX))
            return true;
        t += strcspn(t, "/ \t\r");
        if (*t == '/') {
            t++;
            bool normal_only = *t == '/'; /* i//k */
            t += normal_only;
            if (refuses(normal_only ? NORMAL_INDEX : TEXCOORD_INDEX))
                return true;
            t += strcspn(t, "/ \t\r");
            if (!normal_only && *t == '/') { /* i/j/k */
                t++;
                if (refuses(NORMAL_INDEX))
                    return true;
                t += strcspn(t, "/ \t\r");
            }
        }
        t += strspn(t, " \t\r");
    }
    return false;
}

/* "0", "-0", "+000": a zero as written. */
bool is_zero(const std::string &s)
{
    size_t digits = !s.empty() && (s[0] == '+' || s[0] == '-') ? 1 : 0;
    return digits < s.size() && s.find_first_not_of('0', digits) == std::string::npos;
}

/* tinyobjloader's "Failed parse `f' line(e.g. zero value for face index. line N.)" in our words:
 * which index of line N it refused, and why. */
bool fail_face_line(const char *path, std::string_view text, size_t start, uint32_t number,
                    vkrt_error *err)
{
    LineWalker walker(text.data() + start, text.data() + text.size());
    Span line;
    while (walker.next(&line) && walker.number < number) {
    }
    while (line.b < line.e && is_blank(*line.b))
        line.b++;
    std::string corner, field;
    const IndexKind *kind = nullptr;
    if (walker.number == number && has_keyword(line, "f") &&
        refused_face_index(std::string(line.b + 2, line.e), &corner, &field, &kind)) {
        if (field.empty())
            return vkrt_error_set(err, "%s:%u: %s missing in corner '%s'", path, number, kind->what,
                                  quoted(corner).c_str());
        if (is_zero(field))
            return vkrt_error_set(err, "%s:%u: %s 0 is not valid (OBJ indices start at 1)", path, number,
                                  kind->what);
        if (field.find_first_not_of("+-0123456789") == std::string::npos)
            return vkrt_error_set(err, "%s:%u: %s %s is too large", path, number, kind->what,
                                  quoted(field).c_str());
        return vkrt_error_set(err, "%s:%u: %s '%s' is not a number", path, number, kind->what,
                              quoted(field).c_str());
    }
    return vkrt_error_set(err, "%s:%u: face has an index of 0 or one that is not a number (OBJ indices start at 1)",
                          path, number);
}

bool mismatch(const char *path, const char *what, vkrt_error *err)
{
    return vkrt_error_set(err, "%s: cannot load: tinyobjloader and the line scan disagree on %s", path, what);
}

struct OutputPlan {
    size_t triangles = 0;
    bool any_normals = false, any_texcoords = false;
};

/* collect_faces on every core: each chunk validates its own faces into its part of *faces. */
struct CollectPass {
    const char *path;
    std::string_view text;
    const Parsed *p;
    std::vector<size_t> first_face;                     /* per chunk, in *faces */
    std::vector<OutputPlan> plans;                      /* per chunk */
    std::vector<vkrt_error> errors;                     /* per chunk: its first bad face */
    std::unique_ptr<bool[]> failed;                     /* per chunk */
    std::vector<Face> *faces;
};

void collect_chunk(void *context, size_t i)
{
    CollectPass *c = static_cast<CollectPass *>(context);
    const Parsed &p = *c->p;
    const obj_geometry::Chunk &chunk = p.geometry.chunks[i];
    OutputPlan &plan = c->plans[i];
    Face *out = c->faces->data() + c->first_face[i];
    for (const FaceLine &face : chunk.scan.faces) {
        const Corner *corners = &chunk.scan.corners[face.first_corner];
        if (!validate_face(c->path, c->text, p, face, corners, &c->errors[i])) {
            c->failed[i] = true;
            return;
        }
        int mat = face.usemtl_before ? p.usemtl_material[face.usemtl_before - 1] : -1;
        if (mat < 0 || static_cast<size_t>(mat) >= p.materials.size())
            mat = -1;
        *out++ = Face{corners, face.corners, mat};
        plan.triangles += face.corners - 2;
        for (uint32_t k = 0; k < face.corners; k++) {
            plan.any_normals |= corners[k].vn >= 0;
            plan.any_texcoords |= corners[k].vt >= 0;
        }
    }
}

/* Validates every index of every face and gives each face the material of the last usemtl before
 * it, in file order in *faces, on every core; fails with the first bad face of the file. *plan
 * says how many triangles the faces make and whether any corner names a normal or texture
 * coordinate. */
bool collect_faces(const char *path, std::string_view text, const Parsed &p, unsigned threads,
                   std::vector<Face> *faces, OutputPlan *plan, vkrt_error *err)
{
    const std::vector<obj_geometry::Chunk> &chunks = p.geometry.chunks;
    size_t n = chunks.size(), total = 0;
    CollectPass c{path, text, &p, std::vector<size_t>(n), std::vector<OutputPlan>(n),
                  std::vector<vkrt_error>(n), std::unique_ptr<bool[]>(new bool[n]()), faces};
    for (size_t i = 0; i < n; i++) {
        c.first_face[i] = total;
        total += chunks[i].scan.faces.size();
    }
    faces->resize(total);
    obj_geometry::run_parallel(n, threads, collect_chunk, &c);
    for (size_t i = 0; i < n; i++) {
        if (c.failed[i]) {
            *err = c.errors[i];
            return false;
        }
        plan->triangles += c.plans[i].triangles;
        plan->any_normals |= c.plans[i].any_normals;
        plan->any_texcoords |= c.plans[i].any_texcoords;
    }
    return true;
}

/* A file with no vn (or no vt) records at all whose faces still name some has evidently had them
 * stripped (tinyobjloader's own catmark_torus_creases0.obj does this): those references are dropped
 * with a warning rather than refusing the file. Where records exist, a bad index stays an error. */
void drop_references_to_absent_attributes(const char *path, Parsed *p, Warnings *warnings)
{
    bool no_normals = p->geometry.normals.empty(), no_texcoords = p->geometry.texcoords.empty();
    size_t dropped_normals = 0, dropped_texcoords = 0;
    if (!no_normals && !no_texcoords)
        return;
    for (obj_geometry::Chunk &chunk : p->geometry.chunks)
        for (Corner &corner : chunk.scan.corners) {
            if (no_normals && corner.vn != -1)
                corner.vn = -1, dropped_normals++;
            if (no_texcoords && corner.vt != -1)
                corner.vt = -1, dropped_texcoords++;
        }
    obj_warnings::warn_dropped_references(path, dropped_normals, dropped_texcoords, warnings);
}

/* tinyobjloader's own number parser may overflow a float even where ours did not (it is not
 * correctly rounded), so the values it produced are checked too. */
bool check_parsed_values(const char *path, const Parsed &p, vkrt_error *err)
{
    for (size_t i = 0; i < p.geometry.vertices.size(); i++)
        if (!std::isfinite(p.geometry.vertices[i]))
            return vkrt_error_set(err, "%s:%u: vertex coordinate is not finite", path,
                                  obj_geometry::record_line(p.geometry, 0, i / 3));
    for (size_t i = 0; i < p.geometry.texcoords.size(); i++)
        if (!std::isfinite(p.geometry.texcoords[i]))
            return vkrt_error_set(err, "%s:%u: texture coordinate is not finite", path,
                                  obj_geometry::record_line(p.geometry, 1, i / 2));
    return true;
}

/* ------------------------------------------------------------------------------- output */

struct Vec3 {
    double x, y, z;
};

Vec3 vertex_at(const Parsed &p, int i)
{
    const float *v = &p.geometry.vertices[3 * static_cast<size_t>(i)];
    return Vec3{v[0], v[1], v[2]};
}

/* Unit vector, or +Z when v has no direction (degenerate triangle, zero normal): never NaN.
 * Doubles keep the cross product of large float coordinates from overflowing. */
Vec3 normalized_or_z(Vec3 v)
{
    double len = std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
    if (!(len > 0.0) || !std::isfinite(len))
        return Vec3{0.0, 0.0, 1.0};
    return Vec3{v.x / len, v.y / len, v.z / len};
}

Vec3 geometric_normal(const Vec3 &a, const Vec3 &b, const Vec3 &c)
{
    Vec3 e1{b.x - a.x, b.y - a.y, b.z - a.z}, e2{c.x - a.x, c.y - a.y, c.z - a.z};
    return normalized_or_z(Vec3{e1.y * e2.z - e1.z * e2.y, e1.z * e2.x - e1.x * e2.z, e1.x * e2.y - e1.y * e2.x});
}

/* The file's normal for a corner, if it has a usable one. */
bool file_normal(const Parsed &p, const Corner &corner, const float **out)
{
    int i = corner.vn;
    if (i < 0 || !p.normal_usable[static_cast<size_t>(i)])
        return false;
    *out = &p.unit_normals[3 * static_cast<size_t>(i)];
    return true;
}

/* Normals per task of unit_normals_task. */
constexpr size_t NORMALS_PER_TASK = size_t(1) << 16;

void unit_normals_task(void *context, size_t task)
{
    Parsed *p = static_cast<Parsed *>(context);
    size_t count = p->geometry.normals.size() / 3, end = std::min(count, (task + 1) * NORMALS_PER_TASK);
    for (size_t i = task * NORMALS_PER_TASK; i < end; i++) {
        const float *n = &p->geometry.normals[3 * i];
        Vec3 v{n[0], n[1], n[2]};
        double len2 = v.x * v.x + v.y * v.y + v.z * v.z;
        p->normal_usable[i] = p->geometry.summary.vn_usable[i] && len2 > 0.0 && std::isfinite(len2);
        if (p->normal_usable[i]) {
            Vec3 u = normalized_or_z(v);
            p->unit_normals[3 * i] = static_cast<float>(u.x);
            p->unit_normals[3 * i + 1] = static_cast<float>(u.y);
            p->unit_normals[3 * i + 2] = static_cast<float>(u.z);
        }
    }
}

/* Parsed::unit_normals and normal_usable, on every core. */
void compute_unit_normals(Parsed *p, unsigned threads)
{
    size_t count = p->geometry.normals.size() / 3;
    p->unit_normals.assign(3 * count, 0.0f);
    p->normal_usable.assign(count, 0);
    obj_geometry::run_parallel((count + NORMALS_PER_TASK - 1) / NORMALS_PER_TASK, threads, unit_normals_task, p);
}

void store3(float *dst, const Vec3 &v)
{
    dst[0] = static_cast<float>(v.x);
    dst[1] = static_cast<float>(v.y);
    dst[2] = static_cast<float>(v.z);
}

void *checked_alloc(size_t count, size_t size)
{
    void *p = calloc(count, size);
    if (!p)
        throw std::bad_alloc();
    return p;
}

void allocate_output(const OutputPlan &plan, vkrt_mesh *mesh)
{
    size_t n = plan.triangles;
    mesh->positions = static_cast<float *>(checked_alloc(n * 9, sizeof(float)));
    mesh->material = static_cast<int32_t *>(checked_alloc(n, sizeof(int32_t)));
    if (plan.any_normals)
        mesh->normals = static_cast<float *>(checked_alloc(n * 9, sizeof(float)));
    if (plan.any_texcoords)
        mesh->texcoords = static_cast<float *>(checked_alloc(n * 6, sizeof(float)));
}

/* Writes triangle t from three corners; returns whether it needed the geometric normal although
 * the file gave normals to some of its corners. */
bool write_triangle(const Parsed &p, const Corner *tri[3], int32_t material, size_t t, vkrt_mesh *mesh)
{
    Vec3 pos[3];
    for (int k = 0; k < 3; k++) {
        pos[k] = vertex_at(p, tri[k]->v);
        store3(&mesh->positions[9 * t + 3 * k], pos[k]);
    }
    mesh->material[t] = material;
    if (mesh->texcoords)
        for (int k = 0; k < 3; k++) {
            int i = tri[k]->vt;
            for (int j = 0; j < 2; j++)
                mesh->texcoords[6 * t + 2 * k + j] = i >= 0 ? p.geometry.texcoords[2 * static_cast<size_t>(i) + j] : 0.0f;
        }
    if (!mesh->normals)
        return false;
    const float *n[3];
    bool all = file_normal(p, *tri[0], &n[0]) && file_normal(p, *tri[1], &n[1]) && file_normal(p, *tri[2], &n[2]);
    bool some = tri[0]->vn >= 0 || tri[1]->vn >= 0 || tri[2]->vn >= 0;
    float *out = &mesh->normals[9 * t];
    if (all) {
        for (int k = 0; k < 3; k++)
            memcpy(out + 3 * k, n[k], 3 * sizeof(float));
    } else {
        Vec3 g = geometric_normal(pos[0], pos[1], pos[2]);
        for (int k = 0; k < 3; k++)
            store3(out + 3 * k, g);
    }
    return !all && some;
}

/* The box of `vertices` points (3 floats each, at least one), in one pass in order: where -0 and
 * +0 tie, the first seen is kept, so boxes of consecutive runs merged in order (merge_bounds) are
 * the box of the whole to the bit. */
void bounds_of(const float *positions, size_t vertices, float min[3], float max[3])
{
    for (int a = 0; a < 3; a++)
        min[a] = max[a] = positions[a];
    for (size_t i = 0; i < vertices; i++)
        for (int a = 0; a < 3; a++) {
            float v = positions[3 * i + a];
            min[a] = v < min[a] ? v : min[a];
            max[a] = v > max[a] ? v : max[a];
        }
}

void merge_bounds(const float min[3], const float max[3], float into_min[3], float into_max[3])
{
    for (int a = 0; a < 3; a++) {
        into_min[a] = min[a] < into_min[a] ? min[a] : into_min[a];
        into_max[a] = max[a] > into_max[a] ? max[a] : into_max[a];
    }
}

/* Faces written by one task of write_triangles. */
constexpr size_t FACES_PER_TASK = size_t(1) << 16;

struct WritePass {
    const Parsed *p;
    const std::vector<Face> *faces;
    std::vector<size_t> first_triangle, replaced; /* per task, and one past the last task */
    std::vector<float> bounds;                    /* per task: min xyz, max xyz */
    vkrt_mesh *mesh;
};

void write_task(void *context, size_t task)
{
    WritePass *w = static_cast<WritePass *>(context);
    size_t t = w->first_triangle[task], end = std::min(w->faces->size(), (task + 1) * FACES_PER_TASK);
    for (size_t k = task * FACES_PER_TASK; k < end; k++) {
        const Face &f = (*w->faces)[k];
        for (uint32_t i = 1; i + 1 < f.count; i++, t++) {
            const Corner *tri[3] = {&f.corners[0], &f.corners[i], &f.corners[i + 1]};
            w->replaced[task] += write_triangle(*w->p, tri, f.material, t, w->mesh);
        }
    }
    size_t first = w->first_triangle[task];
    if (t > first)
        bounds_of(&w->mesh->positions[9 * first], 3 * (t - first), &w->bounds[6 * task], &w->bounds[6 * task + 3]);
}

/* Fans every face (v0, vi, vi+1) into the output arrays and sets the mesh's bounds, on every
 * core; returns the triangles given the geometric normal in place of an unusable file normal. */
size_t write_triangles(const Parsed &p, const std::vector<Face> &faces, unsigned threads, vkrt_mesh *mesh)
{
    size_t tasks = (faces.size() + FACES_PER_TASK - 1) / FACES_PER_TASK, triangles = 0, replaced = 0;
    WritePass w{&p, &faces, std::vector<size_t>(tasks + 1), std::vector<size_t>(tasks),
                std::vector<float>(6 * tasks), mesh};
    for (size_t k = 0; k < faces.size(); k++) {
        if (k % FACES_PER_TASK == 0)
            w.first_triangle[k / FACES_PER_TASK] = triangles;
        triangles += faces[k].count - 2;
    }
    w.first_triangle[tasks] = triangles;
    obj_geometry::run_parallel(tasks, threads, write_task, &w);
    bool first = true;
    for (size_t task = 0; task < tasks; task++) {
        if (w.first_triangle[task + 1] == w.first_triangle[task])
            continue;
        const float *b = &w.bounds[6 * task];
        if (first) {
            memcpy(mesh->bounds_min, b, 3 * sizeof(float));
            memcpy(mesh->bounds_max, b + 3, 3 * sizeof(float));
        }
        merge_bounds(b, b + 3, mesh->bounds_min, mesh->bounds_max);
        first = false;
    }
    for (size_t r : w.replaced)
        replaced += r;
    return replaced;
}

/* ---------------------------------------------------------------------------- the load */

/* tinyobjloader's error is one or more "...\n" lines; the first one is the cause. The failures it
 * knows (an f, l or p record with an index of 0 or not a number) are put in our words. */
bool fail_tinyobj(const char *path, std::string_view text, size_t start, const std::string &message,
                  vkrt_error *err)
{
    std::string first = message.substr(0, message.find('\n'));
    uint32_t number = number_after(first, "line ");
    if (starts_with(first, "Failed parse `f' line") && number)
        return fail_face_line(path, text, start, number, err);
    if ((starts_with(first, "Failed parse `l' line") || starts_with(first, "Failed parse `p' line")) && number)
        return vkrt_error_set(err, "%s:%u: %s record has an index of 0 or one that is not a number "
                                   "(OBJ indices start at 1)",
                              path, number, first[14] == 'l' ? "line (l)" : "point (p)");
    if (first.empty())
        first = "tinyobjloader could not parse the file";
    return vkrt_error_set(err, "%s: %s", path, first.c_str());
}

/* tinyobjloader writes "line N" (or "line: N") in its messages about the text it read; N becomes
 * line_of[N - 1], the file's line. */
void renumber_lines(std::string *message, const std::vector<uint32_t> &line_of)
{
    for (const char *marker : {"line ", "line: "}) {
        size_t at = 0, n = strlen(marker);
        while ((at = message->find(marker, at)) != std::string::npos) {
            at += n;
            size_t digits = 0;
            while (at + digits < message->size() && isdigit(static_cast<unsigned char>((*message)[at + digits])))
                digits++;
            unsigned long number = digits ? strtoul(message->c_str() + at, nullptr, 10) : 0;
            if (number >= 1 && number <= line_of.size()) {
                std::string line = std::to_string(line_of[number - 1]);
                message->replace(at, digits, line);
                digits = line.size();
            }
            at += digits;
        }
    }
}

/* tinyobjloader's LoadObj on the lines the geometry parse leaves to it (obj_geometry.h), in file
 * order, with a face "f 1 1 1" after each usemtl: the material LoadObj gives that face is the one
 * the usemtl chose (rc10 looks the name up among the materials of the mtllib records read so far),
 * so p->usemtl_material holds one per usemtl record. Its errors (an f, l or p record it refuses)
 * and warnings come with the file's line numbers. */
bool read_other_lines(const char *path, std::string_view text, size_t start, Parsed *p,
                      MtlReader *reader, std::string *warnings, vkrt_error *err)
{
    std::string lines;
    std::vector<uint32_t> line_of;
    for (const obj_scan::OtherLine &o : p->geometry.summary.other) {
        lines.append(o.text.b, o.text.e);
        lines += '\n';
        line_of.push_back(o.line);
        if (o.usemtl) {
            lines += "f 1 1 1\n";
            line_of.push_back(o.line);
        }
    }
    MemoryBuffer buffer(lines);
    std::istream stream(&buffer);
    tinyobj::attrib_t attrib;
    std::vector<tinyobj::shape_t> shapes;
    std::string tiny_err;
    bool ok = tinyobj::LoadObj(&attrib, &shapes, &p->materials, warnings, &tiny_err, &stream, reader,
                               /*triangulate=*/false, /*default_vcols_fallback=*/false);
    if (reader && reader->failed) { /* a bad number in an .mtl */
        *err = reader->error;
        return false;
    }
    renumber_lines(warnings, line_of);
    renumber_lines(&tiny_err, line_of);
    if (!ok || !tiny_err.empty())
        return fail_tinyobj(path, text, start, tiny_err, err);
    for (const tinyobj::shape_t &shape : shapes)
        p->usemtl_material.insert(p->usemtl_material.end(), shape.mesh.material_ids.begin(),
                                  shape.mesh.material_ids.end());
    if (p->usemtl_material.size() != p->geometry.summary.usemtl.size())
        return mismatch(path, "the usemtl records", err);
    return true;
}

/* Why a file has no triangles, from what the scan saw. */
const char *why_no_triangles(const obj_geometry::Geometry &g)
{
    if (!g.summary.short_faces.empty())
        return " (every f record has fewer than 3 corners)";
    if (g.v_count == 0)
        return " (no v or f records)";
    return " (no f records)";
}

/* The common path of vkrt_obj_load and vkrt_obj_parse: text is the whole OBJ, path names it in
 * messages, mtl_folder is where mtllib files are looked up (nullptr: .mtl files are not read),
 * and split says how the geometry is read in parallel. */
bool parse(const char *path, std::string_view text, const std::string *mtl_folder, obj_geometry::Split split,
           vkrt_model *model, vkrt_error *err)
{
    size_t start = 0;
    Parsed p;
    if (!check_encoding(path, text, &start, err) ||
        !obj_geometry::parse_geometry(path, text.data(), start, text.size(), split, &p.geometry, err))
        return false;
    const ObjScan &scan = p.geometry.summary;

    std::string obj_folder = mtl_folder ? *mtl_folder : std::string(), tiny_warnings;
    Warnings warnings;
    MtlReader reader(obj_folder, &warnings);
    std::vector<Face> faces;
    /* Without a reader tinyobjloader skips mtllib lines, so no material (and no file) is touched. */
    if (!read_other_lines(path, text, start, &p, mtl_folder ? &reader : nullptr, &tiny_warnings, err) ||
        !check_parsed_values(path, p, err))
        return false;
    obj_warnings::warn_missing_libraries(path, scan, reader.libraries, &warnings);
    obj_warnings::translate_obj_warnings(path, tiny_warnings, scan,
                                         mtl_folder ? &reader.libraries : nullptr, &warnings);
    obj_warnings::warn_short_faces(path, scan, &warnings);
    drop_references_to_absent_attributes(path, &p, &warnings);
    OutputPlan plan;
    if (!collect_faces(path, text, p, split.threads, &faces, &plan, err))
        return false;
    if (plan.triangles == 0)
        return vkrt_error_set(err, "%s: no triangles%s", path, why_no_triangles(p.geometry));
    if (plan.triangles > UINT32_MAX / 9) /* 9 floats per triangle must stay addressable by uint32 */
        return vkrt_error_set(err, "%s: too many triangles (%zu)", path, plan.triangles);

    /* One mesh, one identity instance of it. */
    model->meshes = static_cast<vkrt_mesh *>(checked_alloc(1, sizeof(vkrt_mesh)));
    model->mesh_count = 1;
    model->instances = static_cast<vkrt_instance *>(checked_alloc(1, sizeof(vkrt_instance)));
    model->instance_count = 1;
    memcpy(model->instances[0].transform, vkrt_identity_transform, sizeof vkrt_identity_transform);
    vkrt_mesh *mesh = &model->meshes[0];
    mesh->triangle_count = static_cast<uint32_t>(plan.triangles);
    allocate_output(plan, mesh);
    compute_unit_normals(&p, split.threads);
    size_t replaced = write_triangles(p, faces, split.threads, mesh);
    uint32_t degenerate = vkrt_mesh_drop_degenerate(mesh);
    if (mesh->triangle_count == 0)
        return vkrt_error_set(err, "%s: all %zu faces have zero area (their corners lie on a line or at one "
                                   "point): nothing to draw", path, faces.size());
    obj_warnings::warn_degenerate_triangles(path, degenerate, &warnings);
    mtl_read::convert_materials(p.materials, reader, obj_folder, model);
    obj_warnings::warn_unusable_normals(path, replaced, &warnings);
    obj_warnings::set_warnings(warnings, model);
    std::string mtl_files;
    for (const std::string &file : reader.libraries.loaded)
        mtl_files += file + "\n";
    model->inputs = mtl_files.empty() ? nullptr : copy_string(mtl_files);
    model->inputs_missing = !reader.libraries.missing.empty();
    return vkrt_model_finish(model, err);
}

bool load(const char *path, vkrt_model *model, vkrt_error *err)
{
    char *bytes;
    size_t size;
    if (!vkrt_text_read_file(path, OBJ_MAX_FILE_BYTES, "Wavefront OBJ file", &bytes, &size, err))
        return false;
    std::unique_ptr<char, void (*)(void *)> owned(bytes, free);
    std::string folder = folder_of(path);
    return parse(path, std::string_view(bytes, size), &folder, obj_geometry::Split{0, 0}, model, err);
}

/* Runs body (a load or parse into model) with every C++ exception turned into a message about
 * name, and model freed on any failure, so nothing C++ crosses into the C side. */
template <typename Body>
bool guarded(const char *name, vkrt_model *model, vkrt_error *err, Body body)
{
    bool ok = false;
    try {
        ok = body();
    } catch (const std::bad_alloc &) {
        ok = vkrt_error_set(err, "%s: out of memory", name);
    } catch (const std::exception &e) {
        ok = vkrt_error_set(err, "%s: %s", name, e.what());
    } catch (...) {
        ok = vkrt_error_set(err, "%s: unexpected error while loading", name);
    }
    if (!ok)
        vkrt_model_free(model);
    return ok;
}

} // namespace

extern "C" bool vkrt_obj_load(const char *path, vkrt_model *model, vkrt_error *err)
{
    if (!model)
        return vkrt_error_set(err, "%s: no model to load into", path ? path : "(null)");
    memset(model, 0, sizeof *model);
    if (!path)
        return vkrt_error_set(err, "(null): no OBJ path given");
    return guarded(path, model, err, [&] { return load(path, model, err); });
}

extern "C" bool vkrt_obj_parse(const char *text, size_t size, const char *name, const char *base_dir,
                               vkrt_model *model, vkrt_error *err)
{
    return vkrt_obj_parse_split(text, size, name, base_dir, 0, 0, model, err);
}

extern "C" bool vkrt_obj_parse_split(const char *text, size_t size, const char *name, const char *base_dir,
                                     size_t chunk_bytes, unsigned threads, vkrt_model *model, vkrt_error *err)
{
    if (!name)
        name = "(obj)";
    if (!model)
        return vkrt_error_set(err, "%s: no model to load into", name);
    memset(model, 0, sizeof *model);
    if (!text && size > 0)
        return vkrt_error_set(err, "%s: no OBJ text given", name);
    return guarded(name, model, err, [&] {
        std::string folder = base_dir ? base_dir : "";
        return parse(name, std::string_view(size ? text : "", size), base_dir ? &folder : nullptr,
                     obj_geometry::Split{chunk_bytes, threads}, model, err);
    });
}
