#!/usr/bin/env python3
"""Writes scenes/coated-spheres/: nine spheres under a clear coat (Blender's Principled coat:
weight 1, index 1.5; docs/materials.md), in the room of tools/rough_spheres.py. Rows, top to
bottom: a white @roughconductor (Ks 1, for which vkrt's Schlick Fresnel is Mitsuba's
conductor `none`) of roughness 0.4, a red Lambertian (@roughplastic with Ks 0 and
Ni 1: no coat of its own) and a rough glass of roughness 0.4; columns, left to right, the coat's
roughness 0.05, 0.2 and 0.5 (numbers 18 and 19 of each line: weight, roughness).
Usage:
    coated_spheres.py OUTPUT_DIR
    coated_spheres.py --spheres VKRT.exr MITSUBA.exr CONVERGED.exr
The second form prints, per sphere, the mean of vkrt's image and of Mitsuba's (renders of the
scene.cfg at equal samples; Mitsuba's coat is tools/mitsuba_scene.py's ClearCoat, a plug-in
written from docs/materials.md over Mitsuba's own bases) against Mitsuba's converged image, and
their per-pixel relative errors."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from rough_spheres import scene_cfg, sphere_grid, sphere_table  # noqa: E402

COAT_ROUGHNESS = (0.05, 0.2, 0.5)
# name prefix, built-in, numbers 0-17 (the .mtl layout of docs/materials.md; 16 the base's
# roughness, 17 metallic, unused here); the coat's weight (18) and roughness (19) follow.
ROWS = (
    ("metal", "@roughconductor", "0 0 0 0  1 1 1 0  0 0 0  0  0 0 0  0  0.4  0"),
    ("red", "@roughplastic", "0.7 0.08 0.05 0  0 0 0 0  0 0 0  1  0 0 0  0  0  0"),
    ("glass", "@roughdielectric", "0 0 0 0  0 0 0 0  0 0 0  1.5  0 0 0  0  0.4  0"),
)

CFG = scene_cfg("""\
# Coated spheres: a clear coat (weight 1, index 1.5) over a white rough conductor, a red
# Lambertian and a rough glass (top to bottom), coat roughness 0.05, 0.2, 0.5 (left to right);
# made by tools/coated_spheres.py.
""", "coated-spheres.obj", "coated.mat", "coated-spheres.png")

WHITTED_CFG = scene_cfg("""\
# The coated spheres in Whitted's model: a point light and ambient light instead of the lamp; the
# coat adds the light's highlight through the BSDF, and each hit casts one glossy ray from the
# coat or the base.
""", "coated-spheres.obj", "coated.mat", "coated-spheres-whitted.png", whitted=True)


def material_file():
    lines = ["# The spheres' materials: numbers in the .mtl layout (docs/materials.md); the last "
             "two the coat's weight (18) and roughness (19).",
             "lamp 0 @emissive 0 0 0 0  0 0 0 0  30 30 30"]
    for name, shader, numbers in ROWS:
        for r in COAT_ROUGHNESS:
            lines.append(f"{name}_{r} 0 {shader} {numbers}  1 {r}")
    return "\n".join(lines) + "\n"


def main():
    if sys.argv[1:2] == ["--spheres"]:
        sphere_table(*sys.argv[2:5], names=[r[0] for r in ROWS], values=COAT_ROUGHNESS,
                     value_name="coat roughness")
        return
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    obj, mtl = sphere_grid("Nine coated spheres in a room; made by tools/coated_spheres.py.",
                           "coated-spheres.mtl", "coated.mat", [r[0] for r in ROWS],
                           COAT_ROUGHNESS)
    for file, text in (("coated-spheres.obj", obj),
                       ("coated-spheres.mtl", mtl), ("coated.mat", material_file()),
                       ("scene.cfg", CFG), ("whitted.cfg", WHITTED_CFG)):
        with open(os.path.join(out, file), "w") as f:
            f.write(text)


if __name__ == "__main__":
    main()
