/*
 * obj_scan.h: the pre-scan of an OBJ file, run before tinyobjloader (internal to obj_load.cpp).
 *
 * tinyobjloader (2.0.0rc10) accepts silently what a renderer cannot afford: "nan", "inf" or "abc"
 * as a coordinate becomes 0, "3.1+e2" becomes 3.1, a NUL byte cuts a line short. It parses some
 * input unsafely (an exponent of ten digits, "vw" and "t" records: undefined behaviour, found by
 * fuzzing), and it keeps no line numbers. The pre-scan walks the lines exactly as tinyobjloader
 * does, refuses those cases with "path:LINE: ..." messages, keeps the records it would misread
 * from it, records the line of every v, vt, vn and f record, so the loader can name the line when it
 * validates the faces, and reads the numbers of v, vt and vn records exactly as tinyobjloader
 * does (obj_number.h) and the corners of faces as its parseTriple does. C++ only; nothing here
 * needs tinyobjloader.
 */
#ifndef VKRT_OBJ_SCAN_H
#define VKRT_OBJ_SCAN_H

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

extern "C" {
#include "../../error.h"
}

namespace obj_scan {

/* Longest piece of user text quoted in a message, so a garbage line cannot flood it. */
constexpr int QUOTE_MAX = 40;

/* The bytes [b, e) of the text: a line or a token, never NUL-terminated. */
struct Span {
    const char *b = nullptr, *e = nullptr;
    size_t len() const { return static_cast<size_t>(e - b); }
};

/* Splits text into lines the way tinyobjloader's safeGetline does: "\n", "\r\n" and "\r" all end
 * a line, so our line numbers are the ones its own messages use. */
struct LineWalker {
    const char *p, *end;
    uint32_t number = 0; /* of the line next() returned last, counted from 1 */

    LineWalker(const char *b, const char *e) : p(b), end(e) {}

    /* The next line, without its ending, in *line; false once the text is used up. */
    bool next(Span *line);
};

/* Space or tab: the only separators tinyobjloader knows. */
inline bool is_blank(char c)
{
    return c == ' ' || c == '\t';
}

/* The next blank-separated token of *rest in *token, and *rest moved past it; false at the end
 * of the line. */
bool next_token(Span *rest, Span *token);

/* Whether line (leading blanks already skipped) is a `word` record as tinyobjloader matches it:
 * the word followed by a blank. */
bool has_keyword(const Span &line, const char *word);

/* One f record that tinyobjloader keeps (3 or more corners, no index it refuses). Its corners are
 * the indices as written (tinyobj::index_t order: vertex, normal, texcoord; 0 where a texture
 * coordinate or normal is not given), `corners` of them from ObjScan::corners[first_corner]. */
struct FaceLine {
    size_t offset;      /* of the line in the text, to quote an index in a message */
    uint32_t line;
    uint32_t corners;
    uint32_t v_before, vt_before, vn_before; /* records seen before it: relative indices count back */
    uint32_t usemtl_before;                  /* usemtl records before it: the last one is its material */
    size_t first_corner;
};

/* One corner of a face as written: what rc10's parseTriple reads with atoi. */
struct Corner {
    int v, vn, vt;
};

/* A line the geometry parse does not take (usemtl, mtllib, g, o, s, l, p, faces of fewer than
 * three corners or with an index rc10 refuses, anything unknown): tinyobjloader reads these
 * afterwards, in file order, for its materials, its errors and its warnings. */
struct OtherLine {
    Span text;
    uint32_t line;
    bool usemtl; /* a usemtl record, as rc10 matches it */
};

/* A usemtl or mtllib record: its line and what it names (usemtl: the first word after it, as
 * tinyobjloader reads it; mtllib: the rest of the line). Only for messages. */
struct NameLine {
    uint32_t line;
    std::string name;
};

/* What prescan records, in file order. */
struct ObjScan {
    std::vector<uint32_t> v_line, vt_line, vn_line; /* line of each record, by index */
    std::vector<float> v, vt, vn; /* their numbers as rc10 reads them (obj_number.h): 3, 2, 3 each */
    std::vector<char> vn_usable;                    /* the vn record holds three finite numbers */
    std::vector<FaceLine> faces;
    std::vector<Corner> corners; /* of the faces, in order */
    std::vector<OtherLine> other;
    std::vector<uint32_t> short_faces; /* lines of f records of 0 to 2 corners, which rc10 drops */
    std::vector<NameLine> usemtl, mtllib;
    size_t unusable_normals = 0;
};

/* Refuses what is not OBJ text, with a "path: not an OBJ text file: ..." message in err: a file
 * that starts like an image or another binary format (PNG, JPEG, EXR, glTF, ZIP, ...), and any
 * NUL byte; and UTF-16 text (with a BOM, or without one, seen as interleaved NULs) with a
 * "save it as UTF-8" message. On success *start is how many leading bytes to skip: 3 for a UTF-8
 * BOM, else 0. */
bool check_encoding(const char *path, std::string_view text, size_t *start, vkrt_error *err);

/* Walks the lines of text[begin, end) (begin at the start of a line, end after a line's end or
 * at the end of the text) and fills *scan (empty on entry): line numbers count on from
 * lines_before, record counts (v_before, ...) from 0, offsets from text. Fails with
 * "path:LINE: ..." in err at the first v or vt record with a coordinate that is missing, not a
 * plain decimal or not a finite float, or a v/vt/vn number with an exponent of more than 9 digits.
 * A vn that is not three finite numbers is only marked unusable. The numbers of v, vt and vn
 * records are read into scan->v, vt and vn as rc10's LoadObj reads them. *lines is set to the
 * number of lines walked. */
bool prescan(const char *path, const char *text, size_t begin, size_t end, uint32_t lines_before,
             ObjScan *scan, uint32_t *lines, vkrt_error *err);

} // namespace obj_scan

#endif
