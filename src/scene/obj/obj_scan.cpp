/*
 * obj_scan.cpp: the pre-scan of obj_scan.h, which checks an OBJ's text before tinyobjloader reads it.
 *
 * rc10's parser turns anything it cannot parse ("nan", "inf", "1.#IND", "abc") into 0 without a
 * word, and stops at the first bad character ("3.1+e2" becomes 3.1). The lines are walked exactly
 * as tinyobjloader walks them (LF, CRLF and lone CR all end a line; leading blanks skipped), and
 * the numbers of v/vt/vn records are checked with a strict grammar, then read as rc10 reads them
 * (obj_number.h). Decisions:
 *   - v: all three coordinates must be plain decimal numbers that fit a float; otherwise
 *     "path:LINE: vertex coordinate is not finite (...)" or "... is not a number" is an error.
 *     A coordinate outside +-VKRT_COORDINATE_LIMIT (coordinate_limit.h says why) is an error too:
 *     "path:LINE: vertex coordinate 1e38 is outside [-1e11, 1e11], ...".
 *   - vt: the coordinates present (up to two) get the same check; a missing v defaults to 0.
 *   - vn: a normal that is not three finite numbers is marked unusable, not refused: the loader
 *     gives the triangles using it their geometric normal and records a warning.
 *   - any number of a v, vt or vn record whose exponent has more than 9 significant digits is
 *     an error: rc10 would overflow an int reading it (undefined behaviour, found by fuzzing).
 *   - f: every index given is a whole number within int ("path:LINE: face index '1.5' is not a
 *     whole number", "... 4294967298 is too large"), where rc10's atoi reads "2x" as 2 and wraps
 *     4294967298 to 2; the common corner (plain indices of up to 9 digits) needs no check.
 * Before all that, files that start like an image or another binary format, UTF-16 and NUL bytes
 * are refused (a NUL would cut a line short); "vw" and "t" records are skipped, so tinyobjloader
 * never reads them. The common line of a big file (a v, vt or vn of short decimals such as
 * "-36.9531") passes every check by its shape alone and runs none of them: the checks' strtod
 * calls were most of the scan's time. The lines of usemtl, mtllib and too-short f records are
 * kept only so the loader's warnings can name them.
 */
#include "obj_scan.h"

#include "../coordinate_limit.h"
#include "obj_number.h"

#include <cctype>
#include <cfloat>
#include <cmath>
#include <cstdlib>
#include <climits>
#include <cstring>

