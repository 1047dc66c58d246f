#!/usr/bin/env python3
"""tile_obj: makes a big test scene from a public one: an OBJ repeated on an NX x NZ grid in the
x-z plane (issue 20: ten million triangles from Lost Empire's 225k), for start-up and memory
benchmarks. The output is made where it is needed, never committed.

    tools/tile_obj.py IN.obj OUT_DIR NX NZ [--gap 0.05] [--jobs N]

Writes OUT_DIR/tiled.obj (the copies, each shifted by the model's size plus the gap, with v, vt
and vn indices made relative, so that every copy is the same text but for its vertices; mtllib
pointing at IN's .mtl files by absolute path) and OUT_DIR/scene.cfg (a camera over the whole
grid, the sun and a sky). Plain Python: the input is read once into memory, the copies made by
--jobs processes and written in order."""
import argparse
import multiprocessing
import os
import re

INDEX = re.compile(r"(-?\d+)(/(-?\d*))?(/(-?\d*))?")


def copy_template(lines, folder):
    """The file's header (mtllib, by absolute path) and one copy as a list of pieces: text that is
    the same in every copy (faces with their indices made relative, vt, vn, usemtl...) and lists
    of (x, y, z) vertex lines, which each copy shifts. Relative indices (-1: the latest vertex)
    make every copy's face lines the same text."""
    header, pieces, text, verts = [], [], [], []
    seen = {"v": 0, "vt": 0, "vn": 0}
    keys = ("v", "vt", "vn")

    def relative(m):
        out = []
        for part, key in zip((m.group(1), m.group(3), m.group(5)), keys):
            if part is None:
                break
            n = int(part) if part else 0
            out.append("" if not part else str(n - seen[key] - 1 if n > 0 else n))
        return "/".join(out)

    def flush_text():
        if text:
            pieces.append("".join(text))
            text.clear()

    def flush_verts():
        if verts:
            pieces.append(list(verts))
            verts.clear()

    for line in lines:
        w = line.split()
        if not w:
            continue
        if w[0] == "v":
            flush_text()
            verts.append((float(w[1]), w[2], float(w[3])))
            seen["v"] += 1
            continue
        flush_verts()
        if w[0] == "f":
            text.append("f " + " ".join(INDEX.sub(relative, c) for c in w[1:]) + "\n")
        elif w[0] == "mtllib":
            header.append("mtllib " + " ".join(os.path.join(folder, x) for x in w[1:]) + "\n")
        elif w[0] in ("vt", "vn", "usemtl", "g", "o", "s"):
            text.append(line + "\n")
            if w[0] in seen:
                seen[w[0]] += 1
    flush_text()
    flush_verts()
    return "".join(header), pieces


TEMPLATE = None


def set_template(pieces):
    global TEMPLATE
    TEMPLATE = pieces


def write_copy(offset):
    """One copy's text, its vertices moved by offset (dx, dz)."""
    dx, dz = offset
    out = []
    for piece in TEMPLATE:
        if isinstance(piece, str):
            out.append(piece)
        else:
            out.append("".join(f"v {x + dx:.6g} {y} {z + dz:.6g}\n" for x, y, z in piece))
    return "".join(out)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("obj")
    p.add_argument("out")
    p.add_argument("nx", type=int)
    p.add_argument("nz", type=int)
    p.add_argument("--gap", type=float, default=0.05, help="space between copies, as a share of "
                   "the model's size (default 0.05)")
    p.add_argument("--jobs", type=int, default=os.cpu_count(), help="processes writing copies "
                   "(default: one per core)")
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
    template = copy_template(lines, folder)
    faces = sum(1 for line in lines if line.startswith("f "))
    copies = [(i * step[0], j * step[2]) for i in range(a.nx) for j in range(a.nz)]
    with open(os.path.join(a.out, "tiled.obj"), "w", encoding="utf-8") as out:
        out.write(f"# {a.nx} x {a.nz} copies of {os.path.abspath(a.obj)}, by tools/tile_obj.py\n")
        out.write(template[0])
        # Copies are independent (their faces count back to their own vertices): made by
        # a.jobs processes, written in order.
        with multiprocessing.Pool(a.jobs, initializer=set_template, initargs=(template[1],)) as pool:
            for text in pool.imap(write_copy, copies, chunksize=1):
                out.write(text)
    faces *= len(copies)
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
