/*
 * gltf_context.h: what the glTF loader's parts share (internal to src/scene/gltf/, C++ only).
 *
 * The file is parsed by tinygltf (gltf_read.cpp) into a tinygltf::Model; each part then
 * translates one concern of it into the vkrt model: accessors (gltf_accessor.cpp), meshes
 * (gltf_mesh.cpp), the node tree and instances (gltf_nodes.cpp), materials and their textures
 * (gltf_material.cpp), lights and cameras (gltf_lights_cameras.cpp) and an animated camera's
 * frames (gltf_animation.cpp). A part that finds the file malformed throws gltf::LoadError with
 * the whole message; gltf_read.cpp turns it into the vkrt_error and frees the model.
 */
#ifndef VKRT_GLTF_CONTEXT_H
#define VKRT_GLTF_CONTEXT_H

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include <tiny_gltf.h>

extern "C" {
#include "gltf_load.h"
}
#include "../obj/obj_warnings.h"
#include "gltf_math.h"

namespace gltf {

/* A malformed file: what() is the whole message, "file.gltf: where: what". */
struct LoadError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/* An image of the file as the parse found it: its encoded bytes when they live in the file (a
 * buffer view, a data URI), else its uri. */
struct ImageSource {
    bool embedded = false;
    std::vector<unsigned char> bytes;
    std::string uri; /* as the file writes it (percent-encoded) */
};

struct Context {
    const tinygltf::Model &gltf;
    std::string name;        /* the file, for messages */
    const char *folder;      /* external images are resolved against it; NULL: none looked for */
    vkrt_load_options options;
    vkrt_model *model;
    obj_warnings::Warnings warnings;
    std::vector<ImageSource> images;   /* per glTF image */
    std::vector<int32_t> image_blob;   /* per glTF image: its model->images index, or -1 */
    std::vector<int32_t> mesh_of;      /* per glTF mesh: its vkrt mesh, or -1 (no triangles) */
    std::vector<int32_t> mirrored_of;  /* per glTF mesh: its reversed-winding copy, or -1 */
    std::vector<Mat4> world;           /* per glTF node: its world transform at rest */
    std::vector<int32_t> parent;       /* per glTF node: its parent, -1 for a root */
    std::vector<int> scene_nodes;      /* the scene's nodes, parents before children */

    Context(const tinygltf::Model &g, std::string n, const char *f, vkrt_load_options o,
            vkrt_model *m)
        : gltf(g), name(std::move(n)), folder(f), options(o), model(m)
    {
    }

    /* Throws LoadError "name: where: what" (where may be empty). */
    [[noreturn]] void fail(const std::string &where, const std::string &what) const;

    /* Adds "name: warning: text"; warnings of one kind fold into one line naming them. */
    void warn(const std::string &text, const std::string &kind = "", const std::string &item = "",
              const std::string &fold = "");
};

/* "meshes[2]" */
std::string item(const char *array, size_t index);

/* ---- gltf_accessor.cpp: accessors read into plain arrays, every byte checked first. */

/* The accessor's elements as floats, `components` per element (the accessor's type must have
 * that many; integer components are scaled to [0, 1] or [-1, 1] when normalized, else converted),
 * sparse substitutions applied. Throws on an index out of range, a type or component type the
 * use does not allow (float_only: only FLOAT), a byte range past its buffer view or buffer, a
 * byteStride below the element's size, a count that overflows, or (finite) a non-finite value. */
std::vector<float> read_floats(Context &c, int accessor, int components, bool float_only,
                               bool finite, const std::string &where);

/* An index accessor (SCALAR of unsigned byte, short or int) as uint32s, each checked below
 * vertex_count. */
std::vector<uint32_t> read_indices(Context &c, int accessor, size_t vertex_count,
                                   const std::string &where);

/* The accessor's element count, after checking its index. */
size_t accessor_count(const Context &c, int accessor, const std::string &where);

/* ---- gltf_mesh.cpp */

/* Fills model->meshes from every glTF mesh some scene node uses (c.mesh_of says which is which);
 * the materials' indices must be checked already (their count is gltf.materials.size()). */
void read_meshes(Context &c, const std::vector<bool> &used);

/* The vkrt mesh reversed in winding that a mirroring transform places (made on first use). */
uint32_t mirrored_mesh(Context &c, int gltf_mesh);

/* ---- gltf_nodes.cpp */

/* Picks the scene (the default, else scene 0, else every root node), checks the node tree
 * (indices in range, each node reached once) and sets c.parent, c.scene_nodes and c.world. */
void walk_scene(Context &c);

/* The node's local transform at rest (its matrix, or T * R * S). */
Mat4 local_transform(const Context &c, int node);

/* Which glTF meshes the scene's nodes use. */
std::vector<bool> used_meshes(const Context &c);

/* One instance per scene node with a mesh (one per element with EXT_mesh_gpu_instancing). */
void read_instances(Context &c);

/* ---- gltf_material.cpp */

/* Fills model->materials, one record per glTF material, and model->images with the embedded
 * images they use. */
void read_materials(Context &c);

/* ---- gltf_lights_cameras.cpp */

/* KHR_lights_punctual lights of the scene's nodes, at rest, into model->lights. */
void read_lights(Context &c);

/* The scene's cameras into model->cameras: one entry each, an animated one one per frame. */
void read_cameras(Context &c);

/* The camera of glTF camera `camera` seen through world transform m. */
vkrt_config_camera camera_at(const Context &c, int camera, int node, const Mat4 &m);

/* ---- gltf_animation.cpp */

/* The world transforms of node over its animation, sampled at c.options.fps from the first to the
 * last key of the channels that move it or an ancestor; empty when none does. */
std::vector<Mat4> animated_world(Context &c, int node);

/* Whether an animation channel moves node (translation, rotation or scale). */
bool is_animated(const Context &c, int node);

} // namespace gltf

#endif
