/*
 * gltf_read.cpp: reading a .gltf or .glb and checking it (gltf_load.h), then handing the parsed
 * file to the other parts (gltf_context.h) in order: scene tree, meshes, instances, materials,
 * lights, cameras.
 *
 * tinygltf parses the JSON and decodes the buffers; it is given callbacks so that it touches
 * the file system only through this file (no wordexp of paths, every file read listed as an
 * input) and decodes no image: the image callback keeps embedded images' encoded bytes, after
 * checking that their buffer view lies in its buffer (tinygltf 2.7.0 does not). A .glb's header
 * and chunk lengths are checked here before tinygltf sees it: its own check lets a BIN chunk's
 * length run 8 bytes past the file.
 */
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <new>
#include <sys/stat.h>

#include "gltf_context.h"

extern "C" {
#include "../text_file.h"
}

namespace gltf {

namespace {

/* A .glb over 4 GiB cannot be: its header counts bytes in 32 bits. */
const size_t MAX_FILE_BYTES = (size_t)UINT32_MAX;

/* The extensions vkrt reads (docs/scene-format.md); a file that requires another is refused. */
const char *const SUPPORTED_EXTENSIONS[] = {
    "KHR_materials_emissive_strength", "KHR_materials_transmission", "KHR_materials_ior",
    "KHR_materials_volume",            "KHR_materials_clearcoat",    "KHR_materials_sheen",
    "KHR_materials_specular",          "KHR_texture_transform",      "KHR_lights_punctual",
    "EXT_mesh_gpu_instancing",         "KHR_mesh_quantization",
};

bool supported(const std::string &name)
{
    for (const char *s : SUPPORTED_EXTENSIONS)
        if (name == s)
            return true;
    return false;
}

/* What the callbacks share with the load. */
struct Callbacks {
    const tinygltf::Model *model = nullptr; /* being filled by tinygltf */
    bool read_files = true;                 /* false: no file may be read (vkrt_gltf_parse) */
    std::vector<std::string> inputs;        /* the files read */
    std::vector<ImageSource> images;        /* per image, in the file's order */
    std::string image_error;                /* why an image was refused */
};

bool file_exists(const std::string &path, void *user)
{
    struct stat st;
    return static_cast<Callbacks *>(user)->read_files && stat(path.c_str(), &st) == 0 &&
           S_ISREG(st.st_mode);
}

std::string expand_path(const std::string &path, void *)
{
    return path; /* as written: tinygltf's default would run wordexp on it */
}

/* tinygltf reads the buffers (step 3 of its parse) before anything else that refers to them,
 * and images (step 11) after the buffer views, accessors, meshes, nodes, scenes and materials:
 * once any of those is there, the file asked for is an image, which is not read here (texture.c
 * reads it when a material uses it): a byte stands for it. */
bool reading_images(const tinygltf::Model &m)
{
    return !m.bufferViews.empty() || !m.accessors.empty() || !m.meshes.empty() ||
           !m.nodes.empty() || !m.scenes.empty() || !m.materials.empty();
}

bool read_whole_file(std::vector<unsigned char> *out, std::string *err, const std::string &path,
                     void *user)
{
    Callbacks *cb = static_cast<Callbacks *>(user);
    if (!cb->read_files) {
        *err = "'" + path + "': external files are not read here";
        return false;
    }
    if (reading_images(*cb->model)) {
        out->assign(1, 0);
        return true;
    }
    char *bytes = nullptr;
    size_t size = 0;
    vkrt_error e = {{0}};
    if (!vkrt_text_read_file(path.c_str(), MAX_FILE_BYTES, "glTF buffer", &bytes, &size, &e)) {
        *err = e.msg;
        return false;
    }
    out->assign(bytes, bytes + size);
    free(bytes);
    cb->inputs.push_back(path);
    return true;
}

bool write_whole_file(std::string *err, const std::string &, const std::vector<unsigned char> &,
                      void *)
{
    *err = "vkrt writes no glTF";
    return false;
}

/* Keeps an image's encoded bytes (embedded) or notes its uri (external), decoding nothing. */
bool keep_image(tinygltf::Image *image, const int index, std::string *err, std::string *, int,
                int, const unsigned char *bytes, int size, void *user)
{
    Callbacks *cb = static_cast<Callbacks *>(user);
    if (index < 0)
        return false;
    if ((size_t)index >= cb->images.size())
        cb->images.resize((size_t)index + 1);
    ImageSource &src = cb->images[(size_t)index];
    image->as_is = true;
    if (image->bufferView >= 0) {
        /* tinygltf hands over &buffer.data[byteOffset] and byteLength unchecked. */
        const tinygltf::Model &m = *cb->model;
        const tinygltf::BufferView &bv = m.bufferViews[(size_t)image->bufferView];
        size_t buffer_bytes = m.buffers[(size_t)bv.buffer].data.size();
        if (bv.byteOffset > buffer_bytes || bv.byteLength > buffer_bytes - bv.byteOffset) {
            cb->image_error = "images[" + std::to_string(index) + "]: bufferViews[" +
                              std::to_string(image->bufferView) + "] runs past the end of buffer " +
                              std::to_string(bv.buffer) + " (" + std::to_string(buffer_bytes) +
                              " bytes)";
            *err += cb->image_error;
            return false;
        }
        src.embedded = true;
        src.bytes.assign(bytes, bytes + bv.byteLength);
    } else if (!image->uri.empty()) {
        src.uri = image->uri;
    } else {
        src.embedded = true;
        src.bytes.assign(bytes, bytes + (size > 0 ? size : 0));
    }
    return true;
}

uint32_t little_endian32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

/* The .glb's header and chunks (glTF 2.0 spec 4.4), checked; throws with what is wrong. */
void check_glb(const std::string &name, const unsigned char *b, size_t size)
{
    auto fail = [&](const std::string &what) { throw LoadError(name + ": " + what); };
    if (size < 20)
        fail("a .glb of " + std::to_string(size) + " bytes is shorter than its 20-byte header");
    uint32_t version = little_endian32(b + 4), length = little_endian32(b + 8);
    if (version != 2)
        fail("glTF binary version " + std::to_string(version) + "; vkrt reads version 2");
    if (length != size)
        fail("the .glb header says " + std::to_string(length) + " bytes but the file has " +
             std::to_string(size));
    uint64_t json_length = little_endian32(b + 12);
    if (little_endian32(b + 16) != 0x4E4F534Au)
        fail("the .glb's first chunk is not JSON");
    if (json_length == 0 || 20 + json_length > size)
        fail("the .glb's JSON chunk length " + std::to_string(json_length) + " runs past the " +
             std::to_string(size) + " bytes of the file");
    uint64_t at = 20 + json_length;
    if (at == size)
        return;
    if (at + 8 > size)
        fail("the .glb has " + std::to_string(size - at) +
             " bytes after its JSON chunk, too few for a chunk header");
    uint64_t bin_length = little_endian32(b + at);
    if (at + 8 + bin_length > size)
        fail("the .glb's second chunk length " + std::to_string(bin_length) +
             " runs past the end of the file (" + std::to_string(size - at - 8) + " bytes left)");
    if (little_endian32(b + at + 4) != 0x004E4942u)
        fail("the .glb's second chunk is not BIN");
}

/* tinygltf's message (its first line), without nlohmann's "[json.exception...] " prefix. */
std::string tinygltf_message(const std::string &err)
{
    std::string s = err.substr(0, err.find('\n'));
    if (s.rfind("[json.exception", 0) == 0) {
        size_t close = s.find("] ");
        s = "malformed JSON: " + (close == std::string::npos ? s : s.substr(close + 2));
    }
    return s.empty() ? "tinygltf could not read it" : s;
}

char *copy_string(const std::string &s)
{
    char *p = strdup(s.c_str());
    if (!p)
        throw std::bad_alloc();
    return p;
}
/* Triangles of zero area (their corners on a line or at one point) no ray hits and no light
 * samples: dropped as the OBJ loader drops them, with one warning; instances of a mesh left with
 * none place nothing, and a file of nothing else is an error. */
static void drop_zero_area(Context &c, const std::string &name)
{
    vkrt_model *model = c.model;
    uint64_t triangles = 0, dropped = 0;
    for (uint32_t m = 0; m < model->mesh_count; ++m) {
        triangles += model->meshes[m].triangle_count;
        dropped += vkrt_mesh_drop_degenerate(&model->meshes[m]);
    }
    uint32_t kept = 0;
    for (uint32_t i = 0; i < model->instance_count; ++i)
        if (model->meshes[model->instances[i].mesh].triangle_count > 0)
            model->instances[kept++] = model->instances[i];
    model->instance_count = kept;
    if (triangles > 0 && dropped == triangles)
        throw LoadError(name + ": all " + std::to_string(triangles) +
                        " triangles have zero area (their corners lie on a line or at one "
                        "point): nothing to draw");
    obj_warnings::warn_degenerate_triangles(name.c_str(), (size_t)dropped, &c.warnings);
}


bool parse(const unsigned char *bytes, size_t size, const std::string &name, const char *folder,
           const vkrt_load_options &options, vkrt_model *model, vkrt_error *err)
{
    if (size > MAX_FILE_BYTES)
        throw LoadError(name + ": larger than 4 GiB");
    bool binary = size >= 4 && memcmp(bytes, "glTF", 4) == 0;
    if (binary)
        check_glb(name, bytes, size);
    tinygltf::Model g;
    Callbacks cb;
    cb.model = &g;
    cb.read_files = folder != nullptr;
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(keep_image, &cb);
    loader.SetFsCallbacks(tinygltf::FsCallbacks{file_exists, expand_path, read_whole_file,
                                                write_whole_file, &cb});
    std::string tiny_err, tiny_warn;
    std::string base = folder ? folder : "";
    bool ok = binary ? loader.LoadBinaryFromMemory(&g, &tiny_err, &tiny_warn, bytes,
                                                   (unsigned int)size, base)
                     : loader.LoadASCIIFromString(&g, &tiny_err, &tiny_warn,
                                                  reinterpret_cast<const char *>(bytes),
                                                  (unsigned int)size, base);
    if (!ok)
        throw LoadError(name + ": " + (cb.image_error.empty() ? tinygltf_message(tiny_err)
                                                                : cb.image_error));
    std::string unsupported;
    for (const std::string &e : g.extensionsRequired)
        if (!supported(e))
            unsupported += (unsupported.empty() ? "" : ", ") + e;
    if (!unsupported.empty())
        throw LoadError(name + ": the file requires extensions vkrt does not support: " +
                        unsupported);
    Context c(g, name, folder, options, model);
    cb.images.resize(g.images.size());
    for (size_t i = 0; i < g.images.size(); ++i)
        if (!cb.images[i].embedded && cb.images[i].uri.empty())
            cb.images[i].uri = g.images[i].uri; /* an external image tinygltf did not find */
    c.images = std::move(cb.images);
    for (const std::string &e : g.extensionsUsed)
        if (!supported(e))
            c.warn("extension " + e + " is not read", "extension", e,
                   "{n} extensions the file uses are not read");
    if (!g.skins.empty())
        c.warn("skins are not applied: skinned meshes render at their rest pose");
    walk_scene(c);
    read_materials(c);
    read_meshes(c, used_meshes(c));
    read_instances(c);
    drop_zero_area(c, name);
    if (model->instance_count == 0)
        throw LoadError(name + ": no triangles in the scene");
    read_lights(c);
    read_cameras(c);
    /* Images a material names must be there: texture.c would say so later, but only for the
     * materials a triangle uses, and the scene cache must not keep a model naming a lost file. */
    for (uint32_t i = 0; i < model->material_count; ++i)
        for (const vkrt_texture_ref &t : model->materials[i].maps) {
            struct stat st;
            if (folder && t.path && t.embedded < 0 && stat(t.path, &st) != 0)
                throw LoadError(name + ": " + item("materials", i) + ": image '" + t.path +
                                "' not found");
        }
    obj_warnings::set_warnings(c.warnings, model);
    std::string inputs;
    for (const std::string &f : cb.inputs)
        inputs += f + "\n";
    model->inputs = inputs.empty() ? nullptr : copy_string(inputs);
    return vkrt_model_finish(model, err);
}

/* Runs body with every exception turned into err (LoadError's message whole, others about
 * name), and model freed on failure: nothing C++ crosses into C. */
template <typename Body>
bool guarded(const std::string &name, vkrt_model *model, vkrt_error *err, Body body)
{
    bool ok = false;
    try {
        ok = body();
    } catch (const LoadError &e) {
        ok = vkrt_error_set(err, "%s", e.what());
    } catch (const std::bad_alloc &) {
        ok = vkrt_error_set(err, "%s: out of memory", name.c_str());
    } catch (const std::exception &e) {
        ok = vkrt_error_set(err, "%s: %s", name.c_str(), e.what());
    } catch (...) {
        ok = vkrt_error_set(err, "%s: unexpected error while loading", name.c_str());
    }
    if (!ok)
        vkrt_model_free(model);
    return ok;
}

} // namespace

void Context::fail(const std::string &where, const std::string &what) const
{
    throw LoadError(name + ": " + (where.empty() ? "" : where + ": ") + what);
}

void Context::warn(const std::string &text, const std::string &kind, const std::string &item_name,
                   const std::string &fold)
{
    obj_warnings::Warning w;
    w.file = name;
    w.text = text;
    w.kind = kind;
    w.name = item_name;
    w.fold = fold.empty() ? text : fold;
    warnings.add(w);
}

std::string item(const char *array, size_t index)
{
    return std::string(array) + "[" + std::to_string(index) + "]";
}

} // namespace gltf

