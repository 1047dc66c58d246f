/*
 * gltf_nodes.cpp: the scene's node tree, its world transforms and the instances of meshes it
 * places (gltf_context.h).
 */
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <new>

#include "gltf_context.h"

namespace gltf {

namespace {

/* A node's property of n numbers, checked: absent, or n finite numbers. */
bool numbers(const Context &c, const std::vector<double> &v, size_t n, const char *what, int node,
             double *out)
{
    if (v.empty())
        return false;
    if (v.size() != n)
        c.fail(item("nodes", (size_t)node), std::string(what) + " has " +
                                                std::to_string(v.size()) + " numbers, not " +
                                                std::to_string(n));
    for (size_t i = 0; i < n; ++i) {
        if (!std::isfinite(v[i]))
            c.fail(item("nodes", (size_t)node), std::string(what) + " is not finite");
        out[i] = v[i];
    }
    return true;
}

/* The 3x4 row-major floats of m. */
void to_instance(const Mat4 &m, float transform[12])
{
    for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 4; ++col)
            transform[row * 4 + col] = (float)m.at(row, col);
}

void add_instance(Context &c, std::vector<vkrt_instance> &out, int gltf_mesh, const Mat4 &m,
                  const std::string &where)
{
    int32_t mesh = c.mesh_of[(size_t)gltf_mesh];
    if (mesh < 0)
        return;
    double det = determinant3(m);
    if (!std::isfinite(det))
        c.fail(where, "the world transform is not finite");
    vkrt_instance inst;
    /* A mirroring transform turns the winding round: glTF then counts clockwise triangles as
     * front faces (spec 3.7.4), which a copy of the mesh with its winding reversed gives. */
    inst.mesh = det < 0 ? mirrored_mesh(c, gltf_mesh) : (uint32_t)mesh;
    to_instance(m, inst.transform);
    for (float x : inst.transform)
        if (!std::isfinite(x))
            c.fail(where, "the world transform is too large for 32-bit floats");
    out.push_back(inst);
}

/* EXT_mesh_gpu_instancing's per-element transforms of node (spec: TRANSLATION, ROTATION, SCALE
 * accessors of one count, each element's T * R * S applied after the node's own). */
std::vector<Mat4> gpu_instances(Context &c, int node, const tinygltf::Value &ext)
{
    std::string where = item("nodes", (size_t)node) + ".EXT_mesh_gpu_instancing";
    const tinygltf::Value &attributes =
        ext.IsObject() ? ext.Get("attributes") : tinygltf::Value();
    if (!attributes.IsObject())
        c.fail(where, "no attributes object");
    std::vector<float> t, r, s;
    size_t count = SIZE_MAX;
    struct Attr {
        const char *name;
        std::vector<float> *into;
        int components;
    } attrs[] = {{"TRANSLATION", &t, 3}, {"ROTATION", &r, 4}, {"SCALE", &s, 3}};
    for (const Attr &a : attrs) {
        const tinygltf::Value &v = attributes.Get(a.name);
        if (!v.IsInt())
            continue;
        std::string name = where + "." + a.name;
        *a.into = read_floats(c, v.GetNumberAsInt(), a.components, false, true, name);
        size_t n = a.into->size() / (size_t)a.components;
        if (count != SIZE_MAX && n != count)
            c.fail(name, "has " + std::to_string(n) + " elements where the others have " +
                             std::to_string(count));
        count = n;
    }
    if (count == SIZE_MAX)
        c.fail(where, "none of TRANSLATION, ROTATION and SCALE");
    std::vector<Mat4> out(count);
    for (size_t i = 0; i < count; ++i) {
        Vec3 tv{0, 0, 0}, sv{1, 1, 1};
        Quat q{0, 0, 0, 1};
        if (!t.empty())
            tv = {t[i * 3], t[i * 3 + 1], t[i * 3 + 2]};
        if (!r.empty())
            q = normalized(Quat{r[i * 4], r[i * 4 + 1], r[i * 4 + 2], r[i * 4 + 3]});
        if (!s.empty())
            sv = {s[i * 3], s[i * 3 + 1], s[i * 3 + 2]};
        out[i] = compose_trs(tv, q, sv);
    }
    return out;
}

} // namespace

Mat4 local_transform(const Context &c, int node)
{
    const tinygltf::Node &n = c.gltf.nodes[(size_t)node];
    Mat4 m;
    if (numbers(c, n.matrix, 16, "matrix", node, m.m.data()))
        return m;
    Vec3 t{0, 0, 0}, s{1, 1, 1};
    Quat q{0, 0, 0, 1};
    numbers(c, n.translation, 3, "translation", node, t.data());
    if (numbers(c, n.rotation, 4, "rotation", node, q.data()))
        q = normalized(q);
    numbers(c, n.scale, 3, "scale", node, s.data());
    return compose_trs(t, q, s);
}

