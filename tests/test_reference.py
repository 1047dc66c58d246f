#!/usr/bin/env python3
"""test_reference.py: tools/reference (Mitsuba 3) on the inputs real assets bring, each scene
written here into a temporary folder and rendered at a few pixels, with the value vkrt's
conventions give (docs/materials.md, docs/scene-format.md, docs/speed-vs-accuracy.md):

- a mirror over a diffuse base whose doubled Ks Mitsuba refused (Kd 0.071, Ks 0.8, from a car
  model), and one with Kd + Ks > 1: under a white sky and ambient light both show Kd + Ks;
- faces without `vt` under a textured material read the texture at uv (0, 0);
- a surface whose bent vertex normals turn away from the viewer is still lit from the front of
  its triangle, as vkrt's two-sided shading has it (Mitsuba's `twosided` would show it black);
- path mode: an emissive quad shows Ke from its front (counter-clockwise) face only, and
  `integrator auto` picks path for it;
- whitted mode: an emissive square lights a floor under it with the closed form's irradiance
  (vkrt's Whitted samples emissive geometry as a light);
- the environment map's orientation and `rotate` (docs/scene-format.md, environment-map);
- the surface maps (docs/materials.md, "Normal, bump and emission maps"): a height map's
  displaced normal, a normal map's green as +v (mirrored uv included) and -bm, and map_Ke.

Skipped (77) where the repository's .venv has no Mitsuba (tools/setup-python makes it).
    usage: test_reference.py"""
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tools"))
import toolenv  # noqa: E402

toolenv.enter_venv()
try:
    import mitsuba  # noqa: F401
    import imagediff
except ImportError as e:
    print(f"test_reference: skipped: no Mitsuba in {toolenv.VENV} ({e}); run tools/setup-python")
    sys.exit(77)
import numpy as np  # noqa: E402

REFERENCE = os.path.join(ROOT, "tools", "reference")
SIZE = 8
# A quad in the plane z = 0, two units wide, counter-clockwise seen from +z.
QUAD = "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n"
FRONT = "camera eye 0 0 3  look 0 0 0  up 0 1 0  fov 20\n"
failures = []


def render(folder, name, obj, mtl, cfg, spp=64, integrator=None):
    """Writes NAME.obj, NAME.mtl and NAME.cfg and renders them; returns (image, stderr)."""
    with open(os.path.join(folder, f"{name}.obj"), "w") as f:
        f.write(f"mtllib {name}.mtl\n" + obj)
    with open(os.path.join(folder, f"{name}.mtl"), "w") as f:
        f.write(mtl)
    scene = os.path.join(folder, f"{name}.cfg")
    with open(scene, "w") as f:
        f.write(f"geometry {name}.obj\nresolution {SIZE} {SIZE}\n" + cfg)
    out = os.path.join(folder, f"{name}.exr")
    cmd = [REFERENCE, scene, "-o", out, "--spp", str(spp)]
    if integrator:
        cmd += ["--integrator", integrator]
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode != 0:
        failures.append(f"{name}: tools/reference failed:\n{done.stderr}")
        return None, done.stderr
    return imagediff.read_exr(out), done.stderr


def expect(name, image, value, tolerance):
    if image is None:
        return
    mean = image.mean(axis=(0, 1))
    if np.abs(mean - value).max() > tolerance * max(np.abs(value).max(), 1e-6):
        failures.append(f"{name}: mean {mean.round(4).tolist()}, expected {value} within "
                        f"{tolerance:.0%}")
    else:
        print(f"ok {name}: mean {mean.round(4).tolist()} (expected {value})")


def mirrors(folder):
    """illum 3 with Kd: Kd/pi plus a mirror of Ks. The camera looks straight at it, so the mirror
    shows the sky behind the camera: Ks x sky; ambient light adds Kd x ambient."""
    cfg = FRONT + "environment 1 1 1\nlight ambient 1 1 1\n"
    for name, kd, ks in (("car-paint", 0.071, 0.8), ("over-one", 0.6, 0.8)):
        mtl = f"newmtl m\nKd {kd} {kd} {kd}\nKs {ks} {ks} {ks}\nillum 3\n"
        image, log = render(folder, name, QUAD + "usemtl m\nf 1 2 3 4\n", mtl, cfg, spp=256)
        expect(name, image, kd + ks, 0.03)
        if kd + ks > 1 and image is not None and "reflects more light than it receives" not in log:
            failures.append(f"{name}: no warning that Kd + Ks > 1 is not physical:\n{log}")


