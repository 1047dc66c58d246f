/*
 * gltf_animation.cpp: an animated camera's flythrough (gltf_context.h). The channels that move
 * the camera's node or one of its ancestors are sampled at the options' frames per second from
 * their first key to their last, with glTF's interpolations (spec 3.11.3): STEP holds a key's
 * value, LINEAR interpolates (rotations by slerp), CUBICSPLINE is the cubic Hermite spline of
 * the keys' values and tangents (rotations renormalised). Before the first key and after the
 * last a channel holds its end value.
 */
#include <algorithm>
#include <cmath>

#include "gltf_context.h"

namespace gltf {

namespace {

enum Path { TRANSLATION, ROTATION, SCALE };

/* One channel, read and checked. */
struct Channel {
    int node;
    Path path;
    int interpolation; /* 0 STEP, 1 LINEAR, 2 CUBICSPLINE */
    std::vector<float> times, values; /* values: 3 or 4 per key, 3 times that for CUBICSPLINE */
};

bool path_of(const std::string &s, Path *p)
{
    if (s == "translation")
        *p = TRANSLATION;
    else if (s == "rotation")
        *p = ROTATION;
    else if (s == "scale")
        *p = SCALE;
    else
        return false;
    return true;
}

/* Every translation, rotation and scale channel of the file moving one of `nodes`. */
std::vector<Channel> channels_of(Context &c, const std::vector<bool> &nodes)
{
    std::vector<Channel> out;
    const tinygltf::Model &g = c.gltf;
    for (size_t a = 0; a < g.animations.size(); ++a) {
        const tinygltf::Animation &anim = g.animations[a];
        for (size_t k = 0; k < anim.channels.size(); ++k) {
            const tinygltf::AnimationChannel &ch = anim.channels[k];
            Path path;
            if (ch.target_node < 0 || (size_t)ch.target_node >= nodes.size() ||
                !nodes[(size_t)ch.target_node] || !path_of(ch.target_path, &path))
                continue;
            std::string where = item("animations", a) + "." + item("channels", k);
            if (ch.sampler < 0 || (size_t)ch.sampler >= anim.samplers.size())
                c.fail(where, "sampler " + std::to_string(ch.sampler) + " is not one of the " +
                                  std::to_string(anim.samplers.size()));
            if (!g.nodes[(size_t)ch.target_node].matrix.empty())
                c.fail(where, "it moves node " + std::to_string(ch.target_node) +
                                  ", which has a matrix (glTF allows only TRS nodes to move)");
            const tinygltf::AnimationSampler &s = anim.samplers[(size_t)ch.sampler];
            std::string at = item("animations", a) + "." + item("samplers", (size_t)ch.sampler);
            Channel out_ch;
            out_ch.node = ch.target_node;
            out_ch.path = path;
            if (s.interpolation == "STEP")
                out_ch.interpolation = 0;
            else if (s.interpolation == "LINEAR" || s.interpolation.empty())
                out_ch.interpolation = 1;
            else if (s.interpolation == "CUBICSPLINE")
                out_ch.interpolation = 2;
            else
                c.fail(at, "interpolation \"" + s.interpolation + "\" is not one glTF has");
            out_ch.times = read_floats(c, s.input, 1, true, true, at + ".input");
            int components = path == ROTATION ? 4 : 3;
            out_ch.values = read_floats(c, s.output, components, path != ROTATION, true,
                                        at + ".output");
            size_t keys = out_ch.times.size();
            size_t per_key = (size_t)components * (out_ch.interpolation == 2 ? 3 : 1);
            if (keys == 0 || out_ch.values.size() != keys * per_key)
                c.fail(at, std::to_string(keys) + " keys but " +
                               std::to_string(out_ch.values.size() / (size_t)components) +
                               " output values");
            for (size_t i = 1; i < keys; ++i)
                if (!(out_ch.times[i] > out_ch.times[i - 1]))
                    c.fail(at + ".input", "key times must increase (key " + std::to_string(i) +
                                              ")");
            out.push_back(std::move(out_ch));
        }
    }
    return out;
}

/* The channel's value at time t (3 or 4 numbers). */
std::vector<double> sample(const Channel &ch, double t)
{
    size_t n = ch.path == ROTATION ? 4 : 3;
    size_t keys = ch.times.size();
    bool cubic = ch.interpolation == 2;
    /* The value of key k: the middle of its (in-tangent, value, out-tangent) for CUBICSPLINE. */
    auto value = [&](size_t k, size_t part) {
        std::vector<double> v(n);
        size_t base = cubic ? (k * 3 + part) * n : k * n;
        for (size_t i = 0; i < n; ++i)
            v[i] = ch.values[base + i];
        return v;
    };
    std::vector<double> out;
    if (t <= ch.times[0])
        out = value(0, 1);
    else if (t >= ch.times[keys - 1])
        out = value(keys - 1, 1);
    else {
        size_t k = (size_t)(std::upper_bound(ch.times.begin(), ch.times.end(), (float)t) -
                            ch.times.begin()) - 1;
        if (k + 1 >= keys)
            k = keys - 2;
        double t0 = ch.times[k], t1 = ch.times[k + 1], dt = t1 - t0, s = (t - t0) / dt;
        if (ch.interpolation == 0)
            out = value(k, 1);
        else if (ch.interpolation == 1) {
            std::vector<double> a = value(k, 1), b = value(k + 1, 1);
            if (ch.path == ROTATION) {
                Quat q = slerp(normalized(Quat{a[0], a[1], a[2], a[3]}),
                               normalized(Quat{b[0], b[1], b[2], b[3]}), s);
                out.assign(q.begin(), q.end());
            } else {
                out.resize(n);
                for (size_t i = 0; i < n; ++i)
                    out[i] = a[i] + (b[i] - a[i]) * s;
            }
        } else {
            /* Hermite: p = (2s^3 - 3s^2 + 1) v_k + (s^3 - 2s^2 + s) dt b_k
             *            + (-2s^3 + 3s^2) v_k+1 + (s^3 - s^2) dt a_k+1,
             * b_k the out-tangent of key k, a_k+1 the in-tangent of key k + 1. */
            std::vector<double> v0 = value(k, 1), b0 = value(k, 2), v1 = value(k + 1, 1),
                                a1 = value(k + 1, 0);
            double s2 = s * s, s3 = s2 * s;
            out.resize(n);
            for (size_t i = 0; i < n; ++i)
                out[i] = (2 * s3 - 3 * s2 + 1) * v0[i] + (s3 - 2 * s2 + s) * dt * b0[i] +
                         (-2 * s3 + 3 * s2) * v1[i] + (s3 - s2) * dt * a1[i];
        }
    }
    return out;
}

} // namespace

bool is_animated(const Context &c, int node)
{
    for (const tinygltf::Animation &anim : c.gltf.animations)
        for (const tinygltf::AnimationChannel &ch : anim.channels) {
            Path path;
            if (path_of(ch.target_path, &path))
                for (int n = node; n >= 0; n = c.parent[(size_t)n])
                    if (ch.target_node == n)
                        return true;
        }
    return false;
}

std::vector<Mat4> animated_world(Context &c, int node)
{
    std::vector<bool> chain(c.gltf.nodes.size(), false);
    for (int n = node; n >= 0; n = c.parent[(size_t)n])
        chain[(size_t)n] = true;
    std::vector<Channel> channels = channels_of(c, chain);
    if (channels.empty())
        return {};
    double start = INFINITY, end = -INFINITY;
    for (const Channel &ch : channels) {
        start = std::min(start, (double)ch.times.front());
        end = std::max(end, (double)ch.times.back());
    }
    double fps = c.options.fps;
    /* Frames at start + i / fps up to the last key (a rounding's worth past it counts). */
    double span = (end - start) * fps;
    if (span > 1e6)
        c.fail(item("nodes", (size_t)node),
               "its animation of " + std::to_string(end - start) + " s would be over a million "
                                                                  "frames");
    size_t frames = (size_t)std::floor(span + 1e-6) + 1;
    std::vector<Mat4> out;
    out.reserve(frames);
    for (size_t f = 0; f < frames; ++f) {
        double t = start + (double)f / fps;
        Mat4 world;
        std::vector<int> path;
        for (int n = node; n >= 0; n = c.parent[(size_t)n])
            path.push_back(n);
        for (auto it = path.rbegin(); it != path.rend(); ++it) {
            int n = *it;
            const tinygltf::Node &gn = c.gltf.nodes[(size_t)n];
            Mat4 local = local_transform(c, n);
            bool moved = false;
            Vec3 tr{0, 0, 0}, sc{1, 1, 1};
            Quat q{0, 0, 0, 1};
            if (gn.translation.size() == 3)
                tr = {gn.translation[0], gn.translation[1], gn.translation[2]};
            if (gn.rotation.size() == 4)
                q = normalized(Quat{gn.rotation[0], gn.rotation[1], gn.rotation[2], gn.rotation[3]});
            if (gn.scale.size() == 3)
                sc = {gn.scale[0], gn.scale[1], gn.scale[2]};
            for (const Channel &ch : channels) {
                if (ch.node != n)
                    continue;
                moved = true;
                std::vector<double> v = sample(ch, t);
                if (ch.path == TRANSLATION)
                    tr = {v[0], v[1], v[2]};
                else if (ch.path == SCALE)
                    sc = {v[0], v[1], v[2]};
                else
                    q = normalized(Quat{v[0], v[1], v[2], v[3]});
            }
            world = world * (moved ? compose_trs(tr, q, sc) : local);
        }
        out.push_back(world);
    }
    return out;
}

} // namespace gltf
