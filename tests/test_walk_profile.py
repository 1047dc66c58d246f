#!/usr/bin/env python3
"""test_walk_profile.py: research/yardsticks/walk_profile.c walks the rays vkrt bench traces the way the GPU
kernel walks them (research/journal.md, "Third pass"). Its counts are held to the kernel's own:
`vkrt bench --stats` on the same scene, size and tree, walked as it models (the pairs, in one
loop: `--bvh-width 2 --walk one-loop`, which lavapipe, the device in tests, does not default to),
nodes and triangles per ray for primary, shadow and diffuse rays, and the hits and blocked shadow rays. The two test
triangles differently (Moller-Trumbore in double against the watertight test in float), so a ray
through an edge may go either way: a few rays' worth of difference is allowed, no more.
    usage: test_walk_profile.py VKRT WALK_PROFILE SCENE.cfg
"""
import json
import os
import re
import subprocess
import sys
import tempfile

WIDTH, HEIGHT, LEAF, COST = 96, 64, 8, 1  # lavapipe's tree (bvh.h's defaults)
KINDS = ("primary", "shadow", "diffuse")


def main():
    vkrt, walk_profile, scene = sys.argv[1:4]
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "stats.json")
        subprocess.run([vkrt, "bench", scene, "--accel", "bvh", "--stats", "--width", str(WIDTH),
                        "--height", str(HEIGHT), "--bvh-leaf", str(LEAF), "--bvh-cost", str(COST),
                        "--bvh-width", "2", "--walk", "one-loop", "--json", out],
                       check=True, stdout=subprocess.DEVNULL)
        gpu = json.load(open(out, encoding="utf-8"))["results"][0]
    text = subprocess.run([walk_profile, scene, str(WIDTH), str(HEIGHT), str(LEAF), str(COST)],
                          check=True, capture_output=True, text=True).stdout
    failures = 0
    for kind in KINDS:
        m = re.search(kind + r": (\d+) rays, ([\d.]+) nodes, ([\d.]+) triangles", text)
        if not m:
            print(f"FAIL: no {kind} line in walk-profile's output:\n{text}")
            return 1
        rays, nodes, triangles = int(m.group(1)), float(m.group(2)), float(m.group(3))
        # Printed to 0.1: half a step of rounding, and 1% for rays through edges.
        for what, mine, theirs in (("nodes", nodes, gpu[f"{kind}_nodes_per_ray"]),
                                   ("triangles", triangles, gpu[f"{kind}_triangles_per_ray"])):
            ok = abs(mine - theirs) <= 0.05 + 0.01 * theirs
            print(f"{'ok' if ok else 'FAIL'}: {kind} {what} per ray, walk-profile {mine} "
                  f"against the kernel's {theirs}")
            failures += not ok
        if kind == "shadow" and rays != gpu["hits"]:
            print(f"FAIL: {rays} shadow rays, one per primary hit, but the kernel hit {gpu['hits']}")
            failures += 1
    for what in ("hits", "blocked"):
        mine = int(re.search(r"  " + what + r" (\d+)", text).group(1))
        ok = abs(mine - gpu[what]) <= 2
        print(f"{'ok' if ok else 'FAIL'}: {what}, walk-profile {mine} against the kernel's {gpu[what]}")
        failures += not ok
    if gpu["hits"] == 0 or gpu["blocked"] == 0:
        print("FAIL: the scene must have hits and blocked shadow rays for this to test anything")
        failures += 1
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
