#!/usr/bin/env python3
"""Writes surface-maps.obj, surface-maps.mtl and three small PNG textures: a scene that shows the
.mtl maps that change a surface (docs/materials.md, "Normal, bump and emission maps").

The scene, in metres, y up: a floor (y = 0) with a tangent-space normal map of domes (`norm`), a
back wall (z = -3) of bricks from a height map (`map_Bump -bm 0.02`: mortar 2 cm deep), a sphere
with the domes' normal map over its own uv (the frame turning with interpolated normals), and a
panel on the wall that emits through a striped `map_Ke`. Faces wind counter-clockwise seen from
the front. The textures are generated here (a few kB each), not drawn.

Run from anywhere: python3 make_scene.py   (writes next to this script)"""
import math
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))

MTL = """\
# Materials of surface-maps.obj (made by make_scene.py).
newmtl floor
Kd 0.55 0.55 0.6
norm domes.png
newmtl bricks
Kd 0.62 0.4 0.3
map_Bump -bm 0.02 bricks.png
newmtl ball
Kd 0.2 0.35 0.6
Ks 0.3 0.3 0.3
Ns 60
illum 2
norm domes.png
newmtl sign
Kd 0 0 0
Ke 4 4 4
map_Ke sign.png
"""


def write_png(name, width, height, texel):
    """An 8-bit RGB PNG of texel(x, y) -> (r, g, b) in 0..255, y = 0 the top row."""
    rows = b"".join(
        b"\x00" + bytes(c for x in range(width) for c in texel(x, y)) for y in range(height))

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    png = (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
           + chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b""))
    with open(os.path.join(HERE, name), "wb") as f:
        f.write(png)


def encode(n):
    """A unit tangent-space normal as a normal map texel: (n + 1) / 2, rounded."""
    return tuple(max(0, min(255, round((c + 1) * 127.5))) for c in n)


def domes(x, y, cell=32, radius=13.0):
    """Hemispherical domes on a grid, OpenGL convention: green is up in the image (+v)."""
    dx = (x % cell) + 0.5 - cell / 2
    dy = (y % cell) + 0.5 - cell / 2
    r2 = (dx * dx + dy * dy) / (radius * radius)
    if r2 >= 1.0:
        return encode((0.0, 0.0, 1.0))
    return encode((dx / radius, -dy / radius, math.sqrt(1.0 - r2)))


def bricks(x, y, w=64, h=32, mortar=2, bevel=4):
    """Heights: 255 on a brick's face, falling linearly over `bevel` texels to 0 in the mortar;
    every other row shifted by half a brick."""
    row = y // h
    bx = (x + (w // 2 if row % 2 else 0)) % w
    by = y % h
    edge = min(bx, w - 1 - bx, by, h - 1 - by) - mortar
    v = 0 if edge < 0 else min(255, round(255 * (edge + 1) / bevel))
    return (v, v, v)


def sign(x, y):
    """Warm stripes on black with a cool band: the light the panel gives varies across it."""
    if y < 4 or y >= 28 or x < 4 or x >= 60:
        return (0, 0, 0)
    if 14 <= y < 18:
        return (90, 170, 255)
    return (255, 200, 120) if (x // 6) % 2 == 0 else (0, 0, 0)


def quad(out, corners, uvs, material):
    out["mat"].append(material)
    base = len(out["v"])
    out["v"] += corners
    tbase = len(out["vt"])
    out["vt"] += uvs
    out["f"].append((material, [(base + k + 1, tbase + k + 1, None) for k in range(4)]))


def sphere(out, centre, radius, material, rings=24, segments=48):
    """A UV sphere with normals per vertex and uv (u around from +x, v from the south pole),
    the domes repeated 6 x 3 times over it."""
    vbase, tbase, nbase = len(out["v"]), len(out["vt"]), len(out["vn"])
    for r in range(rings + 1):
        theta = math.pi * r / rings
        for s in range(segments + 1):
            phi = 2 * math.pi * s / segments
            n = (math.sin(theta) * math.cos(phi), math.cos(theta), -math.sin(theta) * math.sin(phi))
            out["v"].append(tuple(c + radius * d for c, d in zip(centre, n)))
            out["vn"].append(n)
            out["vt"].append((6.0 * s / segments, 3.0 * (1.0 - r / rings)))

    def k(r, s):
        return r * (segments + 1) + s + 1

    for r in range(rings):
        for s in range(segments):
            corners = [k(r, s), k(r + 1, s), k(r + 1, s + 1), k(r, s + 1)]
            out["f"].append((material, [(vbase + c, tbase + c, nbase + c) for c in corners]))


def main():
    write_png("domes.png", 128, 128, domes)
    write_png("bricks.png", 128, 128, bricks)
    write_png("sign.png", 64, 32, sign)
    with open(os.path.join(HERE, "surface-maps.mtl"), "w") as f:
        f.write(MTL)
    out = {"v": [], "vt": [], "vn": [], "f": [], "mat": []}
    quad(out, [(-3, 0, 3), (3, 0, 3), (3, 0, -3), (-3, 0, -3)],
         [(0, 0), (4, 0), (4, 4), (0, 4)], "floor")
    quad(out, [(-3, 0, -3), (3, 0, -3), (3, 3, -3), (-3, 3, -3)],
         [(0, 0), (3, 0), (3, 1.5), (0, 1.5)], "bricks")
    quad(out, [(0.4, 1.5, -2.98), (2.2, 1.5, -2.98), (2.2, 2.4, -2.98), (0.4, 2.4, -2.98)],
         [(0, 0), (1, 0), (1, 1), (0, 1)], "sign")
    sphere(out, (-0.9, 0.7, -0.6), 0.7, "ball")
    lines = ["# Made by make_scene.py: a floor with a normal map, a brick wall from a height map,",
             "# a sphere with a normal map and a panel emitting through map_Ke.",
             "mtllib surface-maps.mtl"]
    lines += ["v %.6f %.6f %.6f" % v for v in out["v"]]
    lines += ["vt %.6f %.6f" % t for t in out["vt"]]
    lines += ["vn %.6f %.6f %.6f" % n for n in out["vn"]]
    current = None
    for material, corners in out["f"]:
        if material != current:
            lines.append("usemtl " + material)
            current = material
        if corners[0][2] is None:
            lines.append("f " + " ".join("%d/%d" % (v, t) for v, t, _ in corners))
        else:
            lines.append("f " + " ".join("%d/%d/%d" % c for c in corners))
    with open(os.path.join(HERE, "surface-maps.obj"), "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
