/*
 * obj_warnings.h: the OBJ loader's warnings, in vkrt's words (internal to obj_load.cpp).
 *
 * tinyobjloader words its warnings its own way, repeats one for every face or statement it
 * concerns and names a line for few of them. The loader gathers its own warnings and
 * tinyobjloader's, translated here with the lines taken from the pre-scan of obj_scan.h, in one
 * Warnings list: each "file:LINE: warning: text" said once, and those of one kind about one file
 * folded into one line for the mesh's short summary, the whole list kept for --verbose. C++ only;
 * nothing here needs tinyobjloader: the loader hands over its warning text and what its material
 * reader found.
 */
#ifndef VKRT_OBJ_WARNINGS_H
#define VKRT_OBJ_WARNINGS_H

#include <cstddef>
#include <cstdint>
#include <set>
#include <string>
#include <utility>
#include <vector>

extern "C" {
#include "obj_load.h"
}
#include "obj_scan.h"

namespace obj_warnings {

/* One warning as the user reads it: "file:LINE: warning: text" (no LINE when it is 0). Warnings of
 * one kind about one file fold into one line when there are several of them: "file: warning: "
 * then fold with "{n}" replaced by their count, then the first few names in brackets. */
struct Warning {
    std::string file;
    uint32_t line = 0;
    std::string text;
    std::string kind;        /* warnings of one kind fold together; "" never folds */
    std::string name;        /* what a folded line lists for this one */
    std::string fold;        /* the folded line's text, "{n}" standing for the count */
    std::string names_label; /* before the list of names: "lines " */
};

/* The warnings of one load, in the order they arose, each said once (tinyobjloader repeats a
 * warning for every face or statement it concerns). */
class Warnings {
public:
    /* Appends w unless an equal one is there already: same file, kind and name for a warning
     * that folds; same file, line and text for one that does not. */
    void add(const Warning &w);

    /* Whether nothing was added. */
    bool empty() const { return list_.empty(); }

    /* Every warning on its own line, each ending in "\n". */
    std::string all() const;

    /* One line per warning that stands alone, one per kind and file for those that fold, each
     * ending in "\n", in the order of each group's first warning. */
    std::string folded() const;

private:
    std::vector<Warning> list_;
    std::set<std::string> seen_;
};

/* What the loader's material reader found: the .mtl files it read, and each mtllib name it could
 * not find with the path it looked for. */
struct MtlLibraries {
    std::vector<std::string> loaded;
    std::vector<std::pair<std::string, std::string>> missing; /* mtllib name, path looked for */
};

/* User text in a message, cut to obj_scan::QUOTE_MAX characters and "..." so a garbage line
 * cannot flood it. */
std::string quoted(const std::string &s);

/* Whether s begins with prefix. */
bool starts_with(const std::string &s, const char *prefix);

/* The number after the last `marker` in a tinyobjloader message ("... line 15.)"), or 0 when
 * there is no marker, no number after it, or one over UINT32_MAX. */
uint32_t number_after(const std::string &message, const char *marker);

/* Adds to *out tinyobjloader's warnings (tiny, as LoadMtl wrote them) about the .mtl at path:
 * "d and Tr both defined" folds per material; any other line is passed on as it stands. */
void translate_mtl_warnings(const std::string &path, const std::string &tiny, Warnings *out);

/* Adds to *out tinyobjloader's warnings (tiny, as LoadObj wrote them) about the OBJ at path, with
 * lines from scan. Those our own checks word better or that change nothing vkrt draws are left
 * out; an unrecognised one is passed on without a line. libraries is nullptr when .mtl files are
 * not read (then usemtl names that match no material are not warned about). */
void translate_obj_warnings(const char *path, const std::string &tiny, const obj_scan::ObjScan &scan,
                            const MtlLibraries *libraries, Warnings *out);

/* Adds to *out one folding warning per mtllib file not found, at the first mtllib line of scan
 * naming it. */
void warn_missing_libraries(const char *path, const obj_scan::ObjScan &scan,
                            const MtlLibraries &libraries, Warnings *out);

/* Adds to *out one folding warning per f record of fewer than three corners in scan (tinyobjloader
 * drops them), listing their lines when folded. */
void warn_short_faces(const char *path, const obj_scan::ObjScan &scan, Warnings *out);

/* Adds to *out a warning for each kind of reference the loader dropped because the file has no
 * records of that kind: normals (no vn) when normals > 0, texture coordinates (no vt) when
 * texcoords > 0; the counts are not shown. */
void warn_dropped_references(const char *path, size_t normals, size_t texcoords, Warnings *out);

/* Adds to *out, when triangles > 0, that many triangles were given the geometric normal because
 * the file's normal for them was not usable (not finite or zero). */
void warn_unusable_normals(const char *path, size_t triangles, Warnings *out);

/* Adds to *out that material `name` of the .mtl at path has a sheen (Ps or map_Ps, at `line`)
 * but illum 3 to 7, which make it a mirror or glass, which have no sheen; folds per file.
 * Nothing when line is 0. */
void warn_unrendered_sheen(const std::string &path, uint32_t line, const std::string &name,
                           Warnings *out);

/* Adds to *out that material `name` of the .mtl at path has a clear coat (Pc, at `line`) but
 * illum 3 or 5, which makes it the mirror built-in, which has no coat; folds per file. Nothing
 * when line is 0. */
void warn_uncoated_mirror(const std::string &path, uint32_t line, const std::string &name,
                          Warnings *out);

/* Adds to *out a number of the .mtl at path, at line, that vkrt changed to use it (text says what
 * was given and what was used: "material 'm': Pr 5 is outside [0, 1] (used 1)"); folds per file,
 * listing the lines. */
void warn_mtl_number(const std::string &path, uint32_t line, const std::string &text, Warnings *out);

/* Adds to *out that `dropped` of the triangles of the file at path have zero area and were
 * dropped; nothing when dropped is 0. */
void warn_degenerate_triangles(const char *path, size_t dropped, Warnings *out);

/* Writes warnings into model: the folded lines into model->warnings, whole lines while they fit (a
 * first line too long for it is cut), and all of them, unfolded, into model->warnings_all
 * (malloc'd). Leaves model untouched when there are none; throws std::bad_alloc when out of
 * memory. */
void set_warnings(const Warnings &warnings, vkrt_model *model);

} // namespace obj_warnings

#endif
