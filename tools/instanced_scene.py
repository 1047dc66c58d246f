#!/usr/bin/env python3
"""instanced_scene: writes an instanced test scene, N copies of one M-triangle mesh, for the
two-level BVH's benchmarks (issue 35: 10,000 instances of a 100,000-triangle mesh). The output is
made where it is needed, never committed. Plain Python, no dependencies.

    tools/instanced_scene.py OUT_DIR --instances N --triangles M [--seed S] [--format gltf|cfg]

The mesh is a sphere of latitude-longitude bands (M rounded to the nearest count it can make,
printed), indexed, with smooth normals. The instances stand on a square grid in the x-z plane,
each turned about y, tilted and scaled by a seeded random amount (a few of them mirrored), so the
top level is not a regular lattice.

--format gltf (the default) writes OUT_DIR/instanced.gltf and instanced.bin: standard glTF 2.0,
one mesh, one node per instance (translation, rotation quaternion, scale), a perspective camera
framing the grid. --format cfg writes OUT_DIR/mesh.obj and a scene.cfg with one
`geometry mesh.obj translate X Y Z rotate y DEG scale S` line per instance, a camera, a sun and a
sky. Either way OUT_DIR/instanced.json says what was written (the counts and the command)."""
import argparse
import json
import math
import os
import random
import struct
import sys


def sphere(triangles):
    """A unit sphere of `rings` bands of `segments` quads (the poles' bands are triangles): its
    positions, normals (the same) and triangle indices, about `triangles` triangles."""
    # triangles = 2 * segments * (rings - 1), with segments = 2 * rings
    rings = max(2, round(math.sqrt(triangles / 4.0)))
    segments = 2 * rings
    positions = []
    for r in range(rings + 1):
        theta = math.pi * r / rings
        for s in range(segments):
            phi = 2 * math.pi * s / segments
            positions.append((math.sin(theta) * math.cos(phi), math.cos(theta),
                              math.sin(theta) * math.sin(phi)))
    indices = []
    for r in range(rings):
        for s in range(segments):
            a = r * segments + s
            b = r * segments + (s + 1) % segments
            c = a + segments
            d = b + segments
            if r != 0:
                indices.append((a, b, c))
            if r != rings - 1:
                indices.append((b, d, c))
    return positions, indices


def placements(count, seed):
    """Per instance: translation, yaw (degrees), tilt about x (degrees), scale (x, y, z)."""
    rng = random.Random(seed)
    side = math.ceil(math.sqrt(count))
    spacing = 3.0
    out = []
    for i in range(count):
        x = (i % side - (side - 1) / 2) * spacing + rng.uniform(-0.5, 0.5)
        z = (i // side - (side - 1) / 2) * spacing + rng.uniform(-0.5, 0.5)
        s = rng.uniform(0.6, 1.2)
        scale = (s * rng.uniform(0.8, 1.25), s, s * rng.uniform(0.8, 1.25))
        if i % 17 == 5:
            scale = (-scale[0], scale[1], scale[2])  # mirrored
        out.append(((x, s, z), rng.uniform(0, 360), rng.uniform(-20, 20), scale))
    return out, side * spacing


def quaternion(yaw, tilt):
    """The rotation yaw about y after tilt about x, as glTF's (x, y, z, w)."""
    cy, sy = math.cos(math.radians(yaw) / 2), math.sin(math.radians(yaw) / 2)
    cx, sx = math.cos(math.radians(tilt) / 2), math.sin(math.radians(tilt) / 2)
    # q = qy * qx
    return (cy * sx, sy * cx, -sy * sx, cy * cx)


def write_gltf(out_dir, positions, indices, places, extent):
    pos = b"".join(struct.pack("<3f", *p) for p in positions)
    idx = b"".join(struct.pack("<3I", *t) for t in indices)
    with open(os.path.join(out_dir, "instanced.bin"), "wb") as f:
        f.write(pos)   # positions, then the same bytes again as normals (a unit sphere)
        f.write(idx)
    n = len(positions)
    nodes = [{"mesh": 0, "translation": list(t), "rotation": list(quaternion(yaw, tilt)),
              "scale": list(s)} for t, yaw, tilt, s in places]
    height = 0.6 * extent
    pitch = math.atan2(height, extent)
    nodes.append({"camera": 0, "translation": [0, height, extent],
                  "rotation": [-math.sin(pitch / 2), 0, 0, math.cos(pitch / 2)]})
    doc = {
        "asset": {"version": "2.0", "generator": "vkrt tools/instanced_scene.py"},
        "scene": 0,
        "scenes": [{"nodes": list(range(len(nodes)))}],
        "nodes": nodes,
        "cameras": [{"type": "perspective",
                     "perspective": {"yfov": 0.8, "znear": 0.1, "aspectRatio": 1.5}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2,
                                    "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.6, 0.5, 1],
                                                "metallicFactor": 0, "roughnessFactor": 0.8}}],
        "buffers": [{"uri": "instanced.bin", "byteLength": len(pos) + len(idx)}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": len(pos), "target": 34962},
                        {"buffer": 0, "byteOffset": len(pos), "byteLength": len(idx),
                         "target": 34963}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": n, "type": "VEC3",
             "min": [-1, -1, -1], "max": [1, 1, 1]},
            {"bufferView": 0, "componentType": 5126, "count": n, "type": "VEC3"},
            {"bufferView": 1, "componentType": 5125, "count": 3 * len(indices),
             "type": "SCALAR"},
        ],
    }
    with open(os.path.join(out_dir, "instanced.gltf"), "w") as f:
        json.dump(doc, f, separators=(",", ":"))
    return ["instanced.gltf", "instanced.bin"]


