/*
 * test_obj_number.cpp: the OBJ loader's numbers and face corners held to tinyobjloader's own
 * LoadObj (src/scene/obj_number.h, obj_scan.h, obj_geometry.h).
 *
 * The loader no longer hands its records to tinyobjloader: it reads v, vt and vn numbers with
 * rc10's tryParseDouble reproduced and face corners with a scan of its own, and promises the
 * floats and indices the library gives. The library (libtinyobjloader, what obj_load.cpp links)
 * is the reference here, bit for bit:
 *   1. numbers: tokens of every shape rc10's grammar knows, and of shapes it half-reads ("3.1+e2",
 *      "-.", "1e"), read by obj_number::parse_real against the vertex LoadObj reads from a
 *      "v A B C" line of them;
 *   2. faces: 20,000 of random corners in every form rc10 reads (relative, "+1", "007", indices
 *      of 10 digits), their indices against LoadObj's; and the indices it reads with atoi and
 *      the loader refuses (past int, "2x", "1.5");
 *   3. files: every OBJ of the shared scenes that the geometry read accepts (both parser suites,
 *      the bunny, Lost Empire, ...): its arrays of v, vt and vn numbers (usable or not), and the
 *      corners of every face, against LoadObj's attributes and indices.
 */
#include <dirent.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <sys/stat.h>

#include <tiny_obj_loader.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

extern "C" {
#include "scene/text_file.h"
}
#include "scene/obj/obj_geometry.h"
#include "scene/obj/obj_number.h"
#include "shared_scenes.h"

/* Last: cmocka's fail() macro would rename std::ios's fail(). Its header declares C functions
 * without extern "C". */
extern "C" {
#include <cmocka.h>
}

