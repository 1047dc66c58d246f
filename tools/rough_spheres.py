#!/usr/bin/env python3
"""Writes scenes/rough-spheres/: nine spheres, a row each of the rough built-ins (top: a white
@roughconductor, Ks 1, for which Schlick's Fresnel is Mitsuba's conductor `none`; middle: a blue
@roughplastic; bottom: @roughdielectric glass of index 1.5) at roughness 0.05, 0.2 and 0.5 from
left to right, over a grey floor before a wall of two colours (for the glass to show what it
refracts), lit by an emissive quad above and in front and a dim constant environment: the scene
of the Mitsuba agreement in docs/speed-vs-accuracy.md.
Usage:
    rough_spheres.py OUTPUT_DIR
    rough_spheres.py --spheres VKRT.exr MITSUBA.exr CONVERGED.exr
    rough_spheres.py --plastic-albedo
The second form prints, per sphere, the mean of vkrt's image and of Mitsuba's (renders of the
scene.cfg at equal samples, as tools/agreement leaves them in its --work folder) against
Mitsuba's converged image, and their per-pixel relative errors (tools/imagediff.py's). The
third prints the directional albedo at a viewing cosine of 0.5 of Mitsuba's roughplastic (Kd 1,
index 1.5, 2^20 of its own samples) at the furnace's roughnesses, to hold against vkrt's
(tests/test_microfacet.c prints those)."""
import math
import os
import sys

from cornell_spheres import sphere

