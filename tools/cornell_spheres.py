#!/usr/bin/env python3
"""Writes the Cornell box with a mirror sphere and a glass sphere (scenes/cornell-spheres/):
the box of scenes/cornell without its blocks, and two smooth UV spheres whose triangles wind
counter-clockwise seen from outside (glass needs to know inside from outside), and the lamp: a
130 x 105 quad just under the ceiling, facing down, white like the ceiling in scene.cfg (lit by a
point light, Whitted) and an emitter (Ke 17 12 4, the classic box's) in lamp.cfg. Usage:
    cornell_spheres.py OUTPUT_DIR"""
import math
import os
import sys

BOX = """\
v 0 0 0
v 555 0 0
v 555 0 555
v 0 0 555
v 0 555 0
v 0 555 555
v 555 555 555
v 555 555 0
v 0 0 555
v 555 0 555
v 555 555 555
v 0 555 555
v 555 0 0
v 555 555 0
v 555 555 555
v 555 0 555
v 0 0 0
v 0 0 555
v 0 555 555
v 0 555 0
"""

BOX_FACES = """\
usemtl white
f 1 2 3 4
f 5 6 7 8
f 9 10 11 12
usemtl red
f 13 14 15 16
usemtl green
f 17 18 19 20
"""

MTL = """\
# Cornell box walls (as scenes/cornell), a mirror and a glass.
newmtl white
Kd 0.73 0.73 0.73
newmtl red
Kd 0.63 0.065 0.05
newmtl green
Kd 0.14 0.45 0.091
# illum 3: reflection by ray tracing, reflectance Ks.
newmtl mirror
Kd 0 0 0
Ks 0.95 0.95 0.95
illum 3
# illum 7: refraction and Fresnel reflection, index Ni.
newmtl glass
Kd 0 0 0
Ks 1 1 1
Ni 1.5
illum 7
# The lamp: the ceiling's white here; lamp.cfg's lamp.mat makes it emit.
newmtl lamp
Kd 0.73 0.73 0.73
"""

LAMP_CFG = """\
# The Cornell box with a glass and a mirror sphere, lit by its lamp alone: the quad under the
# ceiling emits Ke 17 12 4 downwards (lamp.mat), so `integrator auto` chooses the path tracer.
geometry    cornell-spheres.obj
materials   lamp.mat
resolution  512 512
samples     64
max-depth   8
output      cornell-spheres-lamp.png
camera eye 278 273 -800  look 278 273 0  up 0 1 0  fov 39.3077
"""

DOF_CFG = """\
# Depth of field: the lamp-lit box through a thin lens of radius 25 focused on the glass sphere
# (969 units away along the view axis), so the mirror sphere and the back wall blur.
geometry    cornell-spheres.obj
materials   lamp.mat
resolution  512 512
samples     64
max-depth   8
output      cornell-spheres-dof.png
camera eye 278 273 -800  look 278 273 0  up 0 1 0  fov 39.3077  aperture 25  focus 969
"""

LAMP_MAT = """\
# The lamp of cornell-spheres.obj as an emitter: Ke (numbers 8-10) 17 12 4, no reflection.
lamp 0 @emissive 0 0 0 0  0 0 0 0  17 12 4
"""

# Just under the ceiling (y = 555), counter-clockwise seen from below: it faces down.
LAMP = """\
v 213 554.9 227
v 343 554.9 227
v 343 554.9 332
v 213 554.9 332
usemtl lamp
f -4 -3 -2 -1
"""

CFG = """\
# The Cornell box with a glass sphere (left in the picture) and a mirror sphere (right).
geometry    cornell-spheres.obj
resolution  512 512
samples     4
max-depth   8
accel       auto
output      cornell-spheres.png
environment 0 0 0
light ambient 0.03 0.03 0.03
light point   278 500 279.5   250000 250000 250000
camera eye 278 273 -800  look 278 273 0  up 0 1 0  fov 39.3077
"""


def sphere(centre, radius, material, first_vertex, first_normal, rings=24, segments=48):
    """OBJ lines of a UV sphere with per-vertex normals; returns (lines, vertex count)."""
    lines = [f"usemtl {material}"]
    count = 0
    for i in range(rings + 1):
        theta = math.pi * i / rings
        for j in range(segments):
            phi = 2 * math.pi * j / segments
            n = (math.sin(theta) * math.cos(phi), math.cos(theta), math.sin(theta) * math.sin(phi))
            p = [centre[k] + radius * n[k] for k in range(3)]
            lines.append("v %.6f %.6f %.6f" % tuple(p))
            lines.append("vn %.6f %.6f %.6f" % n)
            count += 1

    def corner(i, j):
        k = i * segments + (j % segments)
        return f"{first_vertex + k}//{first_normal + k}"

    for i in range(rings):
        for j in range(segments):
            a, b = corner(i, j), corner(i, j + 1)
            c, d = corner(i + 1, j + 1), corner(i + 1, j)
            # Counter-clockwise from outside: theta grows downwards, phi towards +z.
            if i != 0:
                lines.append(f"f {a} {b} {c}")
            if i != rings - 1:
                lines.append(f"f {a} {c} {d}")
    return lines, count


def main():
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    obj = ["# Cornell box with a mirror and a glass sphere; made by tools/cornell_spheres.py.",
           "mtllib cornell-spheres.mtl", BOX.rstrip("\n")]
    mirror, n = sphere((185, 100, 351), 100, "mirror", 21, 1)
    glass, _ = sphere((370, 100, 169), 100, "glass", 21 + n, 1 + n)
    obj += [l for l in mirror if l.startswith("v")] + [l for l in glass if l.startswith("v")]
    obj.append(BOX_FACES.rstrip("\n"))
    obj += [l for l in mirror if not l.startswith("v")] + [l for l in glass if not l.startswith("v")]
    obj.append(LAMP.rstrip("\n"))
    for name, text in (("cornell-spheres.obj", "\n".join(obj) + "\n"),
                       ("cornell-spheres.mtl", MTL), ("scene.cfg", CFG), ("lamp.cfg", LAMP_CFG),
                       ("dof.cfg", DOF_CFG),
                       ("lamp.mat", LAMP_MAT)):
        with open(os.path.join(out, name), "w") as f:
            f.write(text)


if __name__ == "__main__":
    main()