namespace obj_scan {

/* ------------------------------------------------------------------------------ encoding */

namespace {

/* UTF-16 text without a BOM shows as NUL bytes on every other position. */
bool looks_like_bomless_utf16(std::string_view text)
{
    size_t n = text.size() < 4096 ? text.size() : 4096;
    size_t nul_even = 0, nul_odd = 0;
    for (size_t i = 0; i < n; i++)
        if (text[i] == '\0')
            (i % 2 ? nul_odd : nul_even)++;
    size_t half = n / 2;
    return half > 0 && ((nul_even * 10 >= half * 8 && nul_odd * 10 < half) ||
                        (nul_odd * 10 >= half * 8 && nul_even * 10 < half));
}

/* The first bytes of formats a user may name as geometry by mistake (a texture, a scene in
 * another format, a download still packed). tinyobjloader reads any of them as an OBJ without a
 * single v or f record, so the user would only hear "no triangles". */
struct Signature {
    const char *bytes;
    size_t size;
    const char *what;
};

const Signature SIGNATURES[] = {
    {"\x89PNG\r\n\x1a\n", 8, "a PNG image"},
    {"\xff\xd8\xff", 3, "a JPEG image"},
    {"GIF87a", 6, "a GIF image"},
    {"GIF89a", 6, "a GIF image"},
    {"#?RADIANCE", 10, "a Radiance HDR image"},
    {"#?RGBE", 6, "a Radiance HDR image"},
    {"\x76\x2f\x31\x01", 4, "an OpenEXR image"},
    {"II*\0", 4, "a TIFF image"},
    {"MM\0*", 4, "a TIFF image"},
    {"8BPS", 4, "a Photoshop image"},
    {"DDS ", 4, "a DDS texture"},
    {"glTF", 4, "a binary glTF (.glb) file"},
    {"Kaydara FBX Binary", 18, "a binary FBX file"},
    {"ply\n", 4, "a PLY file"},
    {"ply\r\n", 5, "a PLY file"},
    {"\x1f\x8b", 2, "gzip-compressed data; decompress it first"},
    {"PK\x03\x04", 4, "a ZIP archive; unpack it first"},
};

const Signature *known_signature(std::string_view text, size_t start)
{
    for (const Signature &s : SIGNATURES)
        if (text.size() - start >= s.size && memcmp(text.data() + start, s.bytes, s.size) == 0)
            return &s;
    return nullptr;
}

} // namespace

/* Refuses what is not 8-bit text; returns in *start how many leading bytes to skip (a BOM). */
bool check_encoding(const char *path, std::string_view text, size_t *start, vkrt_error *err)
{
    *start = 0;
    const unsigned char *u = reinterpret_cast<const unsigned char *>(text.data());
    if (const Signature *s = known_signature(text, 0))
        return vkrt_error_set(err, "%s: not an OBJ text file: it starts like %s", path, s->what);
    bool bom16 = text.size() >= 2 && ((u[0] == 0xFE && u[1] == 0xFF) || (u[0] == 0xFF && u[1] == 0xFE));
    if (bom16 || looks_like_bomless_utf16(text))
        return vkrt_error_set(err, "%s: looks like UTF-16 text; save it as UTF-8", path);
    /* A NUL would silently cut a line short in tinyobjloader (it parses C strings). */
    if (const void *nul = memchr(text.data(), '\0', text.size()))
        return vkrt_error_set(err, "%s: not an OBJ text file: byte %zu is a NUL, so it holds binary data",
                              path, static_cast<size_t>(static_cast<const char *>(nul) - text.data()));
    if (text.size() >= 3 && u[0] == 0xEF && u[1] == 0xBB && u[2] == 0xBF)
        *start = 3;
    return true;
}

/* -------------------------------------------------------------------------- line walking */

bool LineWalker::next(Span *line)
{
    if (p >= end)
        return false;
    line->b = p;
    /* memchr is vectorised: the line's '\n', then any '\r' before it (a CRLF or a lone CR). */
    const char *nl = static_cast<const char *>(memchr(p, '\n', static_cast<size_t>(end - p)));
    if (!nl)
        nl = end;
    const char *cr = static_cast<const char *>(memchr(p, '\r', static_cast<size_t>(nl - p)));
    p = cr ? cr : nl;
    line->e = p;
    if (p < end) {
        char ending = *p++;
        if (ending == '\r' && p < end && *p == '\n')
            p++;
    }
    number++;
    return true;
}

/* Next blank-separated token of *rest, or false at the end of the line. */
bool next_token(Span *rest, Span *token)
{
    while (rest->b < rest->e && is_blank(*rest->b))
        rest->b++;
    if (rest->b >= rest->e)
        return false;
    token->b = rest->b;
    while (rest->b < rest->e && !is_blank(*rest->b))
        rest->b++;
    token->e = rest->b;
    return true;
}

/* The record keyword, as tinyobjloader matches it: the word followed by a blank. */
bool has_keyword(const Span &line, const char *word)
{
    size_t n = strlen(word);
    return line.len() > n && memcmp(line.b, word, n) == 0 && is_blank(line.b[n]);
}

/* --------------------------------------------------------------------------------- numbers */

namespace {

enum class Number { ok, not_finite, invalid };

Number classify_number(const Span &t)
{
    if (!obj_number::is_plain_decimal(t.b, t.e))
        return obj_number::names_non_finite(t.b, t.e) ? Number::not_finite : Number::invalid;
    std::string s(t.b, t.e);
    double v = strtod(s.c_str(), nullptr); /* overflow (1e999) gives HUGE_VAL */
    if (!std::isfinite(v) || std::fabs(v) > FLT_MAX)
        return Number::not_finite; /* a float is what reaches the GPU */
    return Number::ok;
}

/* ------------------------------------------------------------------------------- pre-scan */

bool fail_number(const char *path, uint32_t line, const char *what, Number kind, const Span &t,
                 vkrt_error *err)
{
    int n = static_cast<int>(t.len() < QUOTE_MAX ? t.len() : QUOTE_MAX);
    if (kind == Number::not_finite)
        return vkrt_error_set(err, "%s:%u: %s is not finite (%.*s)", path, line, what, n, t.b);
    return vkrt_error_set(err, "%s:%u: %s '%.*s' is not a number", path, line, what, n, t.b);
}

bool scan_vertex(const char *path, uint32_t line, Span rest, vkrt_error *err)
{
    Span t;
    for (int i = 0; i < 3; i++) {
        if (!next_token(&rest, &t))
            return vkrt_error_set(err, "%s:%u: vertex has %d coordinates, needs 3", path, line, i);
        Number kind = classify_number(t);
        if (kind != Number::ok)
            return fail_number(path, line, "vertex coordinate", kind, t, err);
        /* The float the GPU gets is what is checked, as scene.cfg's points are. */
        float v = static_cast<float>(strtod(std::string(t.b, t.e).c_str(), nullptr));
        if (std::fabs(v) > VKRT_COORDINATE_LIMIT) {
            int n = static_cast<int>(t.len() < QUOTE_MAX ? t.len() : QUOTE_MAX);
            return vkrt_error_set(
                err, "%s:%u: vertex coordinate %.*s is outside " VKRT_COORDINATE_RANGE_TEXT, path,
                line, n, t.b);
        }
    }
    return true;
}

bool scan_texcoord(const char *path, uint32_t line, Span rest, vkrt_error *err)
{
    Span t;
    for (int i = 0; i < 2 && next_token(&rest, &t); i++) {
        Number kind = classify_number(t);
        if (kind != Number::ok)
            return fail_number(path, line, "texture coordinate", kind, t, err);
    }
    return true;
}

bool normal_is_usable(Span rest)
{
    Span t;
    for (int i = 0; i < 3; i++)
        if (!next_token(&rest, &t) || classify_number(t) != Number::ok)
            return false;
    return true;
}

uint32_t count_tokens(Span rest)
{
    uint32_t n = 0;
    Span t;
    while (next_token(&rest, &t))
        n++;
    return n;
}

/* Every token of a v, vt or vn record goes through tinyobjloader's number parser (v also reads
 * up to three colour values), so none may carry an exponent it cannot hold; see exponent_too_long. */
bool scan_exponents(const char *path, uint32_t line, Span rest, vkrt_error *err)
{
    Span t;
    while (next_token(&rest, &t))
        if (obj_number::exponent_too_long(t.b, t.e)) {
            int n = static_cast<int>(t.len() < QUOTE_MAX ? t.len() : QUOTE_MAX);
            return vkrt_error_set(err, "%s:%u: number '%.*s' has an exponent of more than 9 digits",
                                  path, line, n, t.b);
        }
    return true;
}

/* Records vkrt has no use for, which rc10 parses unsafely: "vw" skin weights (a joint id such as
 * 8.9e9 is cast from float to int, undefined behaviour) and "t" tags (their numbers go through
 * the same exponent parser as above, unchecked). They are skipped: neither the scan nor
 * tinyobjloader (which reads only the lines in ObjScan::other) reads them. */
bool is_ignored_record(const Span &line) { return has_keyword(line, "vw") || has_keyword(line, "t"); }

/* What glibc's atoi reads from [p, e): strtol's value (white space skipped, a sign, digits,
 * saturated at LONG_MAX or LONG_MIN) cast to int, so a face reads exactly as rc10 reads it. */
int atoi_bounded(const char *p, const char *e)
{
    while (p < e && (*p == ' ' || *p == '\t' || *p == '\v' || *p == '\f'))
        p++;
    bool negative = p < e && *p == '-';
    if (p < e && (*p == '+' || *p == '-'))
        p++;
    unsigned long limit = negative ? static_cast<unsigned long>(LONG_MAX) + 1 : LONG_MAX, value = 0;
    for (; p < e && *p >= '0' && *p <= '9'; p++) {
        unsigned long digit = static_cast<unsigned long>(*p - '0');
        value = value > (limit - digit) / 10 ? limit : value * 10 + digit;
    }
    long result = negative ? (value == limit ? LONG_MIN : -static_cast<long>(value)) : static_cast<long>(value);
    return static_cast<int>(result);
}

/* One index of a face corner, [b, e) (not empty), as an integer: [sign] digits whose value fits an
 * int, and nothing after them. rc10 reads it with atoi, which stops at the first character that
 * is not a digit ("2x", "1.5" and "1e5" read 2, 1 and 1) and, in glibc, saturates a long and then
 * truncates it to int (4294967298 reads 2; 99999999999999999999 reads -1, the last vertex): those
 * are refused here. A 0 is left to tinyobjloader, which refuses it in its own words
 * (obj_load.cpp puts them in ours). */
bool check_index(const char *path, uint32_t line, const char *what, const char *b, const char *e,
                 vkrt_error *err)
{
    const char *p = b + (*b == '+' || *b == '-');
    unsigned long long value = 0;
    const char *digits = p;
    for (; p < e && *p >= '0' && *p <= '9'; p++)
        value = value > INT_MAX ? value : value * 10 + static_cast<unsigned long long>(*p - '0');
    int n = static_cast<int>(e - b < QUOTE_MAX ? e - b : QUOTE_MAX);
    if (p != e || p == digits)
        return vkrt_error_set(err, "%s:%u: %s '%.*s' is not %s", path, line, what, n, b,
                              obj_number::is_plain_decimal(b, e) ? "a whole number" : "a number");
    if (value > INT_MAX)
        return vkrt_error_set(err, "%s:%u: %s %.*s is too large (more than %d)", path, line, what,
                              n, b, INT_MAX);
    return true;
}

/* Checks every index of an f record that read_plain_corners did not take (rest: the line after
 * "f ") with check_index: the vertex, texture coordinate and normal of each corner that are
 * given (an empty field, as in "1//3", is not an index). */
bool check_face_indices(const char *path, uint32_t line, Span rest, vkrt_error *err)
{
    static const char *const WHAT[] = {"face index", "face texture coordinate index",
                                       "face normal index"};
    Span token;
    while (next_token(&rest, &token)) {
        const char *p = token.b;
        for (int part = 0; part < 3; part++) {
            const char *end = static_cast<const char *>(memchr(p, '/', static_cast<size_t>(token.e - p)));
            end = end ? end : token.e;
            if (end > p && !check_index(path, line, WHAT[part], p, end, err))
                return false;
            if (end == token.e)
                break;
            p = end + 1;
        }
    }
    return true;
}

/* strcspn(p, "/ \t\r") within the line. */
const char *field_end(const char *p, const char *e)
{
    while (p < e && *p != '/' && *p != ' ' && *p != '\t' && *p != '\r')
        p++;
    return p;
}

/* rc10's parseTriple on the corner at *p: false where it refuses the face (atoi reads 0 for an
 * index that is there). Absent texture coordinates and normals are 0. */
bool read_corner(const char **p, const char *e, Corner *c)
{
    *c = Corner{atoi_bounded(*p, e), 0, 0};
    if (c->v == 0)
        return false;
    *p = field_end(*p, e);
    if (*p >= e || **p != '/')
        return true;
    (*p)++;
    if (*p < e && **p == '/') { /* i//k */
        (*p)++;
        c->vn = atoi_bounded(*p, e);
        *p = field_end(*p, e);
        return c->vn != 0;
    }
    c->vt = atoi_bounded(*p, e); /* i/j or i/j/k */
    *p = field_end(*p, e);
    if (c->vt == 0)
        return false;
    if (*p >= e || **p != '/')
        return true;
    (*p)++;
    c->vn = atoi_bounded(*p, e);
    *p = field_end(*p, e);
    return c->vn != 0;
}

/* Reads the corners of an f record (rest: the line after "f ") as rc10's LoadObj does and
 * appends them to *out; returns how many it read, or 0 if rc10 refuses the face. */
uint32_t read_corners(Span rest, std::vector<Corner> *out)
{
    const char *p = rest.b;
    while (p < rest.e && is_blank(*p))
        p++;
    uint32_t n = 0;
    while (p < rest.e) {
        Corner c;
        if (!read_corner(&p, rest.e, &c))
            return 0;
        out->push_back(c);
        n++;
        while (p < rest.e && (*p == ' ' || *p == '\t' || *p == '\r'))
            p++;
    }
    return n;
}

/* Where every token of rest is a short decimal (obj_number.h) and there are at least `least`,
 * the first `count` as rc10's parseReal reads them (0 where missing), appended to *out, and true:
 * the record passes every check of the slow path, which the common line skips. Else false, and
 * *out as it was. */
bool read_short_decimals(Span rest, int least, int count, std::vector<float> *out)
{
    float values[3] = {0.0f, 0.0f, 0.0f};
    Span t;
    int n = 0;
    for (; next_token(&rest, &t); n++) {
        if (!obj_number::is_short_decimal(t.b, t.e))
            return false;
        if (n < count)
            values[n] = obj_number::parse_real(t.b, t.e, 0.0);
    }
    if (n < least)
        return false;
    out->insert(out->end(), values, values + count);
    return true;
}

/* The first `count` numbers of rest as rc10's parseReal reads them (defaults: 0), appended to *out. */
void read_numbers(Span rest, int count, std::vector<float> *out)
{
    Span t;
    for (int i = 0; i < count; i++) {
        if (!next_token(&rest, &t))
            t = Span{rest.e, rest.e};
        out->push_back(obj_number::parse_real(t.b, t.e, 0.0));
    }
}

/* An index as the common file writes it: [-] 1 to 9 digits, not 0, ending at '/', a blank or the
 * line's end. atoi reads it as its digits say, so *value is what read_corner would read. */
bool read_plain_index(const char **p, const char *e, int *value)
{
    const char *q = *p;
    bool negative = q < e && *q == '-';
    q += negative;
    int v = 0, digits = 0;
    for (; q < e && *q >= '0' && *q <= '9' && digits < 9; q++, digits++)
        v = 10 * v + (*q - '0');
    if (digits == 0 || v == 0 || (q < e && *q != '/' && !is_blank(*q))) /* a 10th digit too */
        return false;
    *value = negative ? -v : v;
    *p = q;
    return true;
}

/* The corners of an f record (rest: the line after "f ") whose every corner is v, v/t, v//n or
 * v/t/n of plain indices, appended to *out; their number, or 0 (with *out partly written) where a
 * corner is anything else and read_corners must read the line. Then both read the same corners
 * and count the same tokens: a plain corner is one token that parseTriple reads to its end. */
uint32_t read_plain_corners(Span rest, std::vector<Corner> *out)
{
    const char *p = rest.b, *e = rest.e;
    uint32_t n = 0;
    for (;;) {
        while (p < e && is_blank(*p))
            p++;
        if (p == e)
            return n;
        Corner c{0, 0, 0};
        if (!read_plain_index(&p, e, &c.v))
            return 0;
        if (p < e && *p == '/') {
            p++;
            if (p < e && *p == '/') {
                p++;
                if (!read_plain_index(&p, e, &c.vn))
                    return 0;
            } else {
                if (!read_plain_index(&p, e, &c.vt))
                    return 0;
                if (p < e && *p == '/' && (++p, !read_plain_index(&p, e, &c.vn)))
                    return 0;
            }
        }
        if (p < e && !is_blank(*p))
            return 0;
        out->push_back(c);
        n++;
    }
}

/* The numbers of a v record (count 3, check scan_vertex) or a vt record (2, scan_texcoord) after
 * their checks, appended to *out: short decimals need none; anything else gets `check` and
 * scan_exponents, which fail with the record's message. */
bool read_coordinates(const char *path, uint32_t number, Span rest, int count,
                      bool (*check)(const char *, uint32_t, Span, vkrt_error *), std::vector<float> *out,
                      vkrt_error *err)
{
    int least = count == 3 ? 3 : 0; /* a v needs all three; a vt's missing numbers are 0 */
    if (read_short_decimals(rest, least, count, out))
        return true;
    if (!check(path, number, rest, err) || !scan_exponents(path, number, rest, err))
        return false;
    read_numbers(rest, count, out);
    return true;
}

/* has_keyword for a word known at compile time, whose memcmp the compiler inlines: the scan asks
 * it of every line. */
template <size_t N> bool is_record(const Span &line, const char (&word)[N])
{
    return line.len() > N - 1 && memcmp(line.b, word, N - 1) == 0 && is_blank(line.b[N - 1]);
}

/* Classifies one line (leading blanks already skipped) and records what it is. */
bool scan_line(const char *path, const char *text, uint32_t number, Span line, ObjScan *scan,
               vkrt_error *err)
{
    if (is_record(line, "v")) {
        scan->v_line.push_back(number);
        return read_coordinates(path, number, Span{line.b + 2, line.e}, 3, scan_vertex, &scan->v, err);
    }
    if (is_record(line, "vt")) {
        scan->vt_line.push_back(number);
        return read_coordinates(path, number, Span{line.b + 3, line.e}, 2, scan_texcoord, &scan->vt,
                                err);
    }
    if (is_record(line, "vn")) {
        Span rest{line.b + 3, line.e};
        bool usable = read_short_decimals(rest, 3, 3, &scan->vn);
        if (!usable) {
            if (!scan_exponents(path, number, rest, err))
                return false;
            usable = normal_is_usable(rest);
            read_numbers(rest, 3, &scan->vn);
        }
        scan->vn_line.push_back(number);
        scan->vn_usable.push_back(usable);
        scan->unusable_normals += !usable;
        return true;
    }
    /* A bare "f", as a file cut short after the keyword ends: tinyobjloader skips it as an
     * unknown record; it is a face of no corners. */
    if (line.len() == 1 && line.b[0] == 'f') {
        scan->short_faces.push_back(number);
        return true;
    }
    if (is_record(line, "f")) {
        size_t first = scan->corners.size();
        uint32_t corners = read_plain_corners(Span{line.b + 2, line.e}, &scan->corners);
        if (corners == 0) { /* not plain: checked, then read as rc10 reads it */
            scan->corners.resize(first);
            if (!check_face_indices(path, number, Span{line.b + 2, line.e}, err))
                return false;
            corners = count_tokens(Span{line.b + 2, line.e});
        }
        if (corners >= 3 && (scan->corners.size() > first ||
                             read_corners(Span{line.b + 2, line.e}, &scan->corners) == corners)) {
            scan->faces.push_back(FaceLine{static_cast<size_t>(line.b - text), number, corners,
                                           static_cast<uint32_t>(scan->v_line.size()),
                                           static_cast<uint32_t>(scan->vt_line.size()),
                                           static_cast<uint32_t>(scan->vn_line.size()),
                                           static_cast<uint32_t>(scan->usemtl.size()), first});
            return true;
        }
        /* tinyobjloader refuses the face (an index atoi reads as 0) or drops it (fewer than 3
         * corners, which the loader warns about with these lines): it reads the line itself. */
        scan->corners.resize(first);
        if (corners < 3)
            scan->short_faces.push_back(number);
        scan->other.push_back(OtherLine{line, number, false});
        return true;
    }
    if (line.len() == 0 || line.b[0] == '#' || is_ignored_record(line))
        return true;
    /* rc10 matches "usemtl" without a blank after it, and reads the first word that follows. */
    if (line.len() >= 6 && memcmp(line.b, "usemtl", 6) == 0) {
        Span rest{line.b + 6, line.e}, name{rest.e, rest.e};
        next_token(&rest, &name);
        scan->usemtl.push_back(NameLine{number, std::string(name.b, name.e)});
        scan->other.push_back(OtherLine{line, number, true});
        return true;
    }
    if (has_keyword(line, "mtllib"))
        scan->mtllib.push_back(NameLine{number, std::string(line.b + 7, line.e)});
    scan->other.push_back(OtherLine{line, number, false});
    return true;
}

} // namespace

bool prescan(const char *path, const char *text, size_t begin, size_t end, uint32_t lines_before,
             ObjScan *scan, uint32_t *lines, vkrt_error *err)
{
    LineWalker walker(text + begin, text + end);
    walker.number = lines_before;
    Span line;
    while (walker.next(&line)) {
        while (line.b < line.e && is_blank(*line.b))
            line.b++;
        if (!scan_line(path, text, walker.number, line, scan, err))
            return false;
    }
    *lines = walker.number - lines_before;
    return true;
}

} // namespace obj_scan