def texture_without_vt(folder):
    """A 4x4 map whose four corner texels are white and the rest black: at uv (0, 0) bilinear
    filtering with wrapping reads exactly the four corners, so every pixel is 1 (Kd 1, ambient
    1). Mitsuba's own default (the barycentric coordinates as uv) reads mostly black."""
    import mitsuba as mi
    mi.set_variant("scalar_rgb")
    texels = np.zeros((4, 4, 3), np.uint8)
    texels[[0, 0, -1, -1], [0, -1, 0, -1]] = 255
    mi.Bitmap(texels, pixel_format=mi.Bitmap.PixelFormat.RGB).write(
        os.path.join(folder, "corners.png"))
    mtl = "newmtl t\nKd 1 1 1\nmap_Kd corners.png\n"
    image, _ = render(folder, "no-vt", QUAD + "usemtl t\nf 1 2 3 4\n", mtl,
                      FRONT + "light ambient 1 1 1\n", spp=4)
    expect("no-vt", image, 1.0, 0.01)


def bent_normals(folder):
    """The camera looks up at the quad from below (direction to it (0, -0.8, 0.6)); the vertex
    normals lean up, (0, 1, 0.3) normalised, still on the triangle's side (+z) but turned away
    from the viewer. A directional light from (0, 0.5, 0.866) is in front of both normals: vkrt
    shows Kd / pi x irradiance x cos(light, shading normal)."""
    n = np.array([0.0, 1.0, 0.3]) / np.linalg.norm([0.0, 1.0, 0.3])
    light = np.array([0.0, 0.5, np.sqrt(0.75)])
    obj = QUAD + "vn {} {} {}\nusemtl d\nf 1//1 2//1 3//1 4//1\n".format(*n)
    eye = 3.0 * np.array([0.0, -0.8, 0.6])
    cfg = (f"camera eye {eye[0]} {eye[1]} {eye[2]}  look 0 0 0  up 0 0 1  fov 10\n"
           f"light directional {-light[0]} {-light[1]} {-light[2]}  3.14159265 3.14159265 "
           "3.14159265\n")
    image, _ = render(folder, "bent-normals", obj, "newmtl d\nKd 0.5 0.5 0.5\n", cfg, spp=4)
    expect("bent-normals", image, 0.5 * float(np.dot(n, light)), 0.01)


def emitter_sides(folder):
    """Path mode: a quad of Ke 2 (no Kd) seen from its counter-clockwise side shows 2, seen from
    behind (the same quad wound the other way) 0; `integrator auto` chooses path."""
    mtl = "newmtl lamp\nKd 0 0 0\nKe 2 2 2\n"
    for name, face, value in (("lamp-front", "f 1 2 3 4", 2.0), ("lamp-back", "f 4 3 2 1", 0.0)):
        image, log = render(folder, name, QUAD + f"usemtl lamp\n{face}\n", mtl,
                            FRONT + "integrator auto\n", spp=4)
        expect(name, image, value, 0.01)
        if image is not None and "path (auto: emissive material 'lamp'" not in log:
            failures.append(f"{name}: integrator auto did not choose path:\n{log}")


def whitted_lamp(folder):
    """Whitted: a floor (Kd 0.5) under a square lamp of half side 0.25 at height 1 facing down
    (Ke 4), seen at the point under it through a 2-degree view: Kd / pi x E, E = Ke x 4 X /
    sqrt(1 + X^2) atan(X / sqrt(1 + X^2)), X = 0.25 (tests/test_light.c holds vkrt to the same)."""
    x = 0.25
    s = np.sqrt(1 + x * x)
    value = 0.5 / np.pi * 4 * 4 * x / s * np.arctan(x / s)
    obj = ("v -2 0 -2\nv 2 0 -2\nv 2 0 2\nv -2 0 2\nusemtl floor\nf 1 4 3 2\n"
           "v -0.25 1 -0.25\nv 0.25 1 -0.25\nv 0.25 1 0.25\nv -0.25 1 0.25\nusemtl lamp\n"
           "f 5 6 7 8\n")
    mtl = "newmtl floor\nKd 0.5 0.5 0.5\nnewmtl lamp\nKd 0 0 0\nKe 4 4 4\n"
    cfg = "max-depth 0\ncamera eye 0 0.9 0.6  look 0 0 0  up 0 1 0  fov 2\n"
    image, _ = render(folder, "whitted-lamp", obj, mtl, cfg, spp=256, integrator="whitted")
    expect("whitted-lamp", image, value, 0.01)


def environment_map(folder):
    """A map of four columns, red, green, blue, white from the left: column 0 spans directions
    from -z (u = 0) to +x (u = 1/4), so a camera looking halfway between, (1, 0, -1), sees red
    (the middle of column 0); with `rotate 90` (phi = 2 pi u - 90 degrees) it sees u = 3/8,
    green. The quad is behind the camera, out of sight."""
    import mitsuba as mi
    mi.set_variant("scalar_rgb")
    columns = np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 1]], np.float32)
    mi.Bitmap(np.repeat(columns[None], 2, axis=0)).write(os.path.join(folder, "sky-map.exr"))
    camera = "camera eye 0 0 0  look 1 0 -1  up 0 1 0  fov 1\n"
    obj = "v 1 1 5\nv -1 1 5\nv 0 -1 5\nf 1 2 3\n"
    for name, rotate, value in (("sky", 0, [1, 0, 0]), ("sky-rotated", 90, [0, 1, 0])):
        image, _ = render(folder, name, obj, "", camera + f"environment-map sky-map.exr rotate "
                          f"{rotate}\n", spp=1, integrator="path")
        expect(name, image, np.array(value, np.float32), 0.02)


