#!/usr/bin/env python3
"""Compares the kernels two vkrt builds compiled for one scene, after specialization: did a
change that a specialization constant is meant to compile away (a material feature the scene
does not use) leave the scene's kernels as they were?

    VKRT_CACHE_DIR=/tmp/a OLD/vkrt render SCENE.cfg --width 32 --height 32 --spp 1
    VKRT_CACHE_DIR=/tmp/b NEW/vkrt render SCENE.cfg --width 32 --height 32 --spp 1
    research/spirv_specialized.py /tmp/a /tmp/b --spec 14:16

Reads the kernels of each kernel cache (src/gpu/spirv_cache.c's files: a 32-byte header whose
last 8 bytes are the word count, the SPIR-V, a hash), and for each: its SPIR-V without debug
information, and the same specialized (spirv-opt --set-spec-const-default-value for each --spec
ID:VALUE, --freeze-spec-const, --fold-spec-const-op-composite, -O, --strip-debug), which is
what is left once the driver has the constants. Kernels of equal stripped SPIR-V are paired and
reported equal; for the others (paired by size order), the count of each opcode after
specialization in A and B, where they differ: instructions of arithmetic or control flow there
mean code that specialization did not remove. The cache keys hash the kernels' text, comments
included, so keys differ between any two builds; contents are what is compared."""
import argparse
import collections
import glob
import hashlib
import os
import re
import struct
import subprocess
import sys
import tempfile


def kernels(cache):
    """{name: SPIR-V bytes} of the .spv files of a kernel cache."""
    out = {}
    for path in sorted(glob.glob(os.path.join(cache, "*.spv"))):
        data = open(path, "rb").read()
        words = struct.unpack("<Q", data[24:32])[0]
        out[os.path.basename(path)] = data[32:32 + 4 * words]
    return out


def run(args, spirv, work):
    src, dst = os.path.join(work, "in.spv"), os.path.join(work, "out.spv")
    with open(src, "wb") as f:
        f.write(spirv)
    subprocess.run(["spirv-opt", *args, src, "-o", dst], check=True)
    return open(dst, "rb").read()


def opcodes(spirv, work):
    path = os.path.join(work, "dis.spv")
    with open(path, "wb") as f:
        f.write(spirv)
    text = subprocess.run(["spirv-dis", "--raw-id", path], check=True, capture_output=True,
                          text=True).stdout
    return collections.Counter(re.findall(r"\bOp[A-Za-z0-9]+", text))


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("a")
    p.add_argument("b")
    p.add_argument("--spec", action="append", default=[],
                   help="ID:VALUE of a specialization constant, as the renderer sets it")
    args = p.parse_args()
    spec = [x for s in args.spec for x in ("--set-spec-const-default-value", s)]
    specialize = spec + ["--freeze-spec-const", "--fold-spec-const-op-composite", "-O",
                         "--strip-debug"]
    with tempfile.TemporaryDirectory() as work:
        sides = []
        for cache in (args.a, args.b):
            k = kernels(cache)
            sides.append({name: (run(["--strip-debug"], s, work), s) for name, s in k.items()})
        digest = lambda b: hashlib.md5(b).hexdigest()
        left = {digest(v[0]): n for n, v in sides[0].items()}
        right = {digest(v[0]): n for n, v in sides[1].items()}
        for d in sorted(set(left) & set(right), key=lambda d: len(sides[0][left[d]][0])):
            print(f"equal   {len(sides[0][left[d]][0]) // 4:6d} words  {left[d]}  {right[d]}")
        rest = [sorted((n for d, n in side.items() if d not in other),
                       key=lambda n: len(s[n][0]))
                for side, other, s in ((left, right, sides[0]), (right, left, sides[1]))]
        for na, nb in zip(*rest):
            sa, sb = (run(specialize, s[n][1], work) for s, n in ((sides[0], na), (sides[1], nb)))
            oa, ob = opcodes(sa, work), opcodes(sb, work)
            same = "equal after specialization" if sa == sb else "differ after specialization"
            print(f"differ  {len(sides[0][na][0]) // 4:6d} / {len(sides[1][nb][0]) // 4} words  "
                  f"{na}  {nb}: {same}")
            for op in sorted(set(oa) | set(ob)):
                if oa[op] != ob[op]:
                    print(f"        {op:28s} {oa[op]:7d} {ob[op]:7d} {ob[op] - oa[op]:+d}")
        if len(rest[0]) != len(rest[1]):
            print(f"unpaired: {rest[0][len(rest[1]):]} {rest[1][len(rest[0]):]}", file=sys.stderr)


if __name__ == "__main__":
    main()