namespace {

/* ------------------------------------------------------------------------ the reference */

struct Reference {
    bool ok = false;
    tinyobj::attrib_t attrib;
    std::vector<tinyobj::index_t> corners; /* of every face, in file order */
};

/* "vw" and "t" records, which rc10 parses unsafely and the loader skips (obj_scan.h), become blank
 * lines for the reference too. */
std::string without_ignored_records(std::string text)
{
    size_t at = 0;
    while (at < text.size()) {
        size_t end = text.find_first_of("\r\n", at), b = at;
        if (end == std::string::npos)
            end = text.size();
        while (b < end && (text[b] == ' ' || text[b] == '\t'))
            b++;
        bool ignored = (end - b > 2 && text.compare(b, 2, "vw") == 0 && (text[b + 2] == ' ' || text[b + 2] == '\t')) ||
                       (end - b > 1 && text[b] == 't' && (text[b + 1] == ' ' || text[b + 1] == '\t'));
        if (ignored)
            text.replace(b, end - b, end - b, ' ');
        at = end + 1;
    }
    return text;
}

/* tinyobjloader's LoadObj on text (no materials read, polygons kept whole). */
Reference load_reference(const std::string &text)
{
    Reference r;
    std::istringstream stream(without_ignored_records(text));
    std::vector<tinyobj::shape_t> shapes;
    std::vector<tinyobj::material_t> materials;
    std::string warn, err;
    r.ok = tinyobj::LoadObj(&r.attrib, &shapes, &materials, &warn, &err, &stream, nullptr,
                            /*triangulate=*/false, /*default_vcols_fallback=*/false) &&
           err.empty();
    for (const tinyobj::shape_t &s : shapes)
        r.corners.insert(r.corners.end(), s.mesh.indices.begin(), s.mesh.indices.end());
    return r;
}

bool same_bits(float a, float b)
{
    return memcmp(&a, &b, sizeof a) == 0;
}

/* ------------------------------------------------------------------------ 1. numbers */

/* A small LCG: the same tokens on every run. */
struct Random {
    uint64_t state;
    uint32_t next(uint32_t n)
    {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return static_cast<uint32_t>((state >> 33) % n);
    }
};

/* A token of random shape: sign, 0-22 integer digits (leading zeros too), a point, 0-25 fraction
 * digits (past the 8 of rc10's power table), an exponent of 0-9 digits (10 would overflow rc10's
 * int), sometimes a tail rc10 stops at. Never empty, never a blank. */
std::string random_token(Random *r)
{
    static const char *const SIGNS[] = {"", "", "", "-", "+"};
    static const char *const TAILS[] = {"x", "+e2", ".", "e", "#IND", "/", "e+", "..5", "-"};
    std::string t = SIGNS[r->next(5)];
    uint32_t int_digits = r->next(4) == 0 ? r->next(23) : r->next(4);
    for (uint32_t i = 0; i < int_digits; i++)
        t += static_cast<char>('0' + r->next(10));
    if (r->next(4) != 0) {
        t += '.';
        uint32_t frac_digits = r->next(3) == 0 ? r->next(26) : r->next(9);
        for (uint32_t i = 0; i < frac_digits; i++)
            t += static_cast<char>('0' + r->next(10));
    }
    if (r->next(4) == 0) {
        t += r->next(2) ? 'e' : 'E';
        t += SIGNS[r->next(5)];
        uint32_t exp_digits = r->next(5) == 0 ? r->next(10) : 1 + r->next(3);
        for (uint32_t i = 0; i < exp_digits; i++)
            t += static_cast<char>('0' + r->next(10));
    }
    if (r->next(16) == 0)
        t += TAILS[r->next(sizeof TAILS / sizeof TAILS[0])];
    return t.empty() ? "." : t;
}

/* Tokens whose reading has a turn of its own in rc10's parser. */
const char *const SPECIAL_TOKENS[] = {
    "0", "-0", "+0", ".", "-.", "+.", "-", "+", ".5", "-.5", "5.", "1e", "1e+", "1E-", "e5",
    "3.1+e2", "1..2", "0x10", "nan", "-inf", "1.#IND", "abc", "00012.000", "1e0", "1e-0",
    "123456789", "1234567890", "0.12345678", "0.123456789", "-36.9531", "0.707107",
    "179769313486231570000000000000000000000000000000000000000000000000000000000000000000000000000",
    "3.4028235e38", "3.4028236e38", "1e-45", "1.4e-45", "7e-46", "1e999999999", "-1e-999999999",
    "0e999999999", "9.99999999999999999999", "1e308", "1e309", "2.2250738585072014e-308",
};

void numbers_match_tinyobjloader(void **)
{
    std::vector<std::string> tokens(SPECIAL_TOKENS,
                                    SPECIAL_TOKENS + sizeof SPECIAL_TOKENS / sizeof SPECIAL_TOKENS[0]);
    Random r{20261203};
    while (tokens.size() < 300000)
        tokens.push_back(random_token(&r));
    while (tokens.size() % 3)
        tokens.push_back("1");
    std::string text;
    for (size_t i = 0; i < tokens.size(); i += 3)
        text += "v " + tokens[i] + " " + tokens[i + 1] + "\t" + tokens[i + 2] + "\n";
    Reference ref = load_reference(text);
    assert_true(ref.ok);
    assert_int_equal(ref.attrib.vertices.size(), tokens.size());
    size_t short_ones = 0;
    for (size_t i = 0; i < tokens.size(); i++) {
        const std::string &t = tokens[i];
        float got = obj_number::parse_real(t.data(), t.data() + t.size(), 0.0);
        if (!same_bits(got, ref.attrib.vertices[i]))
            fail_msg("'%s': parse_real gives %.9g, tinyobjloader %.9g", t.c_str(), double(got),
                     double(ref.attrib.vertices[i]));
        short_ones += obj_number::is_short_decimal(t.data(), t.data() + t.size());
    }
    printf("%zu tokens (%zu short decimals) read as tinyobjloader reads them\n", tokens.size(),
           short_ones);
}

/* is_short_decimal's promise: what it takes is a plain decimal of at most 9 integer digits. */
void short_decimals_are_plain(void **)
{
    static const char *const YES[] = {"0", "-0", "+1", ".5", "-.5", "5.", "123456789", "-123456789.987654321987"};
    static const char *const NO[] = {"", "-", "+", ".", "-.", "1234567890", "1e5", "1.5e",
                                     "0x1", "1.2.3", "1-", "nan", "1#", " 1"};
    for (const char *s : YES)
        if (!obj_number::is_short_decimal(s, s + strlen(s)))
            fail_msg("'%s' is a short decimal", s);
    for (const char *s : NO)
        if (obj_number::is_short_decimal(s, s + strlen(s)))
            fail_msg("'%s' is not a short decimal", s);
}

/* ------------------------------------------------------------------------ 2. files */

void find_objs(const std::string &dir, std::vector<std::string> *out)
{
    DIR *d = opendir(dir.c_str());
    assert_non_null(d);
    while (struct dirent *e = readdir(d)) {
        std::string name = e->d_name, path = dir + "/" + name;
        struct stat st;
        if (name[0] == '.' || stat(path.c_str(), &st) != 0)
            continue;
        if (S_ISDIR(st.st_mode))
            find_objs(path, out);
        else if (name.size() > 4 && name.compare(name.size() - 4, 4, ".obj") == 0)
            out->push_back(path);
    }
    closedir(d);
}

void assert_same_numbers(const std::string &path, const char *what, const std::vector<float> &got,
                         const std::vector<tinyobj::real_t> &want)
{
    if (got.size() != want.size())
        fail_msg("%s: %zu %s numbers, tinyobjloader %zu", path.c_str(), got.size(), what, want.size());
    for (size_t i = 0; i < got.size(); i++)
        if (!same_bits(got[i], want[i]))
            fail_msg("%s: %s number %zu is %.9g, tinyobjloader's %.9g", path.c_str(), what, i,
                     double(got[i]), double(want[i]));
}

/* Every face corner of the geometry read against LoadObj's, in file order. */
void assert_same_corners(const std::string &name, const obj_geometry::Geometry &g, const Reference &ref)
{
    size_t k = 0;
    for (const obj_geometry::Chunk &c : g.chunks)
        for (const obj_scan::Corner &corner : c.scan.corners) {
            if (k >= ref.corners.size())
                fail_msg("%s: more face corners than tinyobjloader's %zu", name.c_str(), ref.corners.size());
            const tinyobj::index_t &want = ref.corners[k++];
            if (corner.v != want.vertex_index || corner.vt != want.texcoord_index ||
                corner.vn != want.normal_index)
                fail_msg("%s: corner %zu is %d/%d/%d, tinyobjloader's %d/%d/%d", name.c_str(), k - 1,
                         corner.v, corner.vt, corner.vn, want.vertex_index, want.texcoord_index,
                         want.normal_index);
        }
    if (k != ref.corners.size())
        fail_msg("%s: %zu face corners, tinyobjloader %zu", name.c_str(), k, ref.corners.size());
}

/* An index rc10 accepts and the loader reads, in one of the ways files write it: plain, negative
 * (relative), with a '+' or leading zeros, or of 10 digits within int (past int, where atoi's
 * value wraps, the loader refuses it: indices_past_int_are_refused). */
std::string random_index(Random *r)
{
    static const char *const PREFIXES[] = {"", "", "", "", "-", "+", "00", "-0"};
    std::string s = PREFIXES[r->next(8)];
    uint32_t digits = r->next(8) == 0 ? 10 : 1 + r->next(3);
    s += static_cast<char>(digits == 10 ? '1' : '1' + r->next(9));
    for (uint32_t i = 1; i < digits; i++)
        s += static_cast<char>('0' + r->next(10));
    return s;
}

/* Faces of 3 to 6 corners in every form rc10 reads (v, v/t, v//n, v/t/n), blanks of spaces and
 * tabs, among v, vt and vn records, read by the geometry read against LoadObj. */
void faces_match_tinyobjloader(void **)
{
    static const char *const BLANKS[] = {" ", " ", "\t", "  ", " \t "};
    Random r{1203};
    std::string text;
    for (int i = 0; i < 20000; i++) {
        if (r.next(4) == 0)
            text += r.next(3) == 0 ? "v 1 2 3\n" : r.next(2) ? "vt 0.5 0.25\n" : "vn 0 0 1\n";
        text += "f";
        for (uint32_t c = 0, n = 3 + r.next(4); c < n; c++) {
            text += BLANKS[r.next(5)] + random_index(&r);
            switch (r.next(4)) {
            case 1: text += "/" + random_index(&r); break;
            case 2: text += "//" + random_index(&r); break;
            case 3: text += "/" + random_index(&r) + "/" + random_index(&r); break;
            }
        }
        text += r.next(8) == 0 ? " \n" : "\n";
    }
    obj_geometry::Geometry g;
    vkrt_error err = {{0}};
    if (!obj_geometry::parse_geometry("faces.obj", text.data(), 0, text.size(), obj_geometry::Split{4096, 2}, &g, &err))
        fail_msg("%s", err.msg);
    Reference ref = load_reference(text);
    assert_true(ref.ok);
    assert_same_corners("faces.obj", g, ref);
}

/* Where rc10 reads an index with atoi and the loader refuses it (obj_scan.cpp): past int, atoi's
 * long is truncated, so LoadObj takes 4294967298 as 2 and 99999999999999999999 (saturated to
 * LONG_MAX) as -1, the last vertex; "2x", "1.5" and "1e5" read as 2, 1 and 1. Each is a face
 * LoadObj accepts, as the index said here, and one the geometry read refuses with its line. */
void indices_past_int_are_refused(void **)
{
    static const struct {
        const char *index;
        int tinyobj; /* 0-based, as LoadObj gives it */
    } cases[] = {{"4294967298", 1}, {"99999999999999999999", 2}, {"2x", 1}, {"1.5", 0}, {"1e5", 0}};
    for (const auto &c : cases) {
        std::string text = std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 ") + c.index + "\n";
        Reference ref = load_reference(text);
        assert_true(ref.ok);
        assert_int_equal(ref.corners.size(), 3);
        assert_int_equal(ref.corners[2].vertex_index, c.tinyobj);
        obj_geometry::Geometry g;
        vkrt_error err = {{0}};
        assert_false(obj_geometry::parse_geometry("i.obj", text.data(), 0, text.size(),
                                                  obj_geometry::Split{0, 1}, &g, &err));
        if (strncmp(err.msg, "i.obj:4: face index ", 20) != 0)
            fail_msg("%s: %s", c.index, err.msg);
    }
}

/* Returns whether the file was compared (the geometry read and LoadObj both accept it). */
bool compare_file(const std::string &path)
{
    char *bytes;
    size_t size;
    vkrt_error err = {{0}};
    if (!vkrt_text_read_file(path.c_str(), SIZE_MAX, "OBJ", &bytes, &size, &err))
        fail_msg("%s", err.msg);
    std::string text(bytes, size);
    free(bytes);
    size_t start = 0;
    obj_geometry::Geometry g;
    if (!obj_scan::check_encoding(path.c_str(), text, &start, &err) ||
        !obj_geometry::parse_geometry(path.c_str(), text.data(), start, text.size(),
                                      obj_geometry::Split{0, 2}, &g, &err))
        return false; /* refused before tinyobjloader would read it (some of it unsafely) */
    Reference ref = load_reference(text.substr(start));
    if (!ref.ok)
        return false; /* a face it refuses: the loader fails there too */
    assert_same_numbers(path, "v", g.vertices, ref.attrib.vertices);
    assert_same_numbers(path, "vt", g.texcoords, ref.attrib.texcoords);
    assert_same_numbers(path, "vn", g.normals, ref.attrib.normals);
    assert_same_corners(path, g, ref);
    return true;
}

void files_match_tinyobjloader(void **)
{
    const char *dir = shared_scenes_dir();
    if (!dir)
        skip();
    std::vector<std::string> files;
    find_objs(dir, &files);
    size_t compared = 0;
    for (const std::string &f : files)
        compared += compare_file(f);
    printf("%zu of %zu OBJ files compared with tinyobjloader\n", compared, files.size());
    assert_true(compared > files.size() / 2);
}

} // namespace

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(numbers_match_tinyobjloader),
        cmocka_unit_test(short_decimals_are_plain),
        cmocka_unit_test(faces_match_tinyobjloader),
        cmocka_unit_test(indices_past_int_are_refused),
        cmocka_unit_test(files_match_tinyobjloader),
    };
    return cmocka_run_group_tests(tests, nullptr, nullptr);
}