def write_png(folder, name, texels):
    import mitsuba as mi
    mi.set_variant("scalar_rgb")
    mi.Bitmap(np.ascontiguousarray(texels, np.uint8),
              pixel_format=mi.Bitmap.PixelFormat.RGB).write(os.path.join(folder, name))


# The quad with uv (0, 0) to (1, 1) at its corners: dp/du = 2 x, dp/dv = 2 y.
QUAD_UV = QUAD + "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
# A directional light of irradiance pi from direction l (towards the light): a Lambertian Kd
# shows Kd x max(0, n . l) for a shading normal n.
def lit_from(light):
    return ("light directional {} {} {}  3.14159265 3.14159265 3.14159265\n"
            .format(*(-np.asarray(light))))


def height_map(folder):
    """`map_Bump -bm 2` of a ramp of 8 columns, 32 k / 255 in column k: the slope is
    dh/du = 8 x 32 / 255 per unit of u wherever the view falls (u from 0.24 to 0.76, away from
    the wrap). The displaced surface's normal is (2 x + 2 dh/du z) x (2 y) ~ (-dh/du, 0, 1); lit
    from (-1, 0, 1) it shows 0.5 (Kd) x the cosine."""
    write_png(folder, "ramp.png", np.repeat(np.repeat(np.arange(8, dtype=np.uint8)[None, :, None]
                                                      * 32, 2, axis=0), 3, axis=2))
    slope = 8 * 32 / 255
    n = np.array([-slope, 0.0, 1.0]) / np.hypot(slope, 1.0)
    light = np.array([-1.0, 0.0, 1.0]) / np.sqrt(2.0)
    image, _ = render(folder, "height-map", QUAD_UV + "usemtl b\nf 1/1 2/2 3/3 4/4\n",
                      "newmtl b\nKd 0.5 0.5 0.5\nmap_Bump -bm 2 ramp.png\n",
                      FRONT + lit_from(light), spp=4, integrator="whitted")
    expect("height-map", image, 0.5 * float(np.dot(n, light)), 0.01)


def normal_map(folder):
    """`norm -bm 0.5` of one texel (128, 204, 230): the tangent-space normal (0.004, 0.6, 0.804)
    with x and y halved, in the frame (dp/du, the bitangent, n): green is +v (the OpenGL
    convention), so the normal leans to +y, and lit from (0, 0.6, 0.8) the quad shows 0.5 (Kd)
    x the cosine. With u mirrored (dp/du = -2 x) vkrt mirrors the bitangent with it: green is
    still +v, the same picture; were green -v, the cosine would be 0.37 against 0.92."""
    write_png(folder, "tilt.png", np.full((2, 2, 3), (128, 204, 230), np.uint8))
    c = 2.0 * np.array([128, 204, 230]) / 255.0 - 1.0
    light = np.array([0.0, 0.6, 0.8])
    mtl = "newmtl n\nKd 0.5 0.5 0.5\nnorm -bm 0.5 tilt.png\n"
    for name, vt, tangent in (("normal-map", "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n", 1.0),
                              ("normal-map-mirrored", "vt 1 0\nvt 0 0\nvt 0 1\nvt 1 1\n", -1.0)):
        n = np.array([0.5 * c[0] * tangent, 0.5 * c[1], c[2]])
        n /= np.linalg.norm(n)
        image, _ = render(folder, name, QUAD + vt + "usemtl n\nf 1/1 2/2 3/3 4/4\n", mtl,
                          FRONT + lit_from(light), spp=4, integrator="whitted")
        expect(name, image, 0.5 * float(np.dot(n, light)), 0.01)


def emission_map(folder):
    """Path mode: a lamp whose map_Ke is one grey texel of 128 (0.2159 decoded from sRGB) shows
    Ke x 0.2159 from its front, and the map alone (Ke 1) without a Ke line."""
    write_png(folder, "grey.png", np.full((2, 2, 3), 128, np.uint8))
    grey = ((128 / 255 + 0.055) / 1.055) ** 2.4
    for name, ke, value in (("map-ke", "Ke 2 2 2\n", 2 * grey), ("map-ke-alone", "", grey)):
        image, _ = render(folder, name, QUAD_UV + "usemtl lamp\nf 1/1 2/2 3/3 4/4\n",
                          f"newmtl lamp\nKd 0 0 0\n{ke}map_Ke grey.png\n", FRONT, spp=4)
        expect(name, image, value, 0.01)


def main():
    with tempfile.TemporaryDirectory() as folder:
        height_map(folder)
        normal_map(folder)
        emission_map(folder)
        mirrors(folder)
        texture_without_vt(folder)
        bent_normals(folder)
        emitter_sides(folder)
        whitted_lamp(folder)
        environment_map(folder)
    for failure in failures:
        print(f"FAIL {failure}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
