/*
 * gltf_math.h: the transforms of glTF's node tree (internal to src/scene/gltf/, C++ only).
 *
 * Doubles, column-major as glTF writes matrices (m[column * 4 + row]), so a chain of a few
 * dozen nodes loses nothing before the result becomes vkrt's 3x4 row-major floats.
 */
#ifndef VKRT_GLTF_MATH_H
#define VKRT_GLTF_MATH_H

#include <array>
#include <cmath>

namespace gltf {

using Vec3 = std::array<double, 3>;
using Quat = std::array<double, 4>; /* x, y, z, w as glTF stores it */

struct Mat4 {
    std::array<double, 16> m{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    double at(int row, int column) const { return m[column * 4 + row]; }
};

inline Mat4 operator*(const Mat4 &a, const Mat4 &b)
{
    Mat4 r;
    for (int col = 0; col < 4; ++col)
        for (int row = 0; row < 4; ++row) {
            double s = 0;
            for (int k = 0; k < 4; ++k)
                s += a.at(row, k) * b.at(k, col);
            r.m[col * 4 + row] = s;
        }
    return r;
}

/* T * R * S, the node's transform from its translation, unit rotation and scale. */
inline Mat4 compose_trs(const Vec3 &t, const Quat &q, const Vec3 &s)
{
    double x = q[0], y = q[1], z = q[2], w = q[3];
    double r[3][3] = {
        {1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
        {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
        {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)},
    };
    Mat4 out;
    for (int row = 0; row < 3; ++row) {
        for (int col = 0; col < 3; ++col)
            out.m[col * 4 + row] = r[row][col] * s[col];
        out.m[12 + row] = t[row];
    }
    return out;
}

inline Vec3 transform_point(const Mat4 &a, const Vec3 &p)
{
    Vec3 r;
    for (int row = 0; row < 3; ++row)
        r[row] = a.at(row, 0) * p[0] + a.at(row, 1) * p[1] + a.at(row, 2) * p[2] + a.at(row, 3);
    return r;
}

inline Vec3 transform_direction(const Mat4 &a, const Vec3 &d)
{
    Vec3 r;
    for (int row = 0; row < 3; ++row)
        r[row] = a.at(row, 0) * d[0] + a.at(row, 1) * d[1] + a.at(row, 2) * d[2];
    return r;
}

/* The determinant of the upper 3x3: below 0 the transform mirrors (and reverses the winding). */
inline double determinant3(const Mat4 &a)
{
    return a.at(0, 0) * (a.at(1, 1) * a.at(2, 2) - a.at(1, 2) * a.at(2, 1)) -
           a.at(0, 1) * (a.at(1, 0) * a.at(2, 2) - a.at(1, 2) * a.at(2, 0)) +
           a.at(0, 2) * (a.at(1, 0) * a.at(2, 1) - a.at(1, 1) * a.at(2, 0));
}

inline double length(const Vec3 &v)
{
    return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

/* v over its length; v itself when it has none. */
inline Vec3 normalized(const Vec3 &v)
{
    double l = length(v);
    return l > 0 ? Vec3{v[0] / l, v[1] / l, v[2] / l} : v;
}

/* q over its length; the identity when it has none. */
inline Quat normalized(const Quat &q)
{
    double l = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    return l > 0 ? Quat{q[0] / l, q[1] / l, q[2] / l, q[3] / l} : Quat{0, 0, 0, 1};
}

/* Spherical linear interpolation from a to b (unit) by t, the shorter way round (glTF's LINEAR
 * for rotations); near-parallel quaternions are interpolated linearly and renormalised. */
inline Quat slerp(const Quat &a, Quat b, double t)
{
    double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
    if (d < 0) {
        d = -d;
        for (double &x : b)
            x = -x;
    }
    double wa = 1 - t, wb = t;
    if (d < 0.9995) {
        double theta = std::acos(d), s = std::sin(theta);
        wa = std::sin((1 - t) * theta) / s;
        wb = std::sin(t * theta) / s;
    }
    return normalized(Quat{wa * a[0] + wb * b[0], wa * a[1] + wb * b[1], wa * a[2] + wb * b[2],
                           wa * a[3] + wb * b[3]});
}

} // namespace gltf

#endif
