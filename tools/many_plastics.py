#!/usr/bin/env python3
"""Writes a scene of many @roughplastic spheres, each its own material of its own roughness (from
0.03 at the back left to 1 at the front right, row by row) and colour, on a grey Lambertian floor
under a sky and one lamp: what a user's exported or generated scene of many plastics makes of the
coat tables (src/render/renderer_plastic.c: past 33 roughnesses of one index, one shared table
instead of a row each). `vkrt render --verbose` prints the materials' start-up time.
Usage:
    many_plastics.py OUTPUT_DIR [COUNT]     (COUNT spheres, 500 by default)"""
import colorsys
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cornell_spheres import sphere  # noqa: E402

CFG = """\
# {count} @roughplastic spheres of distinct roughness; made by tools/many_plastics.py.
geometry    many-plastics.obj
materials   many-plastics.mat
integrator  path
resolution  640 400
samples     32
max-depth   6
environment 0.35 0.4 0.5
light point 4 {lamp_y:.1f} 6  {power} {power} {power}
output      many-plastics.png
camera eye 0 {eye_y:.3f} {eye_z:.3f}  look 0 0 {look_z:.3f}  up 0 1 0  fov 45
"""


def main():
    if len(sys.argv) not in (2, 3) or sys.argv[1].startswith("-"):
        sys.exit(__doc__)
    out, count = sys.argv[1], int(sys.argv[2]) if len(sys.argv) == 3 else 500
    columns = math.ceil(math.sqrt(count * 1.6))
    rows = math.ceil(count / columns)
    os.makedirs(out, exist_ok=True)
    obj, mat = ["mtllib many-plastics.mtl"], []
    mtl = ["newmtl floor", "Kd 0.5 0.5 0.5"]
    half_w, half_d = columns / 2 + 1, rows / 2 + 1
    obj += ["usemtl floor"] + [f"v {x} 0 {z}" for x, z in ((-half_w, half_d), (half_w, half_d),
                                                           (half_w, -half_d), (-half_w, -half_d))]
    obj.append("f 1 2 3 4")
    vertex, normal = 5, 1
    for k in range(count):
        row, column = divmod(k, columns)
        roughness = 0.03 + 0.97 * k / max(count - 1, 1)
        name = f"p{k}"
        r, g, b = colorsys.hsv_to_rgb((k * 0.618034) % 1.0, 0.6, 0.7)
        mtl.append(f"newmtl {name}")
        mat.append(f"{name} 0 @roughplastic {r:.3f} {g:.3f} {b:.3f} 0  1 1 1 0  0 0 0  1.5  "
                   f"0 0 0  0  {roughness:.6f}")
        centre = (column - (columns - 1) / 2, 0.4, row - (rows - 1) / 2)
        lines, n = sphere(centre, 0.4, name, vertex, normal, rings=8, segments=16)
        obj += lines
        vertex += n
        normal += n
    with open(os.path.join(out, "many-plastics.obj"), "w") as f:
        f.write("\n".join(obj) + "\n")
    with open(os.path.join(out, "many-plastics.mtl"), "w") as f:
        f.write("\n".join(mtl) + "\n")
    with open(os.path.join(out, "many-plastics.mat"), "w") as f:
        f.write("\n".join(mat) + "\n")
    with open(os.path.join(out, "scene.cfg"), "w") as f:
        f.write(CFG.format(count=count, lamp_y=rows * 1.5, power=round(3 * (rows * 1.5) ** 2),
                           eye_y=rows * 0.9, eye_z=rows * 1.1,
                           look_z=0.5))


if __name__ == "__main__":
    main()
