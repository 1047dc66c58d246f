/*
 * mtl_read.h: the .mtl files an OBJ names, read through tinyobjloader's LoadMtl into the scene
 * model's materials (mtl.h), and the file helpers the OBJ loader shares with it. C++, internal to
 * src/scene/obj/.
 *
 * Materials come through our own tinyobj::MaterialReader so we know which .mtl each came from
 * (texture paths are resolved against that .mtl's folder, falling back to the OBJ's folder when
 * the file only exists there), which fields were actually present (tinyobjloader's defaults differ
 * from the ones mtl.h documents, e.g. Kd 0 vs 0.8, illum 0 vs 2, Tf 0 vs 1), and on which line of
 * the .mtl each texture was named, so that a missing texture's error can point there; and to
 * check every number vkrt reads before LoadMtl does (docs/scene-format.md's table): a bad one
 * stops the load with "file.mtl:LINE: ..." (MtlReader::failed, error).
 */
#ifndef VKRT_MTL_READ_H
#define VKRT_MTL_READ_H

#include <tiny_obj_loader.h>

#include <array>
#include <cstdint>
#include <map>
#include <streambuf>
#include <string>
#include <utility>
#include <vector>

extern "C" {
#include "../model.h"
}
#include "obj_warnings.h"

namespace mtl_read {

/* Only a pipe that never ends reaches this: 16 GiB of OBJ text is hundreds of millions of
 * triangles. */
constexpr uint64_t OBJ_MAX_BYTES_64 = uint64_t(16) << 30;
constexpr size_t OBJ_MAX_FILE_BYTES = OBJ_MAX_BYTES_64 < SIZE_MAX ? size_t(OBJ_MAX_BYTES_64) : SIZE_MAX;

/* Read-only std::streambuf over bytes in memory, so tinyobjloader parses the very bytes we
 * scanned without a second copy. */
class MemoryBuffer : public std::streambuf {
public:
    explicit MemoryBuffer(const std::string &s) : MemoryBuffer(s.data(), s.size()) {}
    MemoryBuffer(const char *data, size_t size)
    {
        char *p = const_cast<char *>(data); /* only read through the get area */
        setg(p, p, p + size);
    }
};

/* The folder of path, "" for a bare name (vkrt_text_dir_of). */
std::string folder_of(const std::string &path);

/* A malloc'd copy of s; throws std::bad_alloc when memory runs out. */
char *copy_string(const std::string &s);

/* Which fields a material's .mtl block set, so absent ones get mtl.h's defaults, and where its
 * texture statements are, so texture errors can name the line. */
struct MtlOrigin {
    MtlOrigin() = default;
    MtlOrigin(std::string folder_, std::string path_) : folder(std::move(folder_)), path(std::move(path_)) {}
    std::string folder; /* of the .mtl that defined it */
    std::string path;   /* the .mtl itself */
    bool kd = true, ks = true, ke = true, ns = true, ni = true, d = true, illum = true, tf = true;
    /* Unknown (the mirror disagreed): pbr only where maps say so. */
    bool pr = false, pm = false, pc = false, ps = false;
    uint32_t pc_line = 0; /* the first Pc statement's */
    uint32_t ps_line = 0; /* the first Ps or map_Ps statement's */
    uint32_t map_kd_line = 0, map_d_line = 0, map_pr_line = 0, map_pm_line = 0, map_ps_line = 0;
    uint32_t norm_line = 0, map_bump_line = 0, map_ke_line = 0;
    /* The block's numbers as the .mtl checks (mtl_read.cpp) read them, by key ("Tr" as "d", 1 - Tr;
     * "Kt" as "Tf"): a one-number colour is grey, a value outside its range clamped where that
     * is allowed. They replace LoadMtl's (which reads "Kd 0.5" as 0.5 0 0). */
    std::map<std::string, std::array<float, 3>> numbers;
};

/* Loads each mtllib file relative to the OBJ's folder (not tinyobjloader's MaterialFileReader,
 * which splits its base folder at ':' and does not say which file a material came from). */
class MtlReader : public tinyobj::MaterialReader {
public:
    MtlReader(std::string obj_folder, obj_warnings::Warnings *warnings)
        : obj_folder_(std::move(obj_folder)), warnings_(warnings)
    {
    }

    std::vector<MtlOrigin> origins;       /* parallel to the materials vector */
    bool failed = false;                  /* an .mtl had a bad number: error says where */
    vkrt_error error = {{0}};
    obj_warnings::MtlLibraries libraries; /* the .mtl files read, and the mtllib names not found */

    bool operator()(const std::string &name, std::vector<tinyobj::material_t> *materials,
                    std::map<std::string, int> *material_map, std::string *warn, std::string *err) override;

private:
    std::string obj_folder_;
    obj_warnings::Warnings *warnings_;
};

/* The model's materials from tinyobjloader's, in its order (the indices its faces carry), each
 * through the .mtl record of mtl.h with the reader's origins; throws std::bad_alloc when memory
 * runs out (what was made is the model's, freed with it). */
void convert_materials(const std::vector<tinyobj::material_t> &materials, const MtlReader &reader,
                       const std::string &obj_folder, vkrt_model *model);

} // namespace mtl_read

#endif
