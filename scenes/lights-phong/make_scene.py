#!/usr/bin/env python3
"""Writes lights-phong.obj and lights-phong.mtl: a scene for holding vkrt against the Mitsuba 3
reference (tools/reference) where scenes/cornell has nothing to test: spot, directional and point
lights together, and Blinn-Phong highlights of three exponents.

The scene, in metres, y up: a floor (y = 0) and a back wall (z = -3), one quad each, and three
UV spheres of radius 0.6 with per-vertex normals, from the left Ns 8, 60 and 500. Faces wind
counter-clockwise seen from outside.

Run from anywhere: python3 make_scene.py   (writes next to this script)"""
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))
MTL = """\
# Materials of lights-phong.obj (made by make_scene.py). illum 2 with Ks and Ns: vkrt's @phong.
newmtl floor
Kd 0.6 0.6 0.6
newmtl wall
Kd 0.5 0.55 0.6
newmtl phong8
Kd 0.6 0.15 0.1
Ks 0.3 0.3 0.3
Ns 8
illum 2
newmtl phong60
Kd 0.15 0.45 0.15
Ks 0.5 0.5 0.5
Ns 60
illum 2
newmtl phong500
Kd 0.1 0.2 0.6
Ks 0.8 0.8 0.8
Ns 500
illum 2
"""


def sphere(lines, counts, centre, radius, rings=24, segments=48):
    """A UV sphere: `rings` bands from pole to pole, `segments` around, normals per vertex;
    counts holds the numbers of v and vn lines written so far, and is advanced."""
    first, first_n = counts[0] + 1, counts[1] + 1
    for i in range(rings + 1):
        theta = math.pi * i / rings
        for j in range(segments + 1):
            phi = 2 * math.pi * j / segments
            n = (math.sin(theta) * math.cos(phi), math.cos(theta), -math.sin(theta) * math.sin(phi))
            x, y, z = (c + radius * k for c, k in zip(centre, n))
            lines.append(f"v {x:.6f} {y:.6f} {z:.6f}")
            lines.append(f"vn {n[0]:.6f} {n[1]:.6f} {n[2]:.6f}")
            counts[0] += 1
            counts[1] += 1
    row = segments + 1
    for i in range(rings):
        for j in range(segments):
            a, b = i * row + j, (i + 1) * row + j
            c, d = b + 1, a + 1
            corner = {k: f"{first + k}//{first_n + k}" for k in (a, b, c, d)}
            if i > 0:
                lines.append(f"f {corner[a]} {corner[b]} {corner[d]}")
            if i < rings - 1:
                lines.append(f"f {corner[d]} {corner[b]} {corner[c]}")


def main():
    lines = ["# lights-phong: made by make_scene.py.", "mtllib lights-phong.mtl"]
    counts = [0, 0]  # vertices and normals written so far
    quads = {"floor": [(-4, 0, 3), (4, 0, 3), (4, 0, -3), (-4, 0, -3)],
             "wall": [(-4, 0, -3), (4, 0, -3), (4, 4, -3), (-4, 4, -3)]}
    for name, corners in quads.items():
        for x, y, z in corners:
            lines.append(f"v {x} {y} {z}")
        n = counts[0]
        counts[0] += 4
        lines += [f"usemtl {name}", f"f {n + 1} {n + 2} {n + 3} {n + 4}"]
    for name, x in (("phong8", -1.6), ("phong60", 0.0), ("phong500", 1.6)):
        lines.append(f"usemtl {name}")
        sphere(lines, counts, (x, 0.6, 0.0), 0.6)
    with open(os.path.join(HERE, "lights-phong.obj"), "w", encoding="utf-8") as f:
        f.write("\n".join(lines) + "\n")
    with open(os.path.join(HERE, "lights-phong.mtl"), "w", encoding="utf-8") as f:
        f.write(MTL)


if __name__ == "__main__":
    main()
