#!/usr/bin/env python3
"""textured_gltf: writes a textured glTF for start-up measurements (issue 35: "start-up of a
1-million-triangle glTF with 50 textures"). The output is made where it is needed, never
committed. Plain Python (zlib and struct write the PNGs), no dependencies; deterministic: the same
arguments give the same bytes.

    tools/textured_gltf.py OUT_DIR [--triangles N] [--materials M] [--texture-size S] [--embed]
                           [--jobs J]

The scene is M height-field patches (default 50) on a grid in the x-z plane, each of about N / M
triangles (default N = 1,000,000: 20,000 a patch, a 100 x 100 grid of quads) with its own
positions, normals, texture coordinates and indices, and its own material whose base colour is
its own S x S texture (default 1024 x 1024 RGB PNG: a checkerboard of two colours of the patch's
hue, darkening down the image, with 4 bits of seeded noise in every channel, so that it
compresses about as a photograph does, near half its raw size). One perspective camera looks down
on the grid; no lights (the default sky lights it).

By default OUT_DIR/textured.gltf and textured.bin hold the scene and the PNGs lie beside them
(texture-00.png ...); --embed writes one OUT_DIR/textured.glb with the images inside (bufferViews
with mimeType image/png). OUT_DIR/textured.json says what was written: counts, sizes in bytes,
the command. --jobs J encodes the PNGs on J processes (default: every core); the bytes do not
depend on it."""
import argparse
import colorsys
import json
import math
import os
import random
import struct
import sys
import zlib
from array import array
from concurrent.futures import ProcessPoolExecutor

BLOCK = 64       # checkerboard squares, in texels
NOISE_BITS = 4   # seeded noise added to every channel


def png_chunk(kind, data):
    return (struct.pack(">I", len(data)) + kind + data +
            struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))