def write_cfg(out_dir, positions, indices, places, extent):
    with open(os.path.join(out_dir, "mesh.obj"), "w") as f:
        f.write("".join("v %.6f %.6f %.6f\nvn %.6f %.6f %.6f\n" % (p + p) for p in positions))
        f.write("".join("f %d//%d %d//%d %d//%d\n" % (a + 1, a + 1, b + 1, b + 1, c + 1, c + 1)
                        for a, b, c in indices))
    lines = ["# %d instances of mesh.obj (tools/instanced_scene.py)" % len(places),
             "resolution 1920 1080", "environment 0.6 0.7 0.9",
             "light directional -0.4 -1 -0.3 2 2 2",
             "camera eye 0 %.3f %.3f look 0 0 0 up 0 1 0 fov 45" % (0.6 * extent, extent)]
    # scene.cfg's placement turns about one axis: the yaw alone (the tilt is glTF's only), and
    # one scale (the mean of the three, mirrored instances keep their sign on it).
    for t, yaw, _tilt, s in places:
        mean = (abs(s[0]) + abs(s[1]) + abs(s[2])) / 3 * (-1 if s[0] < 0 else 1)
        lines.append("geometry mesh.obj translate %.4f %.4f %.4f rotate y %.3f scale %.4f"
                     % (t + (yaw, mean)))
    with open(os.path.join(out_dir, "scene.cfg"), "w") as f:
        f.write("\n".join(lines) + "\n")
    return ["mesh.obj", "scene.cfg"]


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("out_dir")
    p.add_argument("--instances", type=int, required=True)
    p.add_argument("--triangles", type=int, required=True)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--format", choices=("gltf", "cfg"), default="gltf")
    a = p.parse_args()
    if a.instances < 1 or a.triangles < 8:
        sys.exit("instanced_scene: at least 1 instance of 8 triangles")
    os.makedirs(a.out_dir, exist_ok=True)
    positions, indices = sphere(a.triangles)
    places, extent = placements(a.instances, a.seed)
    write = write_gltf if a.format == "gltf" else write_cfg
    files = write(a.out_dir, positions, indices, places, extent)
    about = {"instances": a.instances, "mesh_triangles": len(indices),
             "instanced_triangles": a.instances * len(indices), "files": files,
             "command": " ".join(sys.argv)}
    with open(os.path.join(a.out_dir, "instanced.json"), "w") as f:
        json.dump(about, f, indent=1)
    print("instanced_scene: %d instances of %d triangles (%d instanced) in %s"
          % (a.instances, len(indices), a.instances * len(indices), a.out_dir))


if __name__ == "__main__":
    main()
