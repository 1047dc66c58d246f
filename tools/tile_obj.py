#!/usr/bin/env python3
"""tile_obj: makes a big test scene from a public one: an OBJ repeated on an NX x NZ grid in the
x-z plane (issue 20: ten million triangles from Lost Empire's 225k), for start-up and memory
benchmarks. The output is made where it is needed, never committed.

    tools/tile_obj.py IN.obj OUT_DIR NX NZ [--gap 0.05]

Writes OUT_DIR/tiled.obj (the copies, each shifted by the model's size plus the gap, with v, vt
and vn indices renumbered, mtllib pointing at IN's .mtl files by absolute path) and
OUT_DIR/scene.cfg (a camera over the whole grid, the sun and a sky). Plain Python, streaming: the
input is read once into memory, the output written copy by copy."""
import argparse
import os
import re

INDEX = re.compile(r"(-?\d+)(/(-?\d*))?(/(-?\d*))?")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("obj")
    p.add_argument("out")
    p.add_argument("nx", type=int)
    p.add_argument("nz", type=int)
    p.add_argument("--gap", type=float, default=0.05, help="space between copies, as a share of "
                   "the model's size (default 0.05)")
    a = p.parse_args()
    folder = os.path.dirname(os.path.abspath(a.obj))
    with open(a.obj, encoding="utf-8", errors="replace") as f:
        lines = f.read().splitlines()
    counts = {"v": 0, "vt": 0, "vn": 0}
    lo, hi = [float("inf")] * 3, [float("-inf")] * 3
    for line in lines:
        w = line.split()
        if w and w[0] in counts:
            counts[w[0]] += 1
            if w[0] == "v":
                for k in range(3):
                    x = float(w[1 + k])
                    lo[k], hi[k] = min(lo[k], x), max(hi[k], x)
    step = [(hi[k] - lo[k]) * (1 + a.gap) for k in range(3)]
    os.makedirs(a.out, exist_ok=True)
    faces = 0
    with open(os.path.join(a.out, "tiled.obj"), "w", encoding="utf-8") as out:
        out.write(f"# {a.nx} x {a.nz} copies of {os.path.abspath(a.obj)}, by tools/tile_obj.py\n")
        for i in range(a.nx):
            for j in range(a.nz):
                copy = i * a.nz + j
                dx, dz = i * step[0], j * step[2]
                base = {key: copy * n for key, n in counts.items()}

                def renumber(m):
                    """One corner v[/vt][/vn], its positive indices moved to this copy's."""
                    parts = [m.group(1), m.group(3), m.group(5)]
                    keys = ["v", "vt", "vn"]
                    outp = []
                    for part, key in zip(parts, keys):
                        if part is None:
                            break
                        if part == "":
                            outp.append("")
                            continue
                        n = int(part)
                        outp.append(str(n + base[key] if n > 0 else n))
                    return "/".join(outp)

                for line in lines:
                    w = line.split()
                    if not w:
                        continue
                    if w[0] == "v":
                        out.write(f"v {float(w[1]) + dx:.6g} {w[2]} {float(w[3]) + dz:.6g}\n")
                    elif w[0] == "f":
                        faces += 1
                        out.write("f " + " ".join(INDEX.sub(renumber, c) for c in w[1:]) + "\n")
                    elif w[0] == "mtllib":
                        if copy == 0:
                            out.write("mtllib " + " ".join(os.path.join(folder, x) for x in w[1:])
                                      + "\n")
                    elif w[0] in ("vt", "vn", "usemtl", "g", "o", "s"):
                        out.write(line + "\n")
    size = [a.nx * step[0], hi[1] - lo[1], a.nz * step[2]]
    centre = [lo[0] + size[0] / 2, lo[1], lo[2] + size[2] / 2]
    reach = max(size[0], size[2])
    with open(os.path.join(a.out, "scene.cfg"), "w", encoding="utf-8") as cfg:
        cfg.write(f"# {a.nx} x {a.nz} copies of {os.path.basename(a.obj)} "
                  f"(tools/tile_obj.py)\ngeometry tiled.obj\nresolution 1920 1080\n"
                  "output tiled.png\nenvironment 0.45 0.6 0.85\nlight ambient 0.1 0.1 0.1\n"
                  "light directional -0.4 -1 -0.3 2.5 2.4 2.2\n"
                  f"camera eye {centre[0] - 0.4 * reach:.6g} {centre[1] + 0.5 * reach:.6g} "
                  f"{centre[2] - 0.6 * reach:.6g} look {centre[0]:.6g} {centre[1]:.6g} "
                  f"{centre[2]:.6g} up 0 1 0 fov 60\n")
    print(f"tile_obj: {a.out}/tiled.obj: {a.nx * a.nz} copies, {faces} faces")


if __name__ == "__main__":
    main()