ROUGHNESS = (0.05, 0.2, 0.5)
# name prefix, built-in, the numbers before roughness (the .mtl layout of docs/materials.md):
# 0-2 Kd, 3 transparency, 4-6 Ks, 7 Ns, 8-10 Ke, 11 Ni, 12-14 Tf, 15 illum.
ROWS = (
    ("conductor", "@roughconductor", "0 0 0 0  1 1 1 0  0 0 0  0  0 0 0  0"),
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

def scene_cfg(comment, obj, mat, output, whitted=False):
    """A scene.cfg of a sphere grid (sphere_grid): path traced under the lamp and a dim
    environment, or in Whitted's model with a point light and ambient light instead of the lamp."""
    lights = "light ambient 0.05 0.05 0.05\nlight point 0 6.5 3   60 60 60\n" if whitted else ""
    return (f"{comment}geometry    {obj}\nmaterials   {mat}\n"
            f"integrator  {'whitted' if whitted else 'path'}\nresolution  256 256\nsamples     64\n"
            f"max-depth   8\nenvironment 0.2 0.2 0.2\n{lights}output      {output}\n"
            "camera eye 0 0 11  look 0 0 0  up 0 1 0  fov 50\n")


CFG = scene_cfg("""\
# Rough spheres: rows of @roughconductor, @roughplastic, @roughdielectric (top to bottom) at
# roughness 0.05, 0.2, 0.5 (left to right); made by tools/rough_spheres.py.
""", "rough-spheres.obj", "rough.mat", "rough-spheres.png")

WHITTED_CFG = scene_cfg("""\
# The rough spheres in Whitted's model: a point light and ambient light instead of the lamp; the
# rough built-ins add the light's highlight through their BSDF and cast one glossy ray per hit.
""", "rough-spheres.obj", "rough.mat", "rough-spheres-whitted.png", whitted=True)


def material_file():
    lines = ["# The spheres' materials: numbers in the .mtl layout (docs/materials.md), roughness "
             "the 17th (16).", "lamp 0 @emissive 0 0 0 0  0 0 0 0  30 30 30"]
    for name, shader, numbers in ROWS:
        for r in ROUGHNESS:
            lines.append(f"{name}_{r} 0 {shader} {numbers}  {r}")
    return "\n".join(lines) + "\n"


def sphere_table(vkrt_exr, mitsuba_exr, converged_exr, names=None, values=ROUGHNESS,
                 value_name="roughness", ring=(0.0, 0.6)):
    """Per sphere: image means against the converged one, and per-pixel relative errors, over
    the ring between ring[0] and ring[1] of the sphere's radius about its centre in the picture
    (the camera of CFG; by default a disc of 0.6 of the radius); the rows are names (default:
    ROWS'), the columns values."""
    names = names or [r[0] for r in ROWS]
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import toolenv
    toolenv.enter_venv()
    import imagediff
    import numpy as np
    test, mitsuba, ref = (imagediff.read_exr(p) for p in (vkrt_exr, mitsuba_exr, converged_exr))
    h, w, _ = ref.shape
    half = 11 * math.tan(math.radians(25))  # fov 50 at distance 11: half the picture's height
    ys, xs = np.mgrid[0:h, 0:w]
    floor = imagediff.RELATIVE_FLOOR * float(ref.mean())
    print(f"| sphere | {value_name} | mean: converged | vkrt | Mitsuba | per-pixel error: vkrt "
          "| Mitsuba |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for row, name in enumerate(names):
        for column, r in enumerate(values):
            cx = (0.5 + 2.4 * (column - 1) / (2 * half * w / h)) * w
            cy = (0.5 - 2.4 * (1 - row) / (2 * half)) * h
            r2 = ((xs + 0.5 - cx) ** 2 + (ys + 0.5 - cy) ** 2) / (h / (2 * half)) ** 2
            disc = (r2 >= ring[0] ** 2) & (r2 < ring[1] ** 2)
            m = [float(img[disc].mean()) for img in (ref, test, mitsuba)]
            e = [float((np.abs(img[disc] - ref[disc]) / (np.abs(ref[disc]) + floor)).mean())
                 for img in (test, mitsuba)]
            if m[0] == 0.0:  # a black region (the sheen spheres' black base without a sheen)
                print(f"| {name} | {r} | 0 | {m[1]:.2g} | {m[2]:.2g} | - | - |")
                continue
            print(f"| {name} | {r} | {m[0]:.4f} | {m[1] / m[0] - 1:+.2%} | {m[2] / m[0] - 1:+.2%} "
                  f"| {e[0]:.2%} | {e[1]:.2%} |")


def plastic_albedo():
    """Mitsuba's roughplastic's albedo at cos 0.5, by its own BSDF sampling."""
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import toolenv
    toolenv.enter_venv()
    toolenv.find_llvm()
    import drjit as dr
    import mitsuba as mi
    mi.set_variant("llvm_ad_rgb")
    n = 1 << 20
    for r in (0.05, 0.2, 0.5, 1.0):
        bsdf = mi.load_dict({"type": "roughplastic", "distribution": "ggx", "alpha": r * r,
                             "int_ior": 1.5, "ext_ior": 1.0, "nonlinear": False,
                             "diffuse_reflectance": {"type": "rgb", "value": [1.0, 1.0, 1.0]}})
        si = dr.zeros(mi.SurfaceInteraction3f)
        si.wi = mi.Vector3f(math.sqrt(0.75), 0.0, 0.5)
        si.sh_frame = mi.Frame3f(mi.Normal3f(0.0, 0.0, 1.0))
        rng = mi.PCG32(n)
        _, weight = bsdf.sample(mi.BSDFContext(), si, rng.next_float32(),
                                mi.Point2f(rng.next_float32(), rng.next_float32()))
        print(f"roughplastic, roughness {r}: albedo at cos 0.5 {dr.mean(weight.x)[0]:.4f}")


def sphere_grid(title, mtllib, material_file_name, names, values):
    """The OBJ and .mtl text of a 3 x 3 grid of unit spheres in ROOM: row k (top to bottom) of
    names[k], column j (left to right) of values[j], each sphere's material f"{name}_{value}",
    an .mtl entry that the material file (material_file_name) replaces."""
    obj = [f"# {title}", f"mtllib {mtllib}"]
    first_vertex = first_normal = 1
    for row, name in enumerate(names):
        for column, value in enumerate(values):
            centre = (2.4 * (column - 1), 2.4 * (1 - row), 0.0)
            lines, n = sphere(centre, 1.0, f"{name}_{value}", first_vertex, first_normal, 16, 32)
            obj += lines
            first_vertex += n
            first_normal += n
    obj.append(ROOM.rstrip("\n"))
    # The OBJ's usemtl names must be .mtl materials for the material file's entries to replace.
    mtl = MTL + f"# Replaced by {material_file_name}'s entries of the same names.\n" + "".join(
        f"newmtl {name}_{value}\n" for name in names for value in values)
    return "\n".join(obj) + "\n", mtl


def main():
    if sys.argv[1:2] == ["--plastic-albedo"]:
        plastic_albedo()
        return
    if sys.argv[1:2] == ["--spheres"]:
        sphere_table(*sys.argv[2:5])
        return
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    obj, mtl = sphere_grid("Nine rough spheres in a room; made by tools/rough_spheres.py.",
                           "rough-spheres.mtl", "rough.mat", [r[0] for r in ROWS], ROUGHNESS)
    for file, text in (("rough-spheres.obj", obj), ("rough-spheres.mtl", mtl),
                       ("rough.mat", material_file()), ("scene.cfg", CFG),
                       ("whitted.cfg", WHITTED_CFG)):
        with open(os.path.join(out, file), "w") as f:
            f.write(text)


if __name__ == "__main__":
    main()
