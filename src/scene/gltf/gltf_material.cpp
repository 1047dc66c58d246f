/*
 * gltf_material.cpp: glTF materials into vkrt's physically based records (gltf_context.h), with
 * their textures. Each mapping and what it approximates is docs/materials.md's "glTF 2.0
 * materials"; the numbers in brief:
 *   base_colour = baseColorFactor.rgb, map: baseColorTexture (sRGB)
 *   roughness = roughnessFactor, map: metallicRoughnessTexture's green; metallic =
 *     metallicFactor, map: its blue (the texture refs' channel)
 *   detail: normalTexture, detail_scale = its scale
 *   emission = emissiveFactor * KHR_materials_emissive_strength, map: emissiveTexture
 *   opacity = baseColorFactor.a (BLEND), 1 or 0 by alphaCutoff (MASK), 1 (OPAQUE)
 *   KHR_materials_transmission >= 0.5: glass of KHR_materials_ior, tinted by the base colour
 *   coat = clearcoatFactor, coat_roughness = clearcoatRoughnessFactor
 *   sheen = max(sheenColorFactor)
 *   KHR_materials_specular: ior made so that ((ior-1)/(ior+1))^2 = F0 * specularFactor *
 *     max(specularColorFactor), F0 that of KHR_materials_ior
 */
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <new>

#include "gltf_context.h"

