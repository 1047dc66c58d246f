/*
 * gltf_mesh.cpp: glTF meshes into vkrt meshes (gltf_context.h). Each mesh's triangle primitives
 * are concatenated into one vkrt mesh, de-indexed into the per-corner arrays the kernels read;
 * a primitive's material becomes its triangles' material index.
 */
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <new>

#include "gltf_context.h"

namespace gltf {

namespace {

/* One primitive's attributes, read and checked, and its triangles as corner indices. */
struct Primitive {
    std::vector<float> positions, normals, texcoords, tangents; /* per vertex; empty: absent */
    std::vector<uint32_t> corners;                             /* 3 per triangle */
    int32_t material = -1;
};

int attribute(const tinygltf::Primitive &p, const char *name)
{
    auto it = p.attributes.find(name);
    return it == p.attributes.end() ? -1 : it->second;
}

/* The triangles of mode over the vertex sequence `order` (glTF 2.0 spec 3.7.2.1): lists, strips
 * with every other triangle's first two corners swapped to keep the winding, and fans. */
std::vector<uint32_t> triangles_of(int mode, const std::vector<uint32_t> &order)
{
    std::vector<uint32_t> out;
    size_t n = order.size();
    if (mode == TINYGLTF_MODE_TRIANGLES) {
        out.assign(order.begin(), order.begin() + (ptrdiff_t)(n - n % 3));
    } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        for (size_t i = 0; i + 2 < n; ++i) {
            bool odd = i % 2 == 1;
            out.insert(out.end(), {order[odd ? i + 1 : i], order[odd ? i : i + 1], order[i + 2]});
        }
    } else { /* TRIANGLE_FAN */
        for (size_t i = 1; i + 1 < n; ++i)
            out.insert(out.end(), {order[0], order[i], order[i + 1]});
    }
    return out;
}

/* The primitive's vertex attributes, each with POSITION's count. */
Primitive read_primitive(Context &c, const tinygltf::Primitive &p, const std::string &where)
{
    Primitive out;
    int position = attribute(p, "POSITION");
    if (position < 0)
        c.fail(where, "no POSITION attribute");
    out.positions = read_floats(c, position, 3, false, true, where + ": POSITION");
    size_t vertices = out.positions.size() / 3;
    struct Optional {
        const char *name;
        std::vector<float> *into;
        int components;
    } optional[] = {{"NORMAL", &out.normals, 3},
                    {"TEXCOORD_0", &out.texcoords, 2},
                    {"TANGENT", &out.tangents, 4}};
    for (const Optional &o : optional) {
        int a = attribute(p, o.name);
        if (a < 0)
            continue;
        std::string name = where + ": " + o.name;
        if (accessor_count(c, a, name) != vertices)
            c.fail(name, "has " + std::to_string(accessor_count(c, a, name)) +
                             " elements where POSITION has " + std::to_string(vertices));
        *o.into = read_floats(c, a, o.components, false, false, name);
    }
    if (attribute(p, "TEXCOORD_1") >= 0)
        c.warn("TEXCOORD_1 is not read: every texture reads TEXCOORD_0", "texcoord1", where,
               "{n} primitives have TEXCOORD_1, which is not read: every "
                                  "texture reads TEXCOORD_0");
    std::vector<uint32_t> order;
    if (p.indices >= 0)
        order = read_indices(c, p.indices, vertices, where);
    else
        for (size_t i = 0; i < vertices; ++i)
            order.push_back((uint32_t)i);
    if (p.mode == TINYGLTF_MODE_TRIANGLES && order.size() % 3 != 0)
        c.warn(where + ": " + std::to_string(order.size()) +
               " vertices are not whole triangles: the last " + std::to_string(order.size() % 3) +
               " are left out");
    out.corners = triangles_of(p.mode, order);
    if (p.material >= 0 && (size_t)p.material >= c.gltf.materials.size())
        c.fail(where, "material " + std::to_string(p.material) + " is not one of the file's " +
                          std::to_string(c.gltf.materials.size()));
    out.material = p.material;
    return out;
}

template <typename T> T *allocate(size_t count)
{
    T *p = static_cast<T *>(calloc(count ? count : 1, sizeof(T)));
    if (!p)
        throw std::bad_alloc();
    return p;
}

/* The unit normal of the triangle at positions p (9 floats), or 0 0 1 when it has no area. */
void face_normal(const float *p, float n[3])
{
    float e1[3] = {p[3] - p[0], p[4] - p[1], p[5] - p[2]};
    float e2[3] = {p[6] - p[0], p[7] - p[1], p[8] - p[2]};
    float x[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                  e1[0] * e2[1] - e1[1] * e2[0]};
    float l = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    n[0] = l > 0 ? x[0] / l : 0;
    n[1] = l > 0 ? x[1] / l : 0;
    n[2] = l > 0 ? x[2] / l : 1;
}

/* The tangent of the triangle from its positions p and vkrt texture coordinates uv (dP/du), w 1:
 * what a corner without a TANGENT gets in a mesh where others have one. */
void face_tangent(const float *p, const float *uv, float t[4])
{
    float e1[3] = {p[3] - p[0], p[4] - p[1], p[5] - p[2]};
    float e2[3] = {p[6] - p[0], p[7] - p[1], p[8] - p[2]};
    float du1 = uv[2] - uv[0], dv1 = uv[3] - uv[1], du2 = uv[4] - uv[0], dv2 = uv[5] - uv[1];
    float det = du1 * dv2 - du2 * dv1;
    float x[3] = {1, 0, 0};
    if (det != 0)
        for (int k = 0; k < 3; ++k)
            x[k] = (e1[k] * dv2 - e2[k] * dv1) / det;
    float l = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    for (int k = 0; k < 3; ++k)
        t[k] = l > 0 && std::isfinite(l) ? x[k] / l : (k == 0 ? 1.0f : 0.0f);
    t[3] = 1;
}

/* One vkrt mesh from the primitives of glTF mesh m. */
void build_mesh(Context &c, const std::vector<Primitive> &prims, vkrt_mesh *mesh,
                const std::string &where)
{
    size_t triangles = 0;
    bool any_normals = false, any_texcoords = false, any_tangents = false;
    for (const Primitive &p : prims) {
        triangles += p.corners.size() / 3;
        any_normals |= !p.normals.empty();
        any_texcoords |= !p.texcoords.empty();
        any_tangents |= !p.tangents.empty();
    }
    if (triangles > UINT32_MAX / 9)
        c.fail(where, std::to_string(triangles) + " triangles, more than vkrt holds in one mesh");
    mesh->triangle_count = (uint32_t)triangles;
    mesh->positions = allocate<float>(triangles * 9);
    mesh->material = allocate<int32_t>(triangles);
    if (any_normals)
        mesh->normals = allocate<float>(triangles * 9);
    if (any_texcoords)
        mesh->texcoords = allocate<float>(triangles * 6);
    if (any_tangents)
        mesh->tangents = allocate<float>(triangles * 12);
    size_t t = 0;
    for (const Primitive &p : prims) {
        for (size_t k = 0; k < p.corners.size() / 3; ++k, ++t) {
            mesh->material[t] = p.material;
            float *pos = mesh->positions + t * 9;
            for (int v = 0; v < 3; ++v)
                memcpy(pos + v * 3, &p.positions[p.corners[k * 3 + v] * 3], 3 * sizeof(float));
            float geometric[3];
            face_normal(pos, geometric);
            if (mesh->normals)
                for (int v = 0; v < 3; ++v) {
                    float *n = mesh->normals + t * 9 + v * 3;
                    const float *given =
                        p.normals.empty() ? nullptr : &p.normals[p.corners[k * 3 + v] * 3];
                    float l = given ? std::sqrt(given[0] * given[0] + given[1] * given[1] +
                                                given[2] * given[2])
                                    : 0.0f;
                    /* A missing, zero or non-finite normal: the face's (glTF's flat normals). */
                    bool usable = given && l > 0 && std::isfinite(l);
                    for (int i = 0; i < 3; ++i)
                        n[i] = usable ? given[i] / l : geometric[i];
                }
            if (mesh->texcoords)
                for (int v = 0; v < 3; ++v) {
                    float *uv = mesh->texcoords + t * 6 + v * 2;
                    if (p.texcoords.empty())
                        continue;
                    const float *given = &p.texcoords[p.corners[k * 3 + v] * 2];
                    /* glTF's v runs down from the image's top; vkrt's (the OBJ's) up from its
                     * bottom. */
                    uv[0] = std::isfinite(given[0]) ? given[0] : 0.0f;
                    uv[1] = std::isfinite(given[1]) ? 1.0f - given[1] : 0.0f;
                }
            if (mesh->tangents) {
                float *tan = mesh->tangents + t * 12;
                if (p.tangents.empty()) {
                    float made[4] = {1, 0, 0, 1};
                    if (mesh->texcoords)
                        face_tangent(pos, mesh->texcoords + t * 6, made);
                    for (int v = 0; v < 3; ++v)
                        memcpy(tan + v * 4, made, sizeof made);
                } else
                    for (int v = 0; v < 3; ++v)
                        for (int i = 0; i < 4; ++i) {
                            float x = p.tangents[p.corners[k * 3 + v] * 4 + (size_t)i];
                            tan[v * 4 + i] = std::isfinite(x) ? x : 0.0f;
                        }
            }
        }
    }
    for (int k = 0; k < 3; ++k) {
        mesh->bounds_min[k] = triangles ? INFINITY : 0.0f;
        mesh->bounds_max[k] = triangles ? -INFINITY : 0.0f;
    }
    for (size_t i = 0; i < triangles * 3; ++i)
        for (int k = 0; k < 3; ++k) {
            mesh->bounds_min[k] = std::fmin(mesh->bounds_min[k], mesh->positions[i * 3 + k]);
            mesh->bounds_max[k] = std::fmax(mesh->bounds_max[k], mesh->positions[i * 3 + k]);
        }
}

} // namespace

