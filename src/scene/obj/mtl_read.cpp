/*
 * mtl_read.cpp: the .mtl files of an OBJ, read through tinyobjloader into the model's materials
 * (see mtl_read.h). A mirror of LoadMtl's line handling (scan_mtl_fields) reads which fields a
 * block set, on which line each texture statement stands, and every number vkrt reads, checked
 * (NUMBER_RULES: finite, in range, or a "file:LINE: ..." error; clamped with a warning where
 * the range's end is the only reading) before LoadMtl sees the text; the checked numbers replace
 * LoadMtl's, the rest (names, texture options) are LoadMtl's.
 */
/* The fuzz build defines TINYOBJLOADER_IMPLEMENTATION for every file: obj_load.cpp compiles it. */
#undef TINYOBJLOADER_IMPLEMENTATION
#include "mtl_read.h"

#include <sys/stat.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <istream>
#include <memory>
#include <new>

extern "C" {
#include "../text_file.h"
#include "mtl.h"
}
#include "obj_number.h"

namespace mtl_read {

using obj_scan::has_keyword;
using obj_scan::is_blank;
using obj_scan::LineWalker;
using obj_scan::Span;
using obj_warnings::Warnings;

/* The whole of path as a string, read by text_file.h (a file or a pipe); kind names the format in
 * the message for a file over OBJ_MAX_FILE_BYTES. */
static bool read_whole_file(const char *path, const char *kind, std::string *text, vkrt_error *err)
{
    char *bytes;
    size_t size;
    if (!vkrt_text_read_file(path, OBJ_MAX_FILE_BYTES, kind, &bytes, &size, err))
        return false;
    std::unique_ptr<char, void (*)(void *)> owned(bytes, free);
    text->assign(bytes, size);
    return true;
}



static bool file_exists(const std::string &path)
{
    struct stat st;
    return stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

/* A malloc'd string from text_file.c as a std::string; NULL is text_file.c's out of memory. */
static std::string take_string(char *s)
{
    if (!s)
        throw std::bad_alloc();
    std::unique_ptr<char, void (*)(void *)> owned(s, free);
    return std::string(s);
}

/* The folder of path, "" for a bare name (vkrt_text_dir_of). */
std::string folder_of(const std::string &path)
{
    return take_string(vkrt_text_dir_of(path.c_str()));
}

/* name under folder, unless name is absolute or folder is "" (vkrt_text_join_path). */
static std::string join_path(const std::string &folder, const std::string &name)
{
    return take_string(vkrt_text_join_path(folder.c_str(), name.c_str(), false));
}


/* ------------------------------------------------------------------ the numbers of an .mtl */

namespace {

/* How a key's numbers are checked (docs/scene-format.md has the table): each must be a plain
 * decimal that is finite as a float; above `high` it is clamped with a warning, below `low` too
 * where clamp_low, else it is an error (a negative colour or index has no nearest meaning). A
 * colour takes 1 number (grey: g = b = r, the MTL convention) or 3. Keys vkrt does not read
 * (aniso, anisor, texture options) are left to LoadMtl. */
struct NumberRule {
    const char *key;
    const char *slot; /* the key of MtlOrigin::numbers it sets */
    bool colour;
    float low, high;
    bool clamp_low;
    const char *why; /* after "is negative": the range the meaning allows */
};

constexpr float NO_LIMIT = FLT_MAX;

const NumberRule NUMBER_RULES[] = {
    {"Kd", "Kd", true, 0, 1, false, "a reflectance lies in [0, 1]"},
    {"Ks", "Ks", true, 0, 1, false, "a reflectance lies in [0, 1]"},
    {"Tf", "Tf", true, 0, 1, false, "a transmission filter lies in [0, 1]"},
    {"Kt", "Tf", true, 0, 1, false, "a transmission filter lies in [0, 1]"},
    {"Ka", "Ka", true, 0, NO_LIMIT, false, "a colour is 0 or more"},
    {"Ke", "Ke", true, 0, NO_LIMIT, false, "an emitted radiance is 0 or more"},
    {"Ns", "Ns", false, 0, NO_LIMIT, false, "a Phong exponent is 0 or more"},
    {"Ni", "Ni", false, 0, NO_LIMIT, false, "an index of refraction is above 0, or 0 for the default"},
    {"d", "d", false, 0, 1, true, ""},
    {"Tr", "d", false, 0, 1, true, ""},
    {"Pr", "Pr", false, 0, 1, true, ""},
    {"Pm", "Pm", false, 0, 1, true, ""},
    {"Pc", "Pc", false, 0, 4, true, ""},
    {"Pcr", "Pcr", false, 0, 1, true, ""},
    {"Ps", "Ps", false, 0, 1, true, ""},
};

/* The illumination models the MTL format defines. */
constexpr int ILLUM_MAX = 10;

/* Where the scan of one .mtl stands, for messages: its path, line and block. */
struct MtlScan {
    const std::string &path;
    Warnings *warnings;
    vkrt_error *err;
    std::string material; /* the current block's name, "" before the first newmtl */
    uint32_t line = 0;

    /* "material 'NAME': ", or "" before the first newmtl. */
    std::string of() const
    {
        return material.empty() ? std::string() : "material '" + obj_warnings::quoted(material) + "': ";
    }
    /* Sets "path:LINE: material 'NAME': what" and returns false. */
    bool fail(const std::string &what) const
    {
        return vkrt_error_set(err, "%s:%u: %s%s", path.c_str(), line, of().c_str(), what.c_str());
    }
};

std::string text_of(const Span &t) { return obj_warnings::quoted(std::string(t.b, t.e)); }

/* A float as a message shows it: "0.5", "1", "1e+06". */
std::string shown(float v)
{
    char buf[32];
    snprintf(buf, sizeof buf, "%g", static_cast<double>(v));
    return buf;
}

/* The float token t gives, as LoadMtl reads it (obj_number.h: the same float for a valid number),
 * if it is a plain decimal that is finite as a float; else false with the error set. */
bool read_number(const MtlScan &s, const std::string &key, const Span &t, float *out)
{
    if (obj_number::exponent_too_long(t.b, t.e)) /* undefined behaviour in LoadMtl */
        return s.fail(key + " " + text_of(t) + " has an exponent of more than 9 digits");
    if (!obj_number::is_plain_decimal(t.b, t.e))
        return s.fail(key + (obj_number::names_non_finite(t.b, t.e) ? " " + text_of(t) + " is not finite"
                                                                    : " '" + text_of(t) + "' is not a number"));
    *out = obj_number::parse_real(t.b, t.e, 0.0);
    if (!std::isfinite(*out))
        return s.fail(key + " " + text_of(t) + " is not finite (too large for a float)");
    return true;
}

/* The number tokens of rest, up to a '#' that starts a comment ("Ka 0.63 0.065 0.05 # Red"). */
std::vector<Span> number_tokens(Span rest)
{
    std::vector<Span> tokens;
    Span t;
    while (next_token(&rest, &t) && *t.b != '#')
        tokens.push_back(t);
    return tokens;
}

/* The numbers of one line of a NUMBER_RULES key (rest: after the key), checked, into *out (a
 * colour's three, or one); false with the error set. */
bool read_rule(const MtlScan &s, const NumberRule &rule, Span rest, std::array<float, 3> *out)
{
    std::vector<Span> tokens = number_tokens(rest);
    size_t wanted = rule.colour ? 3 : 1;
    std::string key = rule.key;
    if (rule.colour && !tokens.empty() && (text_of(tokens[0]) == "spectral" || text_of(tokens[0]) == "xyz"))
        return s.fail(key + " " + text_of(tokens[0]) + " is not supported; write " + key + " r g b");
    if (tokens.empty() || (rule.colour && tokens.size() == 2))
        return s.fail(key + (rule.colour ? " needs 1 or 3 numbers" : " needs a number") + ", found " +
                      std::to_string(tokens.size()));
    size_t n = tokens.size() < wanted ? 1 : wanted;
    std::string given = key, used;
    bool clamped = false;
    for (size_t i = 0; i < n; i++) {
        float v;
        if (!read_number(s, key, tokens[i], &v))
            return false;
        if (v < rule.low && !rule.clamp_low)
            return s.fail(key + " " + text_of(tokens[i]) + " is negative (" + rule.why + ")");
        float c = std::fmin(std::fmax(v, rule.low), rule.high);
        clamped |= c != v;
        (*out)[i] = c;
        given += " " + text_of(tokens[i]);
        used += (i ? " " : "") + shown(c);
    }
    for (size_t i = n; i < 3; i++) /* one number: grey */
        (*out)[i] = (*out)[0];
    std::string range = "[" + shown(rule.low) + ", " + shown(rule.high) + "]";
    if (clamped)
        obj_warnings::warn_mtl_number(s.path, s.line, s.of() + given + " is outside " + range + " (used " + used + ")",
                                      s.warnings);
    if (tokens.size() > wanted)
        obj_warnings::warn_mtl_number(s.path, s.line,
                                      s.of() + key + " has " + std::to_string(tokens.size()) +
                                          " numbers (used the first " + std::to_string(wanted) + ")",
                                      s.warnings);
    return true;
}

/* illum: a whole number of the MTL's models, 0 to ILLUM_MAX ("2.0" too: LoadMtl's atoi reads it
 * as 2). */
bool check_illum(const MtlScan &s, Span rest)
{
    std::vector<Span> tokens = number_tokens(rest);
    if (tokens.empty())
        return s.fail("illum needs a number, found 0");
    float v;
    if (!read_number(s, "illum", tokens[0], &v))
        return false;
    if (v != std::floor(v) || v < 0 || v > ILLUM_MAX)
        return s.fail("illum " + text_of(tokens[0]) + " is not an illumination model (0 to " +
                      std::to_string(ILLUM_MAX) + ")");
    if (tokens.size() > 1)
        obj_warnings::warn_mtl_number(s.path, s.line,
                                      s.of() + "illum has " + std::to_string(tokens.size()) +
                                          " numbers (used the first 1)",
                                      s.warnings);
    return true;
}

/* A NUMBER_RULES line or illum, checked into cur (LoadMtl's d-and-Tr rule: d wins whatever the
 * order, so a Tr after a d is ignored); true for any other line. */
bool scan_numbers(const MtlScan &s, const Span &line, bool *has_d, MtlOrigin *cur)
{
    if (has_keyword(line, "illum"))
        return check_illum(s, Span{line.b + 5, line.e});
    for (const NumberRule &rule : NUMBER_RULES) {
        if (!has_keyword(line, rule.key))
            continue;
        std::array<float, 3> v;
        if (!read_rule(s, rule, Span{line.b + strlen(rule.key), line.e}, &v))
            return false;
        bool tr = strcmp(rule.key, "Tr") == 0;
        if (tr && *has_d)
            return true;
        if (tr)
            v[0] = 1.0f - v[0];
        *has_d |= strcmp(rule.key, "d") == 0;
        cur->numbers[rule.slot] = v;
        return true;
    }
    return true;
}

/* Mirrors tinyobj::LoadMtl's line handling to see which keywords each material block has, on
 * which line each texture statement is (tinyobjloader keeps no line numbers), and to check every
 * number vkrt reads (scan_numbers) before LoadMtl sees it: false with "path:LINE: ..." in err
 * at the first bad one; values clamped are warnings. The blocks line up with the materials
 * LoadMtl pushes: one per named newmtl, plus the last one. */
bool scan_mtl_fields(const std::string &text, const std::string &path, std::vector<MtlOrigin> *out,
                     Warnings *warnings, vkrt_error *err)
{
    MtlOrigin cur;
    bool named = false, has_d = false;
    std::string folder = folder_of(path);
    auto none = [&folder, &path]() {
        MtlOrigin m;
        m.folder = folder;
        m.path = path;
        m.kd = m.ks = m.ke = m.ns = m.ni = m.d = m.illum = m.tf = false;
        return m;
    };
    cur = none();
    MtlScan s{path, warnings, err, std::string(), 0};
    LineWalker walker(text.data(), text.data() + text.size());
    Span line;
    while (walker.next(&line)) {
        while (line.e > line.b && is_blank(line.e[-1]))
            line.e--;
        while (line.b < line.e && is_blank(*line.b))
            line.b++;
        s.line = walker.number;
        if (has_keyword(line, "newmtl")) {
            if (named)
                out->push_back(cur);
            cur = none();
            named = line.len() > 7;
            has_d = false;
            s.material = named ? std::string(line.b + 7, line.e) : std::string();
            size_t b = s.material.find_first_not_of(" \t");
            s.material.erase(0, b == std::string::npos ? s.material.size() : b);
            continue;
        }
        if (!scan_numbers(s, line, &has_d, &cur))
            return false;
        cur.kd |= has_keyword(line, "Kd");
        cur.ks |= has_keyword(line, "Ks");
        cur.ke |= has_keyword(line, "Ke");
        cur.ns |= has_keyword(line, "Ns");
        cur.ni |= has_keyword(line, "Ni");
        cur.d |= has_keyword(line, "d") || has_keyword(line, "Tr");
        cur.illum |= has_keyword(line, "illum");
        cur.tf |= has_keyword(line, "Tf") || has_keyword(line, "Kt"); /* LoadMtl reads both */
        /* LoadMtl assigns the texture name, so a later statement replaces an earlier one. */
        if (has_keyword(line, "map_Kd"))
            cur.map_kd_line = walker.number;
        if (has_keyword(line, "map_d"))
            cur.map_d_line = walker.number;
        cur.pr |= has_keyword(line, "Pr");
        cur.pm |= has_keyword(line, "Pm");
        cur.pc |= has_keyword(line, "Pc");
        if (!cur.pc_line && has_keyword(line, "Pc"))
            cur.pc_line = walker.number;
        cur.map_pr_line = has_keyword(line, "map_Pr") ? walker.number : cur.map_pr_line;
        cur.map_pm_line = has_keyword(line, "map_Pm") ? walker.number : cur.map_pm_line;
        cur.ps |= has_keyword(line, "Ps");
        cur.map_ps_line = has_keyword(line, "map_Ps") ? walker.number : cur.map_ps_line;
        cur.norm_line = has_keyword(line, "norm") ? walker.number : cur.norm_line;
        if (has_keyword(line, "map_Bump") || has_keyword(line, "map_bump") || has_keyword(line, "bump"))
            cur.map_bump_line = walker.number;
        cur.map_ke_line = has_keyword(line, "map_Ke") ? walker.number : cur.map_ke_line;
        if (!cur.ps_line && (has_keyword(line, "Ps") || has_keyword(line, "map_Ps")))
            cur.ps_line = walker.number;
    }
    out->push_back(cur);
    return true;
}

/* The checked numbers of o over LoadMtl's in m. */
void apply_numbers(const MtlOrigin &o, tinyobj::material_t *m)
{
    struct Target {
        const char *slot;
        tinyobj::real_t *to;
        int count;
    } targets[] = {
        {"Kd", m->diffuse, 3},   {"Ks", m->specular, 3}, {"Tf", m->transmittance, 3},
        {"Ka", m->ambient, 3},   {"Ke", m->emission, 3}, {"Ns", &m->shininess, 1},
        {"Ni", &m->ior, 1},      {"d", &m->dissolve, 1}, {"Pr", &m->roughness, 1},
        {"Pm", &m->metallic, 1}, {"Pc", &m->clearcoat_thickness, 1},
        {"Pcr", &m->clearcoat_roughness, 1}, {"Ps", &m->sheen, 1},
    };
    for (const Target &t : targets) {
        auto found = o.numbers.find(t.slot);
        if (found != o.numbers.end())
            std::copy(found->second.begin(), found->second.begin() + t.count, t.to);
    }
}

} // namespace

/* "newmtl  RearLights" (two blanks, as a real exporter wrote it) names "RearLights" for other OBJ
 * readers; rc10 keeps the leading blank, so `usemtl RearLights` would miss it. The names LoadMtl
 * just added (from index `from` on) are trimmed, and the name map follows them. (LoadMtl trims
 * the ends of lines already, so trailing blanks never reach a name.) */
static void trim_material_names(std::vector<tinyobj::material_t> *materials, size_t from,
                         std::map<std::string, int> *material_map)
{
    for (size_t i = from; i < materials->size(); i++) {
        std::string &name = (*materials)[i].name;
        size_t b = name.find_first_not_of(" \t");
        if (b == 0 || b == std::string::npos)
            continue;
        auto it = material_map->find(name);
        if (it != material_map->end() && it->second == static_cast<int>(i))
            material_map->erase(it);
        name.erase(0, b);
        material_map->insert({name, static_cast<int>(i)}); /* as LoadMtl does: the first one wins */
    }
}

bool MtlReader::operator()(const std::string &name, std::vector<tinyobj::material_t> *materials,
                std::map<std::string, int> *material_map, std::string *warn, std::string *err)
{
    (void)warn; /* ours go to warnings_, in our words */
    if (failed)
        return false;
    std::string path = join_path(obj_folder_, name);
    std::string text;
    if (!file_exists(path) || !read_whole_file(path.c_str(), "material library", &text, nullptr)) {
        libraries.missing.emplace_back(name, path);
        return false;
    }
    std::vector<MtlOrigin> fields;
    if (!scan_mtl_fields(text, path, &fields, warnings_, &error)) {
        failed = true; /* before LoadMtl, which would read what the scan refused */
        return false;
    }
    size_t before = materials->size();
    MemoryBuffer buffer(text);
    std::istream stream(&buffer);
    std::string mtl_warn; /* LoadMtl assigns, not appends, to its warning string */
    tinyobj::LoadMtl(material_map, materials, &stream, &mtl_warn, err);
    trim_material_names(materials, before, material_map);
    obj_warnings::translate_mtl_warnings(path, mtl_warn, warnings_);
    libraries.loaded.push_back(path);
    size_t added = materials->size() - before;
    if (fields.size() != added) /* our mirror disagreed: trust all of tinyobjloader's values */
        fields.assign(added, MtlOrigin{folder_of(path), path});
    else
        for (size_t k = 0; k < added; k++)
            apply_numbers(fields[k], &(*materials)[before + k]);
    origins.insert(origins.end(), fields.begin(), fields.end());
    for (size_t k = 0; k < added; k++) { /* the line is 0 where there is nothing to say */
        const tinyobj::material_t &m = (*materials)[before + k];
        /* illum 3 and 5 are the mirror built-in, which has no coat (materials.c); illum 3 to
         * 7 are mirrors and glass, which have no sheen (the diffuse bases carry it). */
        bool mirror = m.illum == 3 || m.illum == 5;
        if (mirror && m.clearcoat_thickness > 0.0f)
            obj_warnings::warn_uncoated_mirror(path, fields[k].pc_line, m.name, warnings_);
        bool sheen = (fields[k].ps && m.sheen > 0.0f) || !m.sheen_texname.empty();
        if (sheen && m.illum >= 3 && m.illum <= 7)
            obj_warnings::warn_unrendered_sheen(path, fields[k].ps_line, m.name, warnings_);
    }
    return true;
}

char *copy_string(const std::string &s)
{
    char *out = static_cast<char *>(malloc(s.size() + 1));
    if (!out)
        throw std::bad_alloc();
    memcpy(out, s.c_str(), s.size() + 1);
    return out;
}

/* Windows exporters write ".\tex.jpg"; the file is found relative to the .mtl, or the OBJ. */
static std::string resolve_texture(std::string name, const std::string &mtl_folder, const std::string &obj_folder)
{
    for (char &c : name)
        if (c == '\\')
            c = '/';
    std::string beside_mtl = join_path(mtl_folder, name);
    if (!file_exists(beside_mtl) && mtl_folder != obj_folder && file_exists(join_path(obj_folder, name)))
        return join_path(obj_folder, name);
    return beside_mtl;
}

/* Non-finite .mtl values (tinyobjloader reads "1e999" as inf) fall back to the default. */
static float finite_or(float v, float fallback) { return std::isfinite(v) ? v : fallback; }

static void copy3(float dst[3], const float src[3], bool present, float fallback)
{
    for (int i = 0; i < 3; i++)
        dst[i] = present ? finite_or(src[i], fallback) : fallback;
}

static void convert_material(const tinyobj::material_t &m, const MtlOrigin &o, const std::string &obj_folder,
                      vkrt_mtl *out)
{
    copy3(out->kd, m.diffuse, o.kd, 0.8f);
    copy3(out->ks, m.specular, o.ks, 0.0f);
    copy3(out->ke, m.emission, o.ke, 0.0f);
    out->ns = o.ns ? finite_or(m.shininess, 0.0f) : 0.0f;
    out->ni = o.ni ? finite_or(m.ior, 1.0f) : 1.0f;
    out->d = o.d ? finite_or(m.dissolve, 1.0f) : 1.0f;
    out->illum = o.illum ? m.illum : 2;
    copy3(out->tf, m.transmittance, o.tf, 1.0f);
    out->name = copy_string(m.name);
    if (!o.path.empty())
        out->mtl_path = copy_string(o.path);
    out->map_kd_line = static_cast<int>(o.map_kd_line);
    out->map_d_line = static_cast<int>(o.map_d_line);
    out->map_pr_line = static_cast<int>(o.map_pr_line);
    out->map_pm_line = static_cast<int>(o.map_pm_line);
    out->map_ps_line = static_cast<int>(o.map_ps_line);
    auto map = [&](const std::string &name) -> char * {
        return name.empty() ? nullptr : copy_string(resolve_texture(name, o.folder, obj_folder));
    };
    out->map_kd = map(m.diffuse_texname);
    out->map_d = map(m.alpha_texname);
    out->map_pr = map(m.roughness_texname);
    out->map_pm = map(m.metallic_texname);
    out->map_ps = map(m.sheen_texname);
    out->norm_line = static_cast<int>(o.norm_line);
    out->map_bump_line = static_cast<int>(o.map_bump_line);
    out->map_ke_line = static_cast<int>(o.map_ke_line);
    out->norm = map(m.normal_texname);
    out->map_bump = map(m.bump_texname);
    out->map_ke = map(m.emissive_texname);
    /* -bm is read from whichever statement names the map vkrt uses (norm before map_Bump). */
    const tinyobj::texture_option_t &bump = out->norm ? m.normal_texopt : m.bump_texopt;
    out->bump_multiplier = finite_or(bump.bump_multiplier, 1.0f);
    out->ke_given = o.ke;
    /* A clear coat (Pc above 0) and a sheen (Ps above 0, or map_Ps) are the PBR extension's
     * too: the GGX built-ins render them. Glass has no sheen, so a sheen alone leaves it the
     * smooth glass (the loader warns). */
    bool coated = o.pc && finite_or(m.clearcoat_thickness, 0.0f) > 0.0f;
    bool glass = out->illum == 4 || out->illum == 6 || out->illum == 7;
    bool sheen = !glass && ((o.ps && finite_or(m.sheen, 0.0f) > 0.0f) || out->map_ps);
    out->pbr = o.pr || o.pm || coated || sheen || out->map_pr || out->map_pm;
    out->ps = o.ps ? finite_or(m.sheen, 0.0f) : 0.0f;
    out->pr = o.pr ? finite_or(m.roughness, 0.0f) : -1.0f;
    out->pm = o.pm ? finite_or(m.metallic, 0.0f) : 0.0f;
    out->pc = finite_or(m.clearcoat_thickness, 0.0f);
    out->pcr = finite_or(m.clearcoat_roughness, 0.0f);
}

void convert_materials(const std::vector<tinyobj::material_t> &materials, const MtlReader &reader,
                       const std::string &obj_folder, vkrt_model *model)
{
    if (materials.empty())
        return;
    model->materials = static_cast<vkrt_material *>(calloc(materials.size(), sizeof(vkrt_material)));
    if (!model->materials)
        throw std::bad_alloc();
    model->material_count = static_cast<uint32_t>(materials.size());
    for (size_t i = 0; i < materials.size(); i++) {
        MtlOrigin origin =
            i < reader.origins.size() ? reader.origins[i] : MtlOrigin{obj_folder, std::string()};
        vkrt_mtl mtl = {};
        struct Freed {
            vkrt_mtl *m;
            ~Freed() { vkrt_mtl_free(m); }
        } freed{&mtl};
        convert_material(materials[i], origin, obj_folder, &mtl);
        if (!vkrt_mtl_to_material(&mtl, &model->materials[i]))
            throw std::bad_alloc();
    }
}

} // namespace mtl_read