def texture_png(index, size):
    """The PNG file bytes of texture `index`: RGB, 8 bits, every row filter 0 (none)."""
    hue = index / 50.0 % 1.0
    light = [round(255 * c * 0.85) for c in colorsys.hsv_to_rgb(hue, 0.55, 0.95)]
    dark = [round(255 * c * 0.85) for c in colorsys.hsv_to_rgb((hue + 0.08) % 1.0, 0.8, 0.45)]
    top = 255 - (1 << NOISE_BITS) + 1  # pattern + noise stays within a byte: no carries
    rows = []
    for y in range(size):
        shade = 1.0 - 0.4 * y / max(1, size - 1)
        a = bytes(min(top, round(c * shade)) for c in light) * BLOCK
        b = bytes(min(top, round(c * shade)) for c in dark) * BLOCK
        pair = (a + b) if (y // BLOCK) % 2 == 0 else (b + a)
        rows.append((pair * (size // (2 * BLOCK) + 1))[:3 * size])
    pattern = b"".join(rows)
    noise = random.Random(1000 + index).randbytes(len(pattern))
    noise = noise.translate(bytes(v & ((1 << NOISE_BITS) - 1) for v in range(256)))
    # Byte-wise sum without carries, as one big-integer addition.
    pixels = (int.from_bytes(pattern, "little") + int.from_bytes(noise, "little")).to_bytes(
        len(pattern), "little")
    stride = 3 * size
    raw = b"".join(b"\0" + pixels[y * stride:(y + 1) * stride] for y in range(size))
    ihdr = struct.pack(">IIBBBBB", size, size, 8, 2, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + png_chunk(b"IHDR", ihdr) +
            png_chunk(b"IDAT", zlib.compress(raw, 6)) + png_chunk(b"IEND", b""))


def patch(index, side, origin):
    """Patch `index`: a side x side grid of quads over a unit square at origin (x, z), its
    heights a few seeded waves. Returns positions, normals, uvs (float arrays) and indices."""
    rng = random.Random(index)
    waves = [(rng.uniform(2, 9), rng.uniform(2, 9), rng.uniform(0, 6.3), rng.uniform(0.01, 0.04))
             for _ in range(3)]
    pos, nrm, uv = array("f"), array("f"), array("f")
    for j in range(side + 1):
        v = j / side
        for i in range(side + 1):
            u = i / side
            h = dx = dz = 0.0
            for fx, fz, phase, amp in waves:
                s = fx * u + fz * v + phase
                h += amp * math.sin(s)
                dx += amp * fx * math.cos(s)
                dz += amp * fz * math.cos(s)
            length = math.sqrt(dx * dx + 1 + dz * dz)
            pos.extend((origin[0] + u, h, origin[1] + v))
            nrm.extend((-dx / length, 1 / length, -dz / length))
            uv.extend((u, v))
    idx = array("I")
    row = side + 1
    for j in range(side):
        for i in range(side):
            a = j * row + i
            idx.extend((a, a + row, a + 1, a + 1, a + row, a + row + 1))
    return pos, nrm, uv, idx


def pad4(data, fill=b"\0"):
    return data + fill * (-len(data) % 4)


def build(a):
    """The glTF document, its binary buffer (geometry, then the images when embedded) and the
    external image files {name: bytes}."""
    count = a.materials
    side = max(1, round(math.sqrt(a.triangles / count / 2)))
    columns = math.ceil(math.sqrt(2 * count))
    rows_of_patches = math.ceil(count / columns)
    spacing = 1.1
    with ProcessPoolExecutor(max_workers=a.jobs) as pool:
        pngs = list(pool.map(texture_png, range(count), [a.texture_size] * count))
    blob = bytearray()
    views, accessors, meshes, materials, textures, images, nodes = [], [], [], [], [], [], []

    def view(data, target=None):
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data)})
        if target:
            views[-1]["target"] = target
        blob.extend(pad4(data))
        return len(views) - 1

    for k in range(count):
        origin = ((k % columns - columns / 2) * spacing, (k // columns - rows_of_patches / 2) * spacing)
        pos, nrm, uv, idx = patch(k, side, origin)
        first = len(accessors)
        n = len(pos) // 3
        xs, ys, zs = pos[0::3], pos[1::3], pos[2::3]
        accessors += [
            {"bufferView": view(pos.tobytes(), 34962), "componentType": 5126, "count": n,
             "type": "VEC3", "min": [min(xs), min(ys), min(zs)], "max": [max(xs), max(ys), max(zs)]},
            {"bufferView": view(nrm.tobytes(), 34962), "componentType": 5126, "count": n,
             "type": "VEC3"},
            {"bufferView": view(uv.tobytes(), 34962), "componentType": 5126, "count": n,
             "type": "VEC2"},
            {"bufferView": view(idx.tobytes(), 34963), "componentType": 5125, "count": len(idx),
             "type": "SCALAR"},
        ]
        meshes.append({"name": "patch-%02d" % k, "primitives": [{
            "attributes": {"POSITION": first, "NORMAL": first + 1, "TEXCOORD_0": first + 2},
            "indices": first + 3, "material": k}]})
        materials.append({"name": "material-%02d" % k, "pbrMetallicRoughness": {
            "baseColorTexture": {"index": k}, "metallicFactor": 0.0, "roughnessFactor": 0.7}})
        textures.append({"source": k, "sampler": 0})
        nodes.append({"mesh": k})
    files = {}
    for k, png in enumerate(pngs):
        if a.embed:
            images.append({"bufferView": view(png), "mimeType": "image/png"})
        else:
            name = "texture-%02d.png" % k
            files[name] = png
            images.append({"uri": name})
    depth = rows_of_patches * spacing
    height, back = 0.9 * depth + 2, 0.9 * depth + 3
    pitch = math.atan2(height, back)
    nodes.append({"camera": 0, "translation": [0, height, back],
                  "rotation": [-math.sin(pitch / 2), 0, 0, math.cos(pitch / 2)]})
    doc = {
        "asset": {"version": "2.0", "generator": "vkrt tools/textured_gltf.py"},
        "scene": 0,
        "scenes": [{"nodes": list(range(len(nodes)))}],
        "nodes": nodes,
        "cameras": [{"type": "perspective",
                     "perspective": {"yfov": 0.75, "znear": 0.1, "aspectRatio": 16 / 9}}],
        "meshes": meshes,
        "materials": materials,
        "textures": textures,
        "samplers": [{"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497}],
        "images": images,
        "buffers": [{"byteLength": len(blob)}],
        "bufferViews": views,
        "accessors": accessors,
    }
    return doc, bytes(blob), files, 2 * side * side * count


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("out_dir")
    p.add_argument("--triangles", type=int, default=1_000_000)
    p.add_argument("--materials", type=int, default=50)
    p.add_argument("--texture-size", type=int, default=1024)
    p.add_argument("--embed", action="store_true", help="one .glb with the images inside")
    p.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    a = p.parse_args()
    if a.materials < 1 or a.triangles < 2 * a.materials or not 1 <= a.texture_size <= 16384:
        sys.exit("textured_gltf: at least 2 triangles a material, textures 1 to 16384 texels")
    os.makedirs(a.out_dir, exist_ok=True)
    doc, blob, files, triangles = build(a)
    written = {}
    if a.embed:
        text = pad4(json.dumps(doc, separators=(",", ":")).encode(), b" ")
        body = pad4(blob)
        glb = (struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(text) + 8 + len(body)) +
               struct.pack("<II", len(text), 0x4E4F534A) + text +
               struct.pack("<II", len(body), 0x004E4942) + body)
        written["textured.glb"] = glb
    else:
        doc["buffers"][0]["uri"] = "textured.bin"
        written["textured.bin"] = blob
        written["textured.gltf"] = json.dumps(doc, separators=(",", ":")).encode()
        written.update(files)
    for name, data in written.items():
        with open(os.path.join(a.out_dir, name), "wb") as f:
            f.write(data)
    image_bytes = sum(len(v) for k, v in written.items() if k.endswith(".png")) if not a.embed \
        else sum(v["byteLength"] for v in doc["bufferViews"][-a.materials:])
    summary = {
        "command": " ".join(sys.argv),
        "triangles": triangles,
        "materials": a.materials,
        "textures": a.materials,
        "texture_size": a.texture_size,
        "image_bytes": image_bytes,
        "decoded_rgba8_bytes": 4 * a.texture_size * a.texture_size * a.materials,
        "files": {name: len(data) for name, data in written.items()},
        "total_bytes": sum(len(data) for data in written.values()),
    }
    with open(os.path.join(a.out_dir, "textured.json"), "w") as f:
        json.dump(summary, f, indent=1)
    print("textured_gltf: %d triangles, %d materials, %d textures of %dx%d: %.1f MiB of images "
          "(%.1f MiB decoded as RGBA8), %.1f MiB written to %s" % (
              triangles, a.materials, a.materials, a.texture_size, a.texture_size,
              image_bytes / 2**20, summary["decoded_rgba8_bytes"] / 2**20,
              summary["total_bytes"] / 2**20, a.out_dir))


if __name__ == "__main__":
    main()
