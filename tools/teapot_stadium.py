#!/usr/bin/env python3
"""teapot_stadium.py: writes the "teapot in a stadium" test scene (OBJ + MTL + scene.cfg).

The scene is the classic worst case for a uniform grid (Haines, "teapot in a stadium"; Havran's
thesis, 2000): a small, densely tessellated object (here a UV sphere of radius 1 at the origin,
about 20,000 triangles) inside a huge, sparse environment (a bowl of stands of radius 2000 made of
a few hundred large triangles, and a ground plane). The grid's resolution follows the scene's
bounds, so its cells are tens of units wide and the whole dense object falls into one to eight
cells: rays that hit it test thousands of triangles per cell. A BVH (or a hierarchical grid)
adapts to the dense object and does not suffer. The camera sits close to the sphere, so most
primary rays hit it.

Usage: tools/teapot_stadium.py OUT_DIR [--dense-triangles N]
Writes OUT_DIR/stadium.obj, OUT_DIR/stadium.mtl and OUT_DIR/scene.cfg (docs/scene-format.md);
rendering scene.cfg writes stadium.png there. Standard library only.
"""

import argparse
import math
import os
import sys

SPHERE_RADIUS = 1.0
STADIUM_INNER_RADIUS = 1500.0   # where the stands start (the field is inside)
STADIUM_OUTER_RADIUS = 2000.0   # top row of the stands
STADIUM_HEIGHT = 400.0          # height of the top row above the field
STADIUM_SEGMENTS = 96           # around the bowl
STADIUM_TIERS = 3               # rows of stands, each a ring of quads
GROUND_Y = -SPHERE_RADIUS       # the sphere rests on the field
GROUND_HALF_SIZE = 2100.0       # the field square reaches under the stands


def sphere(dense_triangles):
    """A UV sphere with `stacks` rings and 2 * stacks slices: 2 * slices * (stacks - 1) triangles
    (fans at the poles, quads between). Returns (vertices, normals, faces) with 0-based indices."""
    stacks = max(3, round(math.sqrt(dense_triangles / 4.0)))
    slices = 2 * stacks
    verts = [(0.0, SPHERE_RADIUS, 0.0)]
    for i in range(1, stacks):
        theta = math.pi * i / stacks
        for j in range(slices):
            phi = 2.0 * math.pi * j / slices
            verts.append((SPHERE_RADIUS * math.sin(theta) * math.cos(phi),
                          SPHERE_RADIUS * math.cos(theta),
                          -SPHERE_RADIUS * math.sin(theta) * math.sin(phi)))
    verts.append((0.0, -SPHERE_RADIUS, 0.0))
    south = len(verts) - 1

    def ring(i, j):  # vertex index of ring i (1 .. stacks - 1), slice j
        return 1 + (i - 1) * slices + (j % slices)

    faces = []
    for j in range(slices):  # counter-clockwise seen from outside
        faces.append((0, ring(1, j), ring(1, j + 1)))
    for i in range(1, stacks - 1):
        for j in range(slices):
            a, b = ring(i, j), ring(i, j + 1)
            c, d = ring(i + 1, j), ring(i + 1, j + 1)
            faces.append((a, c, d))
            faces.append((a, d, b))
    for j in range(slices):
        faces.append((south, ring(stacks - 1, j + 1), ring(stacks - 1, j)))
    normals = [tuple(x / SPHERE_RADIUS for x in v) for v in verts]
    return verts, normals, faces


def stadium():
    """The stands: STADIUM_TIERS rings of quads rising from the inner to the outer radius, facing
    the centre, plus a back wall. Returns (vertices, faces)."""
    verts, faces = [], []
    rows = STADIUM_TIERS + 2  # tier boundaries, plus the foot of the back wall
    for k in range(rows):
        if k <= STADIUM_TIERS:
            t = k / STADIUM_TIERS
            radius = STADIUM_INNER_RADIUS + t * (STADIUM_OUTER_RADIUS - STADIUM_INNER_RADIUS)
            height = GROUND_Y + t * t * STADIUM_HEIGHT  # steeper towards the top
        else:
            radius, height = STADIUM_OUTER_RADIUS, GROUND_Y
        for j in range(STADIUM_SEGMENTS):
            phi = 2.0 * math.pi * j / STADIUM_SEGMENTS
            verts.append((radius * math.cos(phi), height, radius * math.sin(phi)))
    for k in range(rows - 1):
        for j in range(STADIUM_SEGMENTS):
            a = k * STADIUM_SEGMENTS + j
            b = k * STADIUM_SEGMENTS + (j + 1) % STADIUM_SEGMENTS
            c, d = a + STADIUM_SEGMENTS, b + STADIUM_SEGMENTS
            faces.append((a, c, d))
            faces.append((a, d, b))
    return verts, faces


