/*
 * gltf_load.h: glTF 2.0 (.gltf with its .bin files and images, data URIs, and .glb) loading into
 * the scene model (model.h), through Debian's tinygltf.
 *
 * What is read and how each unit converts is docs/scene-format.md's "glTF 2.0" section; the
 * materials' mapping is docs/materials.md's. In short: every triangle primitive (strips and fans
 * made lists) of a mesh becomes one vkrt mesh, one record per corner, its material per triangle;
 * every node of the scene with a mesh an instance of it (EXT_mesh_gpu_instancing one per
 * element), a node mirrored by its transform an instance of a copy of its mesh with the winding
 * reversed, so the front faces stay the file's; metallic-roughness materials and their
 * extensions map onto VKRT_BSDF_PRINCIPLED or glass; KHR_lights_punctual lights and the cameras
 * come from their nodes' world transforms, photometric units made radiometric (683 lm/W); an
 * animated camera becomes one camera per frame at options->fps. Texture coordinates have their
 * v flipped (glTF's origin is the image's top left, vkrt's the OBJ's bottom left).
 *
 * Embedded images (a .glb's buffer views, data URIs) are kept encoded in model->images; an
 * external image becomes a texture path resolved against the file's folder; none is decoded
 * here (materials.c does, through texture.h). The model's inputs are the .bin files read.
 * Anything malformed is an error "file.gltf: meshes[2].primitives[0]: what is wrong", checked
 * before any memory is read; what vkrt does not render (points and lines, skins, morph
 * targets, animated objects, occlusion maps, unknown optional extensions) is one warning each.
 */
#ifndef VKRT_GLTF_LOAD_H
#define VKRT_GLTF_LOAD_H

#include <stdbool.h>
#include <stddef.h>

#include "../../error.h"
#include "../loader.h"
#include "../model.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Loads the .gltf or .glb at path (told apart by the bytes, not the name) under options (NULL:
 * the defaults). On failure false with err set to "path: where: what" and *model left empty.
 * A file with no triangles in its scene is an error. The cameras' entries are each camera in
 * the scene's node order; an animated one is several consecutive entries of one name, its
 * frames. */
bool vkrt_gltf_load(const char *path, const vkrt_load_options *options, vkrt_model *model,
                    vkrt_error *err);

/* Parses a .gltf's or .glb's bytes already in memory, with vkrt_gltf_load's checks and contract;
 * name stands for the path in messages (NULL: "(gltf)"). base_dir is the folder external buffers
 * and images are resolved against ("" for the current folder); NULL means no other file is
 * touched: an external buffer is an error and external images are named but not looked for
 * (what a fuzzer wants). */
bool vkrt_gltf_parse(const void *bytes, size_t size, const char *name, const char *base_dir,
                     const vkrt_load_options *options, vkrt_model *model, vkrt_error *err);

#ifdef __cplusplus
}
#endif

#endif