void walk_scene(Context &c)
{
    const tinygltf::Model &g = c.gltf;
    size_t count = g.nodes.size();
    c.parent.assign(count, -1);
    std::vector<bool> is_child(count, false);
    for (size_t i = 0; i < count; ++i)
        for (int child : g.nodes[i].children) {
            if (child < 0 || (size_t)child >= count)
                c.fail(item("nodes", i), "child " + std::to_string(child) +
                                             " is not one of the file's " +
                                             std::to_string(count) + " nodes");
            if (is_child[(size_t)child] || (size_t)child == i)
                c.fail(item("nodes", (size_t)child),
                       "has two parents (or is its own): the nodes must form trees");
            is_child[(size_t)child] = true;
            c.parent[(size_t)child] = (int32_t)i;
        }
    std::vector<int> roots;
    if (g.defaultScene >= 0 && (size_t)g.defaultScene >= g.scenes.size())
        c.fail("scene", std::to_string(g.defaultScene) + " is not one of the file's " +
                            std::to_string(g.scenes.size()) + " scenes");
    if (!g.scenes.empty()) {
        const tinygltf::Scene &scene = g.scenes[g.defaultScene >= 0 ? (size_t)g.defaultScene : 0];
        roots = scene.nodes;
    } else
        for (size_t i = 0; i < count; ++i)
            if (!is_child[i])
                roots.push_back((int)i);
    c.world.assign(count, Mat4());
    std::vector<bool> reached(count, false);
    /* Depth first with a stack of its own: a chain of a million nodes must not overflow the
     * C stack. A node reached twice (a root that is a child, a scene naming one twice) or a
     * cycle (no root reaches it, so it is never walked) cannot loop. */
    std::vector<int> stack(roots.rbegin(), roots.rend());
    for (int r : roots) {
        if (r < 0 || (size_t)r >= count)
            c.fail("scenes", "node " + std::to_string(r) + " is not one of the file's " +
                                 std::to_string(count));
        if (is_child[(size_t)r])
            c.fail(item("nodes", (size_t)r), "is a scene's root and another node's child");
    }
    while (!stack.empty()) {
        int n = stack.back();
        stack.pop_back();
        if (reached[(size_t)n])
            c.fail(item("nodes", (size_t)n), "is reached twice from the scene's roots");
        reached[(size_t)n] = true;
        Mat4 local = local_transform(c, n);
        int32_t p = c.parent[(size_t)n];
        c.world[(size_t)n] = p >= 0 && reached[(size_t)p] ? c.world[(size_t)p] * local : local;
        c.scene_nodes.push_back(n);
        const std::vector<int> &children = g.nodes[(size_t)n].children;
        for (auto it = children.rbegin(); it != children.rend(); ++it)
            stack.push_back(*it);
    }
}

std::vector<bool> used_meshes(const Context &c)
{
    std::vector<bool> used(c.gltf.meshes.size(), false);
    for (int n : c.scene_nodes) {
        int mesh = c.gltf.nodes[(size_t)n].mesh;
        if (mesh >= 0 && (size_t)mesh >= used.size())
            c.fail(item("nodes", (size_t)n), "mesh " + std::to_string(mesh) +
                                                 " is not one of the file's " +
                                                 std::to_string(used.size()));
        if (mesh >= 0)
            used[(size_t)mesh] = true;
    }
    return used;
}

void read_instances(Context &c)
{
    std::vector<vkrt_instance> out;
    for (int n : c.scene_nodes) {
        const tinygltf::Node &node = c.gltf.nodes[(size_t)n];
        std::string where = item("nodes", (size_t)n);
        if (node.skin >= 0)
            c.warn(where + ": its skin is not applied: the mesh renders at its rest pose", "skin",
                   where, "{n} nodes have a skin, not applied: they render at their rest pose");
        if (node.mesh < 0)
            continue;
        if (is_animated(c, n))
            c.warn(where + ": its animation is not played: the mesh renders at its rest pose",
                   "animated", where,
                   "{n} animated nodes with meshes render at their rest pose");
        auto ext = node.extensions.find("EXT_mesh_gpu_instancing");
        if (ext == node.extensions.end()) {
            add_instance(c, out, node.mesh, c.world[(size_t)n], where);
            continue;
        }
        for (const Mat4 &each : gpu_instances(c, n, ext->second))
            add_instance(c, out, node.mesh, c.world[(size_t)n] * each, where);
    }
    if (out.size() > UINT32_MAX)
        c.fail("", "more than 2^32 instances");
    c.model->instances = static_cast<vkrt_instance *>(calloc(out.size() ? out.size() : 1,
                                                             sizeof(vkrt_instance)));
    if (!c.model->instances)
        throw std::bad_alloc();
    if (!out.empty())
        memcpy(c.model->instances, out.data(), out.size() * sizeof(vkrt_instance));
    c.model->instance_count = (uint32_t)out.size();
}

} // namespace gltf