void read_meshes(Context &c, const std::vector<bool> &used)
{
    const tinygltf::Model &g = c.gltf;
    c.mesh_of.assign(g.meshes.size(), -1);
    c.mirrored_of.assign(g.meshes.size(), -1);
    size_t count = 0;
    for (bool u : used)
        count += u;
    /* Room for every mesh and a mirrored copy of each (mirrored_mesh). */
    c.model->meshes = allocate<vkrt_mesh>(count * 2);
    for (size_t m = 0; m < g.meshes.size(); ++m) {
        if (!used[m])
            continue;
        std::string where = item("meshes", m);
        std::vector<Primitive> prims;
        for (size_t k = 0; k < g.meshes[m].primitives.size(); ++k) {
            const tinygltf::Primitive &p = g.meshes[m].primitives[k];
            std::string at = where + "." + item("primitives", k);
            if (p.mode >= TINYGLTF_MODE_POINTS && p.mode <= TINYGLTF_MODE_LINE_STRIP) {
                c.warn(at + ": points or lines are not rendered", "lines", at,
                       "{n} primitives of points or lines are not rendered");
                continue;
            }
            if (p.mode < TINYGLTF_MODE_POINTS || p.mode > TINYGLTF_MODE_TRIANGLE_FAN)
                c.fail(at, "mode " + std::to_string(p.mode) + " is not a glTF primitive mode");
            if (!p.targets.empty())
                c.warn(at + ": morph targets are not applied: the mesh renders at rest", "morph",
                       at, "{n} primitives have morph targets, not applied: they render at rest");
            for (const auto &ext : p.extensions)
                c.fail(at, "extension " + ext.first + " is not supported");
            prims.push_back(read_primitive(c, p, at));
        }
        size_t triangles = 0;
        for (const Primitive &p : prims)
            triangles += p.corners.size() / 3;
        if (triangles == 0)
            continue;
        uint32_t index = c.model->mesh_count++;
        build_mesh(c, prims, &c.model->meshes[index], where);
        c.mesh_of[m] = (int32_t)index;
    }
}

