/*
 * gltf_lights_cameras.cpp: KHR_lights_punctual lights and cameras from their nodes' world
 * transforms (gltf_context.h). glTF lights shine and cameras look down their node's -Z, with +Y
 * up.
 */
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <new>

#include "gltf_context.h"

namespace gltf {

namespace {

/* The luminous efficacy glTF's photometric units are divided by: 683 lm/W, the peak of the
 * photopic curve, which Blender's glTF exporter and importer use (PBR_WATTS_TO_LUMENS), so a
 * Blender light exported and read here has the radiometric power it had in Blender. */
const double LUMENS_PER_WATT = 683.0;

const double PI = 3.14159265358979323846;

template <typename T> T *grow(T *array, size_t count)
{
    T *p = static_cast<T *>(realloc(array, (count ? count : 1) * sizeof(T)));
    if (!p)
        throw std::bad_alloc();
    return p;
}

void store(const Vec3 &v, float out[3])
{
    for (int k = 0; k < 3; ++k)
        out[k] = (float)v[k];
}

} // namespace

void read_lights(Context &c)
{
    const tinygltf::Model &g = c.gltf;
    std::vector<vkrt_config_light> out;
    for (int n : c.scene_nodes) {
        const tinygltf::Node &node = g.nodes[(size_t)n];
        auto ext = node.extensions.find("KHR_lights_punctual");
        if (ext == node.extensions.end())
            continue;
        std::string where = item("nodes", (size_t)n) + ".KHR_lights_punctual";
        const tinygltf::Value &v = ext->second;
        if (!v.IsObject() || !v.Get("light").IsInt())
            c.fail(where, "no light index");
        int index = v.Get("light").GetNumberAsInt();
        if (index < 0 || (size_t)index >= g.lights.size())
            c.fail(where, "light " + std::to_string(index) + " is not one of the file's " +
                              std::to_string(g.lights.size()));
        const tinygltf::Light &l = g.lights[(size_t)index];
        std::string at = "KHR_lights_punctual." + item("lights", (size_t)index);
        vkrt_config_light light;
        memset(&light, 0, sizeof light);
        double colour[3] = {1, 1, 1};
        if (l.color.size() == 3)
            std::copy(l.color.begin(), l.color.end(), colour);
        double intensity = std::isfinite(l.intensity) ? std::max(l.intensity, 0.0) : 0.0;
        /* point and spot: candela (lm/sr) -> W/sr; directional: lux (lm/m^2) -> W/m^2. */
        for (int k = 0; k < 3; ++k)
            light.colour[k] = (float)(std::max(colour[k], 0.0) * intensity / LUMENS_PER_WATT);
        const Mat4 &m = c.world[(size_t)n];
        store(transform_point(m, {0, 0, 0}), light.position);
        store(normalized(transform_direction(m, {0, 0, -1})), light.direction);
        if (l.type == "point")
            light.kind = VKRT_LIGHT_POINT;
        else if (l.type == "directional")
            light.kind = VKRT_LIGHT_DIRECTIONAL;
        else if (l.type == "spot") {
            light.kind = VKRT_LIGHT_SPOT;
            /* vkrt's spot has a hard edge: the outer cone; the inner cone's smooth falloff is
             * not made (docs/scene-format.md). */
            double outer = l.spot.outerConeAngle * 180.0 / PI;
            light.half_angle_deg = (float)std::min(std::max(outer, 0.01), 90.0);
            if (l.spot.innerConeAngle < l.spot.outerConeAngle * 0.999)
                c.warn(at + ": the spot's soft edge (inner cone) is not made: its cone is the "
                            "outer one, with a hard edge",
                       "inner-cone", at,
                       "{n} spot lights' soft edges (inner cones) are not made: their cones "
                       "are the outer ones, hard-edged");
        } else
            c.fail(at, "type \"" + l.type + "\" is not point, spot or directional");
        if (l.range > 0)
            c.warn(at + ": range is ignored: the light falls off as 1/d^2 without end", "range",
                   at, "{n} lights' ranges are ignored: they fall off as 1/d^2 without end");
        if (is_animated(c, n))
            c.warn(item("nodes", (size_t)n) + ": an animated light is placed at its rest pose");
        out.push_back(light);
    }
    c.model->lights = grow<vkrt_config_light>(nullptr, out.size());
    if (!out.empty())
        memcpy(c.model->lights, out.data(), out.size() * sizeof(vkrt_config_light));
    c.model->light_count = (uint32_t)out.size();
}

vkrt_config_camera camera_at(const Context &c, int camera, int node, const Mat4 &m)
{
    const tinygltf::Camera &cam = c.gltf.cameras[(size_t)camera];
    vkrt_config_camera out;
    memset(&out, 0, sizeof out);
    Vec3 eye = transform_point(m, {0, 0, 0});
    Vec3 forward = normalized(transform_direction(m, {0, 0, -1}));
    Vec3 up = normalized(transform_direction(m, {0, 1, 0}));
    store(eye, out.eye);
    store({eye[0] + forward[0], eye[1] + forward[1], eye[2] + forward[2]}, out.look);
    store(up, out.up);
    out.fov_deg = 45.0f;
    if (cam.type == "orthographic")
        out.ortho_width = (float)(2.0 * std::fabs(cam.orthographic.xmag));
    else
        out.fov_deg = (float)(cam.perspective.yfov * 180.0 / PI);
    const std::string &name = !cam.name.empty()                           ? cam.name
                              : !c.gltf.nodes[(size_t)node].name.empty() ? c.gltf.nodes[(size_t)node].name
                                                                          : item("cameras", (size_t)camera);
    snprintf(out.name, sizeof out.name, "%s", name.c_str());
    return out;
}

void read_cameras(Context &c)
{
    const tinygltf::Model &g = c.gltf;
    std::vector<vkrt_config_camera> out;
    for (int n : c.scene_nodes) {
        int camera = g.nodes[(size_t)n].camera;
        if (camera < 0)
            continue;
        std::string where = item("nodes", (size_t)n);
        if ((size_t)camera >= g.cameras.size())
            c.fail(where, "camera " + std::to_string(camera) + " is not one of the file's " +
                              std::to_string(g.cameras.size()));
        const tinygltf::Camera &cam = g.cameras[(size_t)camera];
        std::string at = item("cameras", (size_t)camera);
        if (cam.type == "perspective") {
            double fov = cam.perspective.yfov * 180.0 / PI;
            if (!(fov > 0 && fov < 180))
                c.fail(at, "yfov " + std::to_string(cam.perspective.yfov) +
                               " is not between 0 and pi");
        } else if (cam.type == "orthographic") {
            if (!(std::fabs(cam.orthographic.xmag) > 0) || !std::isfinite(cam.orthographic.xmag))
                c.fail(at, "xmag must be a finite number other than 0");
        } else
            c.fail(at, "type \"" + cam.type + "\" is not perspective or orthographic");
        std::vector<Mat4> frames = animated_world(c, n);
        if (frames.empty())
            frames.push_back(c.world[(size_t)n]);
        for (const Mat4 &m : frames) {
            vkrt_config_camera made = camera_at(c, camera, n, m);
            for (float x : {made.eye[0], made.eye[1], made.eye[2], made.look[0], made.look[1],
                            made.look[2], made.up[0], made.up[1], made.up[2]})
                if (!std::isfinite(x))
                    c.fail(where, "the camera's world transform is not finite");
            out.push_back(made);
        }
    }
    c.model->cameras = grow<vkrt_config_camera>(nullptr, out.size());
    if (!out.empty())
        memcpy(c.model->cameras, out.data(), out.size() * sizeof(vkrt_config_camera));
    c.model->camera_count = (uint32_t)out.size();
}

} // namespace gltf
