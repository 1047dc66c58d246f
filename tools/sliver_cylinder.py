#!/usr/bin/env python3
"""sliver_cylinder.py: writes a scene of long thin triangles (OBJ + MTL + scene.cfg).

Tessellated cylinders whose sides are slivers: each tube is `sides` strips around and `rings`
strips along, each strip two triangles a ring long and a side wide (about 600:1 at the defaults),
as CAD exports of cars and aircraft tessellate smooth panels. The tubes cross each other at
different tilts over a ground plane, so a sliver's bounding box is long and diagonal and overlaps
the boxes of hundreds of others: the case where a BVH that puts every triangle whole into one
leaf has children whose boxes overlap, and spatial splits (an SBVH, docs/scene-format.md
`bvh-splits`) pay. Defaults give 96,002 triangles.

Usage: tools/sliver_cylinder.py OUT_DIR [--sides N] [--rings N] [--tubes N]
Writes OUT_DIR/slivers.obj, OUT_DIR/slivers.mtl and OUT_DIR/scene.cfg; rendering scene.cfg writes
slivers.png there. Standard library only.
"""

import argparse
import math
import os
import sys

RADIUS = 1.0
LENGTH = 16.0            # of each tube, along its axis
GROUND_Y = -6.0
GROUND_HALF_SIZE = 30.0


def tube(sides, rings, tilt_z, tilt_x, offset):
    """One tube, its axis along y tilted by tilt_z about z then tilt_x about x, moved by offset.
    Returns (vertices, faces) with 0-based indices."""
    cz, sz, cx, sx = math.cos(tilt_z), math.sin(tilt_z), math.cos(tilt_x), math.sin(tilt_x)
    verts = []
    for r in range(rings + 1):
        y = -LENGTH / 2 + LENGTH * r / rings
        for s in range(sides):
            a = 2 * math.pi * s / sides
            x, z = RADIUS * math.cos(a), RADIUS * math.sin(a)
            x, y1 = x * cz - y * sz, x * sz + y * cz      # about z
            y2, z = y1 * cx - z * sx, y1 * sx + z * cx    # about x
            verts.append((x + offset[0], y2 + offset[1], z + offset[2]))
    faces = []
    for r in range(rings):
        for s in range(sides):
            a, b = r * sides + s, r * sides + (s + 1) % sides
            c, d = b + sides, a + sides
            faces.append((a, b, c))
            faces.append((a, c, d))
    return verts, faces


def fmt(x):
    return ("%.6f" % x).rstrip("0").rstrip(".")


def write_obj(path, tubes):
    with open(path, "w", newline="\n") as f:
        f.write("# Slivers: tubes of long thin triangles, written by tools/sliver_cylinder.py\n")
        f.write("mtllib slivers.mtl\n")
        base = 0
        for i, (verts, faces) in enumerate(tubes):
            for v in verts:
                f.write("v %s %s %s\n" % tuple(fmt(x) for x in v))
            f.write("g tube%d\nusemtl tube\n" % i)
            for a, b, c in faces:
                f.write("f %d %d %d\n" % (a + base + 1, b + base + 1, c + base + 1))
            base += len(verts)
        g = GROUND_HALF_SIZE
        for x, z in ((-g, -g), (g, -g), (g, g), (-g, g)):
            f.write("v %s %s %s\n" % (fmt(x), fmt(GROUND_Y), fmt(z)))
        f.write("g ground\nusemtl ground\n")
        f.write("f %d %d %d\nf %d %d %d\n" % (base + 1, base + 3, base + 2,
                                              base + 1, base + 4, base + 3))


MTL = """newmtl tube
Kd 0.7 0.2 0.15
Ks 0.3 0.3 0.3
Ns 40
illum 2

newmtl ground
Kd 0.6 0.6 0.6
illum 1
"""

SCENE_CFG = """# Slivers (tools/sliver_cylinder.py): {tubes} tubes of {sides} x {rings} strips, {triangles}
# triangles, each a long thin sliver, crossing over a ground plane.
geometry slivers.obj
output slivers.png
resolution 640 480
light ambient     0.05 0.05 0.05
light directional -0.3 -1 -0.4   2.5 2.5 2.5
camera eye 0 4 26  look 0 0 0  up 0 1 0  fov 50
"""


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("out_dir", help="folder for slivers.obj, slivers.mtl and scene.cfg")
    parser.add_argument("--sides", type=int, default=2000, help="strips around each tube")
    parser.add_argument("--rings", type=int, default=6, help="strips along each tube")
    parser.add_argument("--tubes", type=int, default=4, help="tubes, each at its own tilt")
    args = parser.parse_args(argv)
    if args.sides < 3 or args.rings < 1 or args.tubes < 1:
        parser.error("need at least 3 sides, 1 ring and 1 tube")
    os.makedirs(args.out_dir, exist_ok=True)
    tubes = []
    for i in range(args.tubes):
        turn = math.pi * i / args.tubes
        tubes.append(tube(args.sides, args.rings, 0.5 + turn, 0.35 * (i % 3 - 1),
                          (2.0 * math.cos(turn), 0.0, 2.0 * math.sin(turn))))
    write_obj(os.path.join(args.out_dir, "slivers.obj"), tubes)
    with open(os.path.join(args.out_dir, "slivers.mtl"), "w", newline="\n") as f:
        f.write(MTL)
    triangles = sum(len(t[1]) for t in tubes) + 2
    with open(os.path.join(args.out_dir, "scene.cfg"), "w", newline="\n") as f:
        f.write(SCENE_CFG.format(tubes=args.tubes, sides=args.sides, rings=args.rings,
                                 triangles=triangles))
    print("%s: %d triangles" % (args.out_dir, triangles))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