uint32_t mirrored_mesh(Context &c, int gltf_mesh)
{
    int32_t &mirrored = c.mirrored_of[(size_t)gltf_mesh];
    if (mirrored >= 0)
        return (uint32_t)mirrored;
    const vkrt_mesh &from = c.model->meshes[c.mesh_of[(size_t)gltf_mesh]];
    uint32_t index = c.model->mesh_count++;
    vkrt_mesh *to = &c.model->meshes[index];
    size_t n = from.triangle_count;
    to->triangle_count = from.triangle_count;
    memcpy(to->bounds_min, from.bounds_min, sizeof to->bounds_min);
    memcpy(to->bounds_max, from.bounds_max, sizeof to->bounds_max);
    to->material = allocate<int32_t>(n);
    memcpy(to->material, from.material, n * sizeof(int32_t));
    /* Each array with its corners 1 and 2 swapped: the winding reversed, nothing else. */
    struct Array {
        const float *src;
        float **dst;
        size_t per_corner;
    } arrays[] = {{from.positions, &to->positions, 3},
                  {from.normals, &to->normals, 3},
                  {from.texcoords, &to->texcoords, 2},
                  {from.tangents, &to->tangents, 4}};
    for (const Array &a : arrays) {
        if (!a.src)
            continue;
        *a.dst = allocate<float>(n * 3 * a.per_corner);
        for (size_t t = 0; t < n; ++t) {
            const float *s = a.src + t * 3 * a.per_corner;
            float *d = *a.dst + t * 3 * a.per_corner;
            memcpy(d, s, a.per_corner * sizeof(float));
            memcpy(d + a.per_corner, s + 2 * a.per_corner, a.per_corner * sizeof(float));
            memcpy(d + 2 * a.per_corner, s + a.per_corner, a.per_corner * sizeof(float));
        }
    }
    mirrored = (int32_t)index;
    return index;
}

} // namespace gltf
