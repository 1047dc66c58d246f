/*
 * obj_warnings.cpp: the warnings of obj_warnings.h, gathered, translated and folded for the loader.
 *
 * Every warning is kept with its file, line and, for those that fold, a kind and a name; the
 * strings the user sees are made only at the end (set_warnings), in two forms: every warning on
 * its own line (--verbose), and the short form where several warnings of one kind about one file
 * become one line with a count and the first FOLD_NAMES names. tinyobjloader's messages are
 * matched by their fixed wording in rc10 (2.0.0rc10); one not recognised is passed on unchanged,
 * so a new tinyobjloader cannot make a warning disappear. The wording of every warning the loader
 * gives is here; its errors stay in obj_load.cpp and obj_scan.cpp.
 */
#include "obj_warnings.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <map>
#include <new>

namespace obj_warnings {

namespace {

/* Enough names to recognise the problem; --verbose lists them all. */
constexpr size_t FOLD_NAMES = 3;

/* A warning that never folds: file, line (0: none) and text as given. */
Warning plain_warning(const std::string &file, uint32_t line, const std::string &text)
{
    Warning w;
    w.file = file;
    w.line = line;
    w.text = text;
    return w;
}

Warning folding_warning(const std::string &file, uint32_t line, const std::string &text,
                        const std::string &kind, const std::string &name, const std::string &fold)
{
    Warning w = plain_warning(file, line, text);
    w.kind = kind;
    w.name = quoted(name);
    w.fold = fold;
    return w;
}

std::string line_of(const Warning &w)
{
    std::string where = w.line ? w.file + ":" + std::to_string(w.line) : w.file;
    return where + ": warning: " + w.text;
}

std::string folded_line(const std::vector<const Warning *> &g)
{
    const Warning &first = *g[0];
    std::string text = first.fold, count = std::to_string(g.size());
    size_t at = text.find("{n}");
    if (at != std::string::npos)
        text.replace(at, 3, count);
    text += " (" + first.names_label;
    for (size_t i = 0; i < g.size() && i < FOLD_NAMES; i++)
        text += (i ? ", " : "") + g[i]->name;
    text += g.size() > FOLD_NAMES ? ", ...)" : ")";
    return first.file + ": warning: " + text;
}

/* The text's lines, without their "\n". */
std::vector<std::string> lines_of(const std::string &text)
{
    std::vector<std::string> out;
    size_t pos = 0;
    while (pos < text.size()) {
        size_t nl = text.find('\n', pos);
        out.push_back(text.substr(pos, nl == std::string::npos ? std::string::npos : nl - pos));
        pos = nl == std::string::npos ? text.size() : nl + 1;
    }
    return out;
}

} // namespace

/* ------------------------------------------------------------------------------ the list */

void Warnings::add(const Warning &w)
{
    std::string key = w.file + '\n' + w.kind + '\n' +
                      (w.kind.empty() ? std::to_string(w.line) + '\n' + w.text : w.name);
    if (seen_.insert(key).second)
        list_.push_back(w);
}

std::string Warnings::all() const
{
    std::string out;
    for (const Warning &w : list_)
        out += line_of(w) + "\n";
    return out;
}

std::string Warnings::folded() const
{
    std::vector<std::vector<const Warning *>> groups;
    std::map<std::string, size_t> group_of;
    for (const Warning &w : list_) {
        if (w.kind.empty()) {
            groups.push_back({&w});
            continue;
        }
        auto found = group_of.emplace(w.file + '\n' + w.kind, groups.size());
        if (found.second)
            groups.emplace_back();
        groups[found.first->second].push_back(&w);
    }
    std::string out;
    for (const std::vector<const Warning *> &g : groups)
        out += (g.size() == 1 ? line_of(*g[0]) : folded_line(g)) + "\n";
    return out;
}

/* Copies the folded warnings into model->warnings, whole lines while they fit, and all of them into
 * model->warnings_all. */
void set_warnings(const Warnings &warnings, vkrt_model *model)
{
    if (warnings.empty())
        return;
    std::string out;
    for (const std::string &line : lines_of(warnings.folded())) {
        std::string next = out.empty() ? line : out + "\n" + line;
        if (next.size() >= sizeof model->warnings) {
            if (out.empty())
                out = line.substr(0, sizeof model->warnings - 1);
            break;
        }
        out = next;
    }
    memcpy(model->warnings, out.c_str(), out.size() + 1);
    std::string all = warnings.all();
    all.pop_back(); /* the last "\n" */
    model->warnings_all = static_cast<char *>(malloc(all.size() + 1));
    if (!model->warnings_all)
        throw std::bad_alloc();
    memcpy(model->warnings_all, all.c_str(), all.size() + 1);
}

/* --------------------------------------------------------------------------- text helpers */

/* User text in a message, cut short so a garbage line cannot flood it. */
std::string quoted(const std::string &s)
{
    return s.size() > obj_scan::QUOTE_MAX ? s.substr(0, obj_scan::QUOTE_MAX) + "..." : s;
}

bool starts_with(const std::string &s, const char *prefix)
{
    return s.compare(0, strlen(prefix), prefix) == 0;
}

uint32_t number_after(const std::string &message, const char *marker)
{
    size_t at = message.rfind(marker);
    if (at == std::string::npos)
        return 0;
    unsigned long n = strtoul(message.c_str() + at + strlen(marker), nullptr, 10);
    return n <= UINT32_MAX ? static_cast<uint32_t>(n) : 0;
}

/* ------------------------------------------------------------------------- translations */

/* LoadMtl's warnings in our words: its only kind is "Both `d` and `Tr` parameters defined for
 * \"NAME\". Use the value of `d` for dissolve (line N in .mtl.)", once per statement; anything else
 * is passed on as it stands. */
void translate_mtl_warnings(const std::string &path, const std::string &tiny, Warnings *out)
{
    const char *both = "Both `d` and `Tr` parameters defined for \"";
    for (const std::string &line : lines_of(tiny)) {
        size_t end = line.rfind("\". Use the value of `d`");
        if (starts_with(line, both) && end != std::string::npos && end >= strlen(both)) {
            std::string name = line.substr(strlen(both), end - strlen(both));
            name.erase(0, std::min(name.size(), name.find_first_not_of(" \t")));
            out->add(folding_warning(path, number_after(line, "(line "),
                                     "material '" + quoted(name) + "' defines both d and Tr; d is used",
                                     "d and Tr", name, "{n} materials define both d and Tr; d is used"));
        } else if (!line.empty()) {
            out->add(plain_warning(path, 0, line));
        }
    }
}

/* tinyobjloader's warnings about the OBJ in our words, with the lines its messages lack taken from
 * the scan. Those that a check of ours words better, or that change nothing vkrt draws, are left
 * out: short faces (the scan has their lines), indices out of bounds (validated later, an error
 * or our own warning), "Failed to load material file(s)" (the reader names the files), empty
 * group names (vkrt has no use for groups), usemtl names after a .mtl was not found (that
 * warning says it) or when .mtl files are not read at all (vkrt_obj_parse without a folder). */
void translate_obj_warnings(const char *path, const std::string &tiny, const obj_scan::ObjScan &scan,
                            const MtlLibraries *libraries, Warnings *out)
{
    const char *usemtl_head = "material [ '", *usemtl_tail = "' ] not found in .mtl";
    for (std::string line : lines_of(tiny)) {
        if (!line.empty() && line[0] == '.') /* rc10 writes "Degenerated face found\n.", so the
                                                next message starts with that "." */
            line.erase(0, 1);
        if (line.empty() || starts_with(line, "Degenerated face found") ||
            starts_with(line, "Failed to load material file(s)") ||
            line.find("indices out of bounds") != std::string::npos || starts_with(line, "Empty group name"))
            continue;
        size_t tail = line.rfind(usemtl_tail);
        if (starts_with(line, usemtl_head) && tail != std::string::npos && tail >= strlen(usemtl_head)) {
            if (!libraries || !libraries->missing.empty())
                continue;
            std::string name = line.substr(strlen(usemtl_head), tail - strlen(usemtl_head));
            uint32_t number = 0;
            for (const obj_scan::NameLine &u : scan.usemtl)
                if (u.name == name) {
                    number = u.line;
                    break;
                }
            std::string names;
            for (const std::string &l : libraries->loaded)
                names += (names.empty() ? "" : ", ") + l;
            std::string where = names.empty() ? "the file names no material library (mtllib)"
                                              : "no material of that name in " + names;
            std::string fold = names.empty()
                                   ? "{n} usemtl names, but the file names no material library (mtllib)"
                                   : "{n} usemtl names have no material in " + names;
            out->add(folding_warning(path, number,
                                     "usemtl " + quoted(name) + ": " + where + "; the default material is used",
                                     "usemtl", name, fold + "; the default material is used"));
        } else if (starts_with(line, "Looks like empty filename for mtllib")) {
            out->add(plain_warning(path, number_after(line, "(line "),
                                   "mtllib names no file; the default material is used"));
        } else {
            out->add(plain_warning(path, 0, line));
        }
    }
}

/* ------------------------------------------------------------------------ our own checks */

/* The mtllib files that were not found, each at the first mtllib line naming it. */
void warn_missing_libraries(const char *path, const obj_scan::ObjScan &scan,
                            const MtlLibraries &libraries, Warnings *out)
{
    for (const auto &m : libraries.missing) {
        uint32_t number = 0;
        for (const obj_scan::NameLine &l : scan.mtllib)
            if (l.name.find(m.first) != std::string::npos) {
                number = l.line;
                break;
            }
        out->add(folding_warning(path, number,
                                 "material library " + m.second +
                                     " not found; faces using its materials get the default material",
                                 "mtllib", m.first,
                                 "{n} material libraries not found; faces using their materials get "
                                 "the default material"));
    }
}

/* f records of fewer than three corners, which tinyobjloader drops ("Degenerated face found"). */
void warn_short_faces(const char *path, const obj_scan::ObjScan &scan, Warnings *out)
{
    for (uint32_t line : scan.short_faces) {
        Warning w = folding_warning(path, line, "face of fewer than 3 corners ignored", "short face",
                                    std::to_string(line), "{n} faces of fewer than 3 corners ignored");
        w.names_label = "lines ";
        out->add(w);
    }
}

/* Faces that name vn (or vt) records in a file that has none: the loader drops those references
 * (see drop_references_to_absent_attributes in obj_load.cpp). */
void warn_dropped_references(const char *path, size_t normals, size_t texcoords, Warnings *out)
{
    if (normals)
        out->add(plain_warning(path, 0, "faces name normals but the file has no vn records; normals ignored"));
    if (texcoords)
        out->add(plain_warning(
            path, 0, "faces name texture coordinates but the file has no vt records; ignored"));
}

namespace {

/* "material 'NAME' has WHAT, which ..." at line, folded per file as "{n} materials have WHAT,
 * which ..."; nothing when line is 0. */
void warn_material_has(const std::string &path, uint32_t line, const std::string &name,
                       const std::string &what, const std::string &single,
                       const std::string &plural, const char *kind, Warnings *out)
{
    if (!line)
        return;
    out->add(folding_warning(path, line, "material '" + quoted(name) + "' has " + what + single,
                             kind, name, "{n} materials have " + what + plural));
}

} // namespace

void warn_unrendered_sheen(const std::string &path, uint32_t line, const std::string &name,
                           Warnings *out)
{
    warn_material_has(path, line, name,
                      "a sheen (Ps, map_Ps) but illum 3 to 7, which vkrt renders as ",
                      "a mirror or glass, without the sheen", "mirrors or glass, without the sheen",
                      "unrendered-sheen", out);
}

void warn_uncoated_mirror(const std::string &path, uint32_t line, const std::string &name,
                          Warnings *out)
{
    warn_material_has(path, line, name,
                      "a clear coat (Pc) but illum 3 or 5, which vkrt renders as ",
                      "a mirror, without the coat", "mirrors, without the coat", "uncoated-mirror",
                      out);
}

void warn_unusable_normals(const char *path, size_t triangles, Warnings *out)
{
    if (triangles)
        out->add(plain_warning(path, 0,
                               std::to_string(triangles) +
                                   " triangles have an unusable normal (not finite or zero); "
                                   "the geometric normal is used"));
}

void warn_mtl_number(const std::string &path, uint32_t line, const std::string &text, Warnings *out)
{
    Warning w = folding_warning(path, line, text, "mtl number", std::to_string(line),
                                "{n} numbers changed to fit their range");
    w.names_label = "lines ";
    out->add(w);
}

void warn_degenerate_triangles(const char *path, size_t dropped, Warnings *out)
{
    if (dropped)
        out->add(plain_warning(path, 0,
                               std::to_string(dropped) +
                                   (dropped == 1 ? " triangle has zero area (a line or a point) and was dropped"
                                                 : " triangles have zero area (lines or points) and were dropped")));
}

} // namespace obj_warnings
