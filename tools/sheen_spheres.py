#!/usr/bin/env python3
"""Writes scenes/sheen-spheres/: nine spheres with the .mtl's sheen (Ps; docs/materials.md, "The
sheen": Disney's, as Mitsuba 3's `principled` has it) of weight 0, 0.5 and 1 (left to right),
over a dark red Lambertian (top; @roughplastic with Ks 0 and Ni 1, no coat of its own), a black
base (middle: the sheen alone) and a dark blue Lambertian under a clear coat of roughness 0.2
(bottom: the sheen under the coat), against a dark environment and lit from straight behind by
an emissive quad each sphere hides, so that the sheen's grazing rims show.
Usage:
    sheen_spheres.py OUTPUT_DIR
    sheen_spheres.py --spheres VKRT.exr MITSUBA.exr CONVERGED.exr
The second form prints, per sphere (over a disc about its centre, and over its rim, where the
sheen shows), the mean of vkrt's image and of Mitsuba's (renders of the
scene.cfg at equal samples, as tools/agreement leaves them) against Mitsuba's converged image,
and their per-pixel relative errors. Mitsuba's sheen is its own `principled` BSDF's
(tools/mitsuba_scene.py's Sheen adds it to the base)."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cornell_spheres import sphere  # noqa: E402
from rough_spheres import sphere_table  # noqa: E402

SHEEN = (0.0, 0.5, 1.0)
# name prefix, built-in, numbers 0-19 (the .mtl layout of docs/materials.md: 0-2 Kd, 4-6 Ks,
# 11 Ni, 18-19 the clear coat's weight and roughness); the sheen's weight (20) follows.
ROWS = (
    ("red", "@roughplastic", "0.3 0.03 0.04 0  0 0 0 0  0 0 0  1  0 0 0  0  0  0  0 0"),
    ("black", "@roughplastic", "0 0 0 0  0 0 0 0  0 0 0  1  0 0 0  0  0  0  0 0"),
    ("coated", "@roughplastic", "0.02 0.04 0.25 0  0 0 0 0  0 0 0  1  0 0 0  0  0  0  1 0.2"),
)

# The lamps: a 1.2 x 1.2 quad behind each sphere (z = -3), on the camera's ray through the
# sphere's centre so that the sphere hides it, facing the sphere (+z, counter-clockwise seen from
# there): light from straight behind, which the sheen turns into a bright rim.
LAMP_Z, LAMP_HALF, EYE_Z = -3.0, 0.6, 11.0


def lamp(centre):
    k = (EYE_Z - LAMP_Z) / EYE_Z
    x, y = centre[0] * k, centre[1] * k
    return ["usemtl lamp"] + [f"v {x + dx:.6f} {y + dy:.6f} {LAMP_Z}" for dx, dy in
                              ((-LAMP_HALF, -LAMP_HALF), (LAMP_HALF, -LAMP_HALF),
                               (LAMP_HALF, LAMP_HALF), (-LAMP_HALF, LAMP_HALF))] + [
        "f -4 -3 -2 -1"]


CFG = """\
# Sheen spheres: Ps 0, 0.5, 1 (left to right) over a dark red Lambertian, a black base and a
# coated dark blue Lambertian (top to bottom), each lit from behind by a lamp it hides; made by tools/sheen_spheres.py.
geometry    sheen-spheres.obj
materials   sheen.mat
integrator  path
resolution  256 256
samples     64
max-depth   8
environment 0.05 0.05 0.05
output      sheen-spheres.png
camera eye 0 0 11  look 0 0 0  up 0 1 0  fov 50
"""


def material_file():
    lines = ["# The spheres' materials: numbers in the .mtl layout (docs/materials.md); the last "
             "the sheen's weight (20, the .mtl's Ps).",
             "lamp 0 @emissive 0 0 0 0  0 0 0 0  15 15 15"]
    for name, shader, numbers in ROWS:
        for w in SHEEN:
            lines.append(f"{name}_{w} 0 {shader} {numbers}  {w}")
    return "\n".join(lines) + "\n"


def scene_obj():
    """The OBJ and .mtl text: a 3 x 3 grid of unit spheres 2.4 apart (rough_spheres.py's, which
    its sphere_table expects), row k of ROWS[k], column j of SHEEN[j], and their lamps."""
    obj = ["# Nine sheen spheres lit from behind; made by tools/sheen_spheres.py.",
           "mtllib sheen-spheres.mtl"]
    first_vertex = first_normal = 1
    for row, (name, _, _) in enumerate(ROWS):
        for column, w in enumerate(SHEEN):
            centre = (2.4 * (column - 1), 2.4 * (1 - row), 0.0)
            lines, n = sphere(centre, 1.0, f"{name}_{w}", first_vertex, first_normal, 16, 32)
            obj += lines + lamp(centre)
            first_vertex += n + 4
            first_normal += n
    mtl = "# Replaced by sheen.mat's entries of the same names.\nnewmtl lamp\n" + "".join(
        f"newmtl {name}_{w}\n" for name, _, _ in ROWS for w in SHEEN)
    return "\n".join(obj) + "\n", mtl


def main():
    if sys.argv[1:2] == ["--spheres"]:
        import toolenv
        toolenv.enter_venv()  # before printing: it runs this script again in the venv
        for ring, what in (((0.0, 0.6), "a disc of 0.6 of the radius"),
                           ((0.75, 0.95), "the rim, 0.75 to 0.95 of the radius")):
            print(f"\nPer sphere, over {what}:")
            sphere_table(*sys.argv[2:5], names=[r[0] for r in ROWS], values=SHEEN,
                         value_name="sheen", ring=ring)
        return
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    obj, mtl = scene_obj()
    for file, text in (("sheen-spheres.obj", obj), ("sheen-spheres.mtl", mtl),
                       ("sheen.mat", material_file()), ("scene.cfg", CFG)):
        with open(os.path.join(out, file), "w") as f:
            f.write(text)


if __name__ == "__main__":
    main()