def ground():
    h = GROUND_HALF_SIZE
    verts = [(-h, GROUND_Y, -h), (-h, GROUND_Y, h), (h, GROUND_Y, h), (h, GROUND_Y, -h)]
    return verts, [(0, 1, 2), (0, 2, 3)]


def fmt(x):
    return "%.7g" % x


def write_obj(path, dense, stands, field):
    """One OBJ with three groups; the sphere carries its smooth normals, the rest gets geometric
    normals from the loader."""
    sv, sn, sf = dense
    tv, tf = stands
    gv, gf = field
    with open(path, "w", newline="\n") as f:
        f.write("# Teapot in a stadium, written by tools/teapot_stadium.py\n")
        f.write("mtllib stadium.mtl\n")
        for v in sv + tv + gv:
            f.write("v %s %s %s\n" % tuple(fmt(x) for x in v))
        for n in sn:
            f.write("vn %s %s %s\n" % tuple(fmt(x) for x in n))
        f.write("g dense\nusemtl dense\n")
        for a, b, c in sf:
            f.write("f %d//%d %d//%d %d//%d\n" % (a + 1, a + 1, b + 1, b + 1, c + 1, c + 1))
        base = len(sv)
        f.write("g stands\nusemtl stands\n")
        for a, b, c in tf:
            f.write("f %d %d %d\n" % (a + base + 1, b + base + 1, c + base + 1))
        base += len(tv)
        f.write("g ground\nusemtl ground\n")
        for a, b, c in gf:
            f.write("f %d %d %d\n" % (a + base + 1, b + base + 1, c + base + 1))


MTL = """# Materials of the teapot-in-a-stadium scene
newmtl dense
Kd 0.8 0.25 0.1
Ks 0 0 0
illum 2

newmtl stands
Kd 0.55 0.55 0.6
illum 2

newmtl ground
Kd 0.2 0.5 0.2
illum 2
"""

SCENE_CFG = """# Teapot in a stadium (tools/teapot_stadium.py): a dense sphere of {dense} triangles, radius 1,
# inside stands of radius {outer:g} ({sparse} large triangles). The camera is close to the sphere,
# so most primary rays hit it; a uniform grid has nearly all triangles in a few cells.
geometry    stadium.obj
resolution  256 256
samples     1
max-depth   2
accel       auto
output      stadium.png
environment 0.05 0.06 0.09
light ambient     0.02 0.02 0.02
light directional -0.4 -1 -0.3   3 3 3
light point       2 3 2          20 20 20
camera eye 0 0.6 2.0  look 0 0 0  up 0 1 0  fov 50
"""


def main(argv):
    parser = argparse.ArgumentParser(description="Write the teapot-in-a-stadium scene.")
    parser.add_argument("out_dir", help="folder for stadium.obj, stadium.mtl and scene.cfg")
    parser.add_argument("--dense-triangles", type=int, default=20000,
                        help="approximate triangle count of the dense sphere (default 20000)")
    args = parser.parse_args(argv)
    if args.dense_triangles < 8 or args.dense_triangles > 20_000_000:
        parser.error("--dense-triangles must be from 8 to 20000000")
    os.makedirs(args.out_dir, exist_ok=True)
    dense, stands, field = sphere(args.dense_triangles), stadium(), ground()
    write_obj(os.path.join(args.out_dir, "stadium.obj"), dense, stands, field)
    with open(os.path.join(args.out_dir, "stadium.mtl"), "w", newline="\n") as f:
        f.write(MTL)
    sparse = len(stands[1]) + len(field[1])
    with open(os.path.join(args.out_dir, "scene.cfg"), "w", newline="\n") as f:
        f.write(SCENE_CFG.format(dense=len(dense[2]), outer=STADIUM_OUTER_RADIUS, sparse=sparse))
    print("%s: %d triangles (dense sphere %d, stands %d, ground %d)"
          % (args.out_dir, len(dense[2]) + sparse, len(dense[2]), len(stands[1]), len(field[1])))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