extern "C" bool vkrt_gltf_parse(const void *bytes, size_t size, const char *name,
                                const char *base_dir, const vkrt_load_options *options,
                                vkrt_model *model, vkrt_error *err)
{
    std::string shown = name ? name : "(gltf)";
    if (!model)
        return vkrt_error_set(err, "%s: no model to load into", shown.c_str());
    memset(model, 0, sizeof *model);
    if (!bytes && size > 0)
        return vkrt_error_set(err, "%s: no bytes given", shown.c_str());
    vkrt_load_options resolved = vkrt_load_options_resolve(options);
    static const unsigned char empty = 0;
    return gltf::guarded(shown, model, err, [&] {
        return gltf::parse(size ? static_cast<const unsigned char *>(bytes) : &empty, size, shown,
                           base_dir, resolved, model, err);
    });
}

extern "C" bool vkrt_gltf_load(const char *path, const vkrt_load_options *options,
                               vkrt_model *model, vkrt_error *err)
{
    if (!model)
        return vkrt_error_set(err, "%s: no model to load into", path ? path : "(null)");
    memset(model, 0, sizeof *model);
    if (!path)
        return vkrt_error_set(err, "(null): no glTF path given");
    char *bytes = nullptr;
    size_t size = 0;
    if (!vkrt_text_read_file(path, gltf::MAX_FILE_BYTES, "glTF file", &bytes, &size, err))
        return false;
    std::unique_ptr<char, void (*)(void *)> owned(bytes, free);
    char *folder = vkrt_text_dir_of(path);
    if (!folder)
        return vkrt_error_set(err, "%s: out of memory", path);
    std::unique_ptr<char, void (*)(void *)> owned_folder(folder, free);
    return vkrt_gltf_parse(bytes, size, path, folder, options, model, err);
}
