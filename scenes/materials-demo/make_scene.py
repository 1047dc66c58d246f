#!/usr/bin/env python3
"""Writes materials-demo.obj and materials-demo.mtl for the material-shader demo scene.

The scene, in metres, y up:
  - a floor (y = 0) and a back wall (z = -3, 2.5 m high, sky above it), each one quad
  - a gold sphere (left), a striped rim-lit sphere (right, the user shader stripes.glsl),
    a glass cube (front, built-in @glass) and a red cube (back, built-in @diffuse)

The spheres are UV spheres with per-vertex normals (`vn`) and texture coordinates (`vt`).
All faces are wound counter-clockwise seen from outside. The .mtl gives every material a
plain fallback, used only when scene.cfg does not name demo.mat.

Run from anywhere: python3 make_scene.py   (writes next to this script)
"""

import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))


class Obj:
    """Collects vertices, normals, uvs and faces with OBJ's 1-based indices."""

    def __init__(self):
        self.lines = []
        self.nv = self.nvt = self.nvn = 0
        self.triangles = 0

    def comment(self, text):
        self.lines.append(f"# {text}")

    def usemtl(self, name):
        self.lines.append(f"usemtl {name}")

    def v(self, p):
        self.lines.append("v %.6f %.6f %.6f" % p)
        self.nv += 1
        return self.nv

    def vt(self, uv):
        self.lines.append("vt %.6f %.6f" % uv)
        self.nvt += 1
        return self.nvt

    def vn(self, n):
        self.lines.append("vn %.6f %.6f %.6f" % n)
        self.nvn += 1
        return self.nvn

    def face(self, corners):
        """corners: list of (v, vt, vn) index triples (vt or vn may be None)."""
        parts = []
        for v, t, n in corners:
            if t is None and n is None:
                parts.append(f"{v}")
            elif n is None:
                parts.append(f"{v}/{t}")
            elif t is None:
                parts.append(f"{v}//{n}")
            else:
                parts.append(f"{v}/{t}/{n}")
        self.lines.append("f " + " ".join(parts))
        self.triangles += len(corners) - 2


def quad(obj, p0, p1, p2, p3, normal, uv_scale=1.0):
    """A quad p0 p1 p2 p3 (counter-clockwise seen from the side `normal` points to)."""
    n = obj.vn(normal)
    uvs = [(0, 0), (uv_scale, 0), (uv_scale, uv_scale), (0, uv_scale)]
    corners = []
    for p, uv in zip((p0, p1, p2, p3), uvs):
        corners.append((obj.v(p), obj.vt(uv), n))
    obj.face(corners[:3])
    obj.face([corners[0], corners[2], corners[3]])


def sphere(obj, centre, radius, slices=32, stacks=16):
    """UV sphere: `slices` around y, `stacks` from pole to pole, smooth normals."""
    cx, cy, cz = centre
    index = {}
    for i in range(stacks + 1):
        theta = math.pi * i / stacks            # 0 at the top pole, pi at the bottom
        for j in range(slices + 1):
            phi = 2.0 * math.pi * j / slices
            n = (math.sin(theta) * math.cos(phi), math.cos(theta), -math.sin(theta) * math.sin(phi))
            p = (cx + radius * n[0], cy + radius * n[1], cz + radius * n[2])
            index[i, j] = (obj.v(p), obj.vt((j / slices, 1.0 - i / stacks)), obj.vn(n))
    for i in range(stacks):
        for j in range(slices):
            a, b = index[i, j], index[i + 1, j]
            c, d = index[i + 1, j + 1], index[i, j + 1]
            # a (top left), b (below), c (below right), d (right): counter-clockwise from outside
            if i != 0:
                obj.face([a, b, d])
            if i != stacks - 1:
                obj.face([b, c, d])


def cube(obj, centre, half, angle_deg=0.0):
    """Axis-aligned cube (rotated about y by angle_deg), flat normals per face."""
    cx, cy, cz = centre
    ca, sa = math.cos(math.radians(angle_deg)), math.sin(math.radians(angle_deg))

    def rot(x, y, z):
        return (ca * x + sa * z, y, -sa * x + ca * z)

    # each face: outward normal, and two in-plane axes u, v with u x v = normal
    faces = [
        ((1, 0, 0), (0, 0, -1), (0, 1, 0)),
        ((-1, 0, 0), (0, 0, 1), (0, 1, 0)),
        ((0, 1, 0), (1, 0, 0), (0, 0, -1)),
        ((0, -1, 0), (1, 0, 0), (0, 0, 1)),
        ((0, 0, 1), (1, 0, 0), (0, 1, 0)),
        ((0, 0, -1), (-1, 0, 0), (0, 1, 0)),
    ]
    for n, u, v in faces:
        pts = []
        for su, sv in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
            local = [half * (n[k] + su * u[k] + sv * v[k]) for k in range(3)]
            x, y, z = rot(*local)
            pts.append((cx + x, cy + y, cz + z))
        quad(obj, *pts, normal=rot(*n))


def main():
    obj = Obj()
    obj.lines.append("# Materials demo scene; made by make_scene.py. Metres, y up.")
    obj.lines.append("mtllib materials-demo.mtl")

    obj.comment("floor, y = 0")
    obj.usemtl("floor")
    quad(obj, (-4, 0, 3), (4, 0, 3), (4, 0, -3), (-4, 0, -3), (0, 1, 0), uv_scale=4)

    obj.comment("back wall, z = -3")
    obj.usemtl("wall")
    quad(obj, (-4, 0, -3), (4, 0, -3), (4, 2.5, -3), (-4, 2.5, -3), (0, 0, 1), uv_scale=4)

    obj.comment("gold sphere, left")
    obj.usemtl("gold")
    sphere(obj, (-1.3, 0.7, -0.6), 0.7)

    obj.comment("striped rim-lit sphere, right")
    obj.usemtl("stripes")
    sphere(obj, (1.3, 0.7, -0.6), 0.7)

    obj.comment("glass cube, front centre")
    obj.usemtl("glass")
    cube(obj, (0.0, 0.352, 0.9), 0.35, angle_deg=30)  # just above the floor: no coplanar faces

    obj.comment("red cube, back centre")
    obj.usemtl("red")
    cube(obj, (0.0, 0.452, -1.9), 0.45, angle_deg=-20)

    with open(os.path.join(HERE, "materials-demo.obj"), "w") as f:
        f.write("\n".join(obj.lines) + "\n")

    # Fallback .mtl: what the OBJ looks like without demo.mat (e.g. in another renderer).
    mtl = """# Fallback materials for materials-demo.obj; demo.mat overrides every one of them.
newmtl floor
Kd 0.7 0.7 0.7
newmtl wall
Kd 0.6 0.65 0.7
newmtl gold
Kd 0 0 0
Ks 1.0 0.78 0.34
illum 3
newmtl stripes
Kd 0.2 0.4 0.8
newmtl glass
Kd 0 0 0
Ks 1 1 1
Ni 1.5
illum 7
newmtl red
Kd 0.7 0.1 0.08
"""
    with open(os.path.join(HERE, "materials-demo.mtl"), "w") as f:
        f.write(mtl)
    print(f"materials-demo.obj: {obj.nv} vertices, {obj.triangles} triangles")


if __name__ == "__main__":
    main()
