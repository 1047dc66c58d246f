#!/usr/bin/env python3
"""Writes scenes/rough-spheres/: nine spheres, a row each of the rough built-ins (top: a
copper-coloured @roughconductor, middle: a blue @roughplastic, bottom: @roughdielectric glass of
index 1.5) at roughness 0.05, 0.2 and 0.5 from left to right, over a grey floor before a wall of
two colours (for the glass to show what it refracts), lit by an emissive quad above and in front
and a dim constant environment: the scene of the Mitsuba agreement in docs/speed-vs-accuracy.md.
Usage:
    rough_spheres.py OUTPUT_DIR"""
import os
import sys

from cornell_spheres import sphere

ROUGHNESS = (0.05, 0.2, 0.5)
# name prefix, built-in, the numbers before roughness (the .mtl layout of docs/materials.md):
# 0-2 Kd, 3 transparency, 4-6 Ks, 7 Ns, 8-10 Ke, 11 Ni, 12-14 Tf, 15 illum.
ROWS = (
    ("conductor", "@roughconductor", "0 0 0 0  0.95 0.64 0.54 0  0 0 0  0  0 0 0  0"),
    ("plastic", "@roughplastic", "0.1 0.25 0.6 0  1 1 1 0  0 0 0  1.5  0 0 0  0"),
    ("dielectric", "@roughdielectric", "0 0 0 0  0 0 0 0  0 0 0  1.5  0 0 0  0"),
)

MTL = """\
# The room of the rough spheres (the spheres' materials are in rough.mat).
newmtl floor
Kd 0.5 0.5 0.5
newmtl wall_left
Kd 0.7 0.2 0.15
newmtl wall_right
Kd 0.8 0.8 0.8
newmtl lamp
Kd 0 0 0
"""

# Floor at y = -3.5, a wall at z = -4 of two halves, the lamp a 4 x 4 quad at y = 7 facing
# down, in front of the spheres (z = 3). Counter-clockwise seen from the side that faces the
# spheres.
ROOM = """\
v -9 -3.5 -4
v 9 -3.5 -4
v 9 -3.5 12
v -9 -3.5 12
v -9 -3.5 -4
v 0 -3.5 -4
v 0 9 -4
v -9 9 -4
v 0 -3.5 -4
v 9 -3.5 -4
v 9 9 -4
v 0 9 -4
v -2 7 1
v 2 7 1
v 2 7 5
v -2 7 5
usemtl floor
f -16 -13 -14 -15
usemtl wall_left
f -12 -11 -10 -9
usemtl wall_right
f -8 -7 -6 -5
usemtl lamp
f -4 -3 -2 -1
"""

CFG = """\
# Rough spheres: rows of @roughconductor, @roughplastic, @roughdielectric (top to bottom) at
# roughness 0.05, 0.2, 0.5 (left to right); made by tools/rough_spheres.py.
geometry    rough-spheres.obj
materials   rough.mat
integrator  path
resolution  256 256
samples     64
max-depth   8
environment 0.2 0.2 0.2
output      rough-spheres.png
camera eye 0 0 11  look 0 0 0  up 0 1 0  fov 50
"""


def material_file():
    lines = ["# The spheres' materials: numbers in the .mtl layout (docs/materials.md), roughness "
             "the 17th (16).", "lamp 0 @emissive 0 0 0 0  0 0 0 0  30 30 30"]
    for name, shader, numbers in ROWS:
        for r in ROUGHNESS:
            lines.append(f"{name}_{r} 0 {shader} {numbers}  {r}")
    return "\n".join(lines) + "\n"


def main():
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    obj = ["# Nine rough spheres in a room; made by tools/rough_spheres.py.",
           "mtllib rough-spheres.mtl"]
    first_vertex = first_normal = 1
    for row, (name, _, _) in enumerate(ROWS):
        for column, r in enumerate(ROUGHNESS):
            centre = (2.4 * (column - 1), 2.4 * (1 - row), 0.0)
            lines, n = sphere(centre, 1.0, f"{name}_{r}", first_vertex, first_normal, 16, 32)
            obj += lines
            first_vertex += n
            first_normal += n
    obj.append(ROOM.rstrip("\n"))
    # The OBJ's usemtl names must be .mtl materials for the material file's entries to replace.
    mtl = MTL + "# Replaced by rough.mat's entries of the same names.\n" + "".join(
        f"newmtl {name}_{r}\n" for name, _, _ in ROWS for r in ROUGHNESS)
    for file, text in (("rough-spheres.obj", "\n".join(obj) + "\n"), ("rough-spheres.mtl", mtl),
                       ("rough.mat", material_file()), ("scene.cfg", CFG)):
        with open(os.path.join(out, file), "w") as f:
            f.write(text)


if __name__ == "__main__":
    main()