namespace gltf {

namespace {

/* The extensions this file reads of a material or texture info; others are noted. */
const char *const MATERIAL_EXTENSIONS[] = {
    "KHR_materials_emissive_strength", "KHR_materials_transmission", "KHR_materials_ior",
    "KHR_materials_volume",            "KHR_materials_clearcoat",    "KHR_materials_sheen",
    "KHR_materials_specular",
};

char *copy(const std::string &s)
{
    char *p = strdup(s.c_str());
    if (!p)
        throw std::bad_alloc();
    return p;
}

/* A number of an extension object, or fallback when it has none. */
double number(const tinygltf::Value &object, const char *key, double fallback)
{
    if (!object.IsObject() || !object.Has(key))
        return fallback;
    const tinygltf::Value &v = object.Get(key);
    return v.IsNumber() && std::isfinite(v.GetNumberAsDouble()) ? v.GetNumberAsDouble() : fallback;
}

/* An array of n numbers of an extension object into out, or false (out untouched). */
bool numbers(const tinygltf::Value &object, const char *key, size_t n, double *out)
{
    if (!object.IsObject() || !object.Has(key))
        return false;
    const tinygltf::Value &v = object.Get(key);
    if (!v.IsArray() || v.ArrayLen() != n)
        return false;
    for (size_t i = 0; i < n; ++i)
        if (!v.Get((int)i).IsNumber())
            return false;
    for (size_t i = 0; i < n; ++i)
        out[i] = v.Get((int)i).GetNumberAsDouble();
    return true;
}

const tinygltf::Value *extension(const tinygltf::ExtensionMap &map, const char *name)
{
    auto it = map.find(name);
    return it == map.end() ? nullptr : &it->second;
}

float clamp01(double x)
{
    return (float)std::min(std::max(std::isfinite(x) ? x : 0.0, 0.0), 1.0);
}

/* "a%20b" -> "a b": glTF's uris are percent-encoded (RFC 3986). */
std::string uri_decode(const std::string &uri)
{
    std::string out;
    for (size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '%' && i + 2 < uri.size() && isxdigit((unsigned char)uri[i + 1]) &&
            isxdigit((unsigned char)uri[i + 2])) {
            out += (char)strtol(uri.substr(i + 1, 2).c_str(), nullptr, 16);
            i += 2;
        } else
            out += uri[i];
    }
    return out;
}

vkrt_wrap wrap_of(int mode)
{
    switch (mode) {
    case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: return VKRT_WRAP_CLAMP;
    case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: return VKRT_WRAP_MIRROR;
    }
    return VKRT_WRAP_REPEAT;
}

/* The vkrt image (model->images index, or the path in *path) of glTF image `image`, made on
 * first use. */
int32_t image_ref(Context &c, int image, const std::string &where, std::string *path)
{
    const ImageSource &src = c.images[(size_t)image];
    const tinygltf::Image &img = c.gltf.images[(size_t)image];
    std::string name = c.name + ": " + item("images", (size_t)image) +
                       (img.name.empty() ? "" : " (\"" + img.name + "\")");
    if (!src.embedded) {
        std::string file = uri_decode(src.uri);
        if (!c.folder) { /* nothing is looked for: the name stands for the file */
            *path = file;
            return -1;
        }
        *path = file[0] == '/' || !*c.folder ? file : std::string(c.folder) + "/" + file;
        return -1;
    }
    *path = name;
    int32_t &blob = c.image_blob[(size_t)image];
    if (blob >= 0)
        return blob;
    (void)where;
    vkrt_model *m = c.model;
    vkrt_image_blob *grown = static_cast<vkrt_image_blob *>(
        realloc(m->images, (m->image_count + 1) * sizeof(vkrt_image_blob)));
    if (!grown)
        throw std::bad_alloc();
    m->images = grown;
    vkrt_image_blob *b = &m->images[m->image_count];
    memset(b, 0, sizeof *b);
    ++m->image_count;
    b->name = copy(name);
    b->size = src.bytes.size();
    b->bytes = static_cast<unsigned char *>(malloc(b->size ? b->size : 1));
    if (!b->bytes)
        throw std::bad_alloc();
    memcpy(b->bytes, src.bytes.data(), b->size);
    blob = (int32_t)(m->image_count - 1);
    return blob;
}

/* Fills ref from a texture info (index, texCoord, extensions) of material `where`; channel is
 * the channel a one-number map reads. Nothing when index < 0. */
void texture_ref(Context &c, int index, int tex_coord, const tinygltf::ExtensionMap &extensions,
                 uint32_t channel, const std::string &where, vkrt_texture_ref *ref)
{
    if (index < 0)
        return;
    const tinygltf::Model &g = c.gltf;
    if ((size_t)index >= g.textures.size())
        c.fail(where, "texture " + std::to_string(index) + " is not one of the file's " +
                          std::to_string(g.textures.size()));
    const tinygltf::Texture &tex = g.textures[(size_t)index];
    std::string at = item("textures", (size_t)index);
    for (const auto &e : tex.extensions)
        c.warn(at + ": extension " + e.first + " is not read (its source image is used)",
               "texture-extension", e.first,
               "textures use extensions that are not read (their source images are used)");
    if (tex.source < 0 || (size_t)tex.source >= g.images.size())
        c.fail(at, "source " + std::to_string(tex.source) + " is not one of the file's " +
                       std::to_string(g.images.size()) + " images");
    if (tex.sampler >= 0) {
        if ((size_t)tex.sampler >= g.samplers.size())
            c.fail(at, "sampler " + std::to_string(tex.sampler) + " is not one of the file's " +
                           std::to_string(g.samplers.size()));
        const tinygltf::Sampler &s = g.samplers[(size_t)tex.sampler];
        ref->sampler.wrap_u = wrap_of(s.wrapS);
        ref->sampler.wrap_v = wrap_of(s.wrapT);
    }
    std::string path;
    ref->embedded = image_ref(c, tex.source, where, &path);
    free(ref->path);
    ref->path = copy(path);
    ref->channel = channel;
    ref->uv_set = tex_coord > 0 ? 1u : 0u;
    if (tex_coord > 1)
        c.warn(where + ": texCoord " + std::to_string(tex_coord) + " is read as TEXCOORD_1");
    if (const tinygltf::Value *t = extension(extensions, "KHR_texture_transform")) {
        double o[2] = {0, 0}, s[2] = {1, 1};
        numbers(*t, "offset", 2, o);
        numbers(*t, "scale", 2, s);
        double r = number(*t, "rotation", 0);
        if (t->IsObject() && t->Has("texCoord"))
            ref->uv_set = number(*t, "texCoord", 0) > 0 ? 1u : 0u;
        /* Kept as the file gives them: the model applies them in glTF's own uv (model.h,
         * vkrt_texture_ref), so no conversion here. */
        for (int i = 0; i < 2; ++i) {
            ref->uv_offset[i] = (float)o[i];
            ref->uv_scale[i] = (float)s[i];
        }
        ref->uv_rotation = (float)r;
    }
}

void read_material(Context &c, size_t index, vkrt_material *m)
{
    const tinygltf::Material &gm = c.gltf.materials[index];
    std::string where = item("materials", index);
    const tinygltf::PbrMetallicRoughness &pbr = gm.pbrMetallicRoughness;
    m->name = copy(gm.name.empty() ? where : gm.name);
    m->file = copy(c.name);
    m->bsdf = VKRT_BSDF_PRINCIPLED;
    double base[4] = {1, 1, 1, 1};
    if (pbr.baseColorFactor.size() == 4)
        std::copy(pbr.baseColorFactor.begin(), pbr.baseColorFactor.end(), base);
    for (int k = 0; k < 3; ++k)
        m->base_colour[k] = clamp01(base[k]);
    m->metallic = clamp01(pbr.metallicFactor);
    m->roughness = clamp01(pbr.roughnessFactor);
    m->ior = 1.5f;
    texture_ref(c, pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord,
                pbr.baseColorTexture.extensions, 0, where + ".baseColorTexture",
                &m->maps[VKRT_MAP_BASE_COLOUR]);
    const tinygltf::TextureInfo &mr = pbr.metallicRoughnessTexture;
    texture_ref(c, mr.index, mr.texCoord, mr.extensions, 1, where + ".metallicRoughnessTexture",
                &m->maps[VKRT_MAP_ROUGHNESS]);
    texture_ref(c, mr.index, mr.texCoord, mr.extensions, 2, where + ".metallicRoughnessTexture",
                &m->maps[VKRT_MAP_METALLIC]);
    const tinygltf::NormalTextureInfo &nt = gm.normalTexture;
    texture_ref(c, nt.index, nt.texCoord, nt.extensions, 0, where + ".normalTexture",
                &m->maps[VKRT_MAP_DETAIL]);
    m->detail_kind = VKRT_DETAIL_NORMAL;
    m->detail_scale = std::isfinite(nt.scale) ? (float)nt.scale : 1.0f;
    if (gm.occlusionTexture.index >= 0)
        c.warn(where + ": occlusionTexture is not read (a path tracer computes occlusion)",
               "occlusion", where,
               "{n} materials have an occlusionTexture, not read (a path tracer computes "
               "occlusion)");
    double strength = 1;
    if (const tinygltf::Value *e = extension(gm.extensions, "KHR_materials_emissive_strength"))
        strength = std::max(number(*e, "emissiveStrength", 1), 0.0);
    for (int k = 0; k < 3 && gm.emissiveFactor.size() == 3; ++k)
        m->emission[k] = (float)(std::max(gm.emissiveFactor[k], 0.0) * strength);
    texture_ref(c, gm.emissiveTexture.index, gm.emissiveTexture.texCoord,
                gm.emissiveTexture.extensions, 0, where + ".emissiveTexture",
                &m->maps[VKRT_MAP_EMISSION]);
    /* Alpha: BLEND as coverage (the see-through share the .mtl's d gives), MASK as all or
     * nothing at alphaCutoff for the factor; a base colour texture's alpha cuts either out
     * stochastically (lib/cutout.glsl), so MASK's edges are a coverage there, not a cutoff. */
    if (gm.alphaMode == "BLEND")
        m->opacity = clamp01(base[3]);
    else if (gm.alphaMode == "MASK")
        m->opacity = base[3] >= gm.alphaCutoff ? 1.0f : 0.0f;
    else if (gm.alphaMode != "OPAQUE" && !gm.alphaMode.empty())
        c.fail(where, "alphaMode \"" + gm.alphaMode + "\" is not OPAQUE, MASK or BLEND");
    double ior = 1.5;
    if (const tinygltf::Value *e = extension(gm.extensions, "KHR_materials_ior"))
        ior = number(*e, "ior", 1.5);
    if (!(ior >= 1.0) || ior > 10.0)
        ior = 1.5;
    m->ior = (float)ior;
    if (const tinygltf::Value *e = extension(gm.extensions, "KHR_materials_specular")) {
        double colour[3] = {1, 1, 1};
        numbers(*e, "specularColorFactor", 3, colour);
        double f0 = std::pow((ior - 1) / (ior + 1), 2) * clamp01(number(*e, "specularFactor", 1)) *
                    std::max({colour[0], colour[1], colour[2], 0.0});
        double r = std::sqrt(std::min(f0, 0.81));
        /* The pbr built-in reads an index of 1 or less as 1.5: a specular of 0 keeps just above. */
        m->ior = (float)std::max((1 + r) / (1 - r), 1.0001);
    }
    if (const tinygltf::Value *e = extension(gm.extensions, "KHR_materials_clearcoat")) {
        m->coat = clamp01(number(*e, "clearcoatFactor", 0));
        m->coat_roughness = clamp01(number(*e, "clearcoatRoughnessFactor", 0));
    }
    if (const tinygltf::Value *e = extension(gm.extensions, "KHR_materials_sheen")) {
        double colour[3] = {0, 0, 0};
        numbers(*e, "sheenColorFactor", 3, colour);
        m->sheen = clamp01(std::max({colour[0], colour[1], colour[2]}));
    }
    if (const tinygltf::Value *e = extension(gm.extensions, "KHR_materials_transmission")) {
        /* vkrt has no blend of glass and the rest: half transmission or more is glass. */
        if (number(*e, "transmissionFactor", 0) >= 0.5) {
            m->bsdf = m->roughness > 0 ? VKRT_BSDF_ROUGH_DIELECTRIC : VKRT_BSDF_DIELECTRIC;
            m->ior = (float)ior;
            for (int k = 0; k < 3; ++k)
                m->transmission_filter[k] = m->base_colour[k];
            if (!extension(gm.extensions, "KHR_materials_volume"))
                c.warn(where + ": transmission without KHR_materials_volume is thin-walled; "
                               "vkrt renders it as solid glass",
                       "thin", where,
                       "{n} materials are thin-walled glass (transmission without "
                       "KHR_materials_volume), rendered as solid glass");
        }
    }
    for (const auto &e : gm.extensions) {
        bool known = false;
        for (const char *k : MATERIAL_EXTENSIONS)
            known |= e.first == k;
        if (!known)
            c.warn(where + ": extension " + e.first + " is not read", "material-extension",
                   e.first, "materials use extensions that are not read");
    }
}

} // namespace

void read_materials(Context &c)
{
    size_t count = c.gltf.materials.size();
    c.image_blob.assign(c.gltf.images.size(), -1);
    if (count > INT32_MAX)
        c.fail("materials", "too many");
    c.model->materials =
        static_cast<vkrt_material *>(calloc(count ? count : 1, sizeof(vkrt_material)));
    if (!c.model->materials)
        throw std::bad_alloc();
    for (size_t i = 0; i < count; ++i) {
        vkrt_material_defaults(&c.model->materials[i]);
        c.model->material_count = (uint32_t)i + 1;
        read_material(c, i, &c.model->materials[i]);
    }
}

} // namespace gltf
