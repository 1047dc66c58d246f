#!/usr/bin/env python3
"""kdtree_table.py DIR: the Markdown table of docs/kdtree.md's H200 section from the JSON of
`research/gpu-run kdtree-all` (DIR holds kdtree.json, kdtree-2.json, bvh.json, bvh-2.json,
grid.json and rtpipe.json): per scene and kind of ray, Mrays/s of the kd-tree (the better of its
two rounds), the BVH (likewise), the grid and the driver's pipeline, and the kd-tree's ratio to
the BVH and to the driver."""
import json
import os
import sys


def load(folder, name):
    with open(os.path.join(folder, name + ".json"), encoding="utf-8") as f:
        return {r["scene"]: r for r in json.load(f)["results"]}


def main():
    folder = sys.argv[1]
    runs = {n: load(folder, n) for n in ("kdtree", "kdtree-2", "bvh", "bvh-2", "grid", "rtpipe")}
    print("| scene | rays | kd-tree | BVH | grid | driver | kd / BVH | kd / driver |")
    print("|---|---|---:|---:|---:|---:|---:|---:|")
    for scene in runs["bvh"]:
        name = os.path.splitext(os.path.basename(scene))[0]
        if name == "scene":
            name = os.path.basename(os.path.dirname(scene))
        for kind in ("primary", "shadow", "diffuse"):
            key = kind + "_mrays_per_s"
            kd = max(runs["kdtree"][scene][key], runs["kdtree-2"][scene][key])
            bvh = max(runs["bvh"][scene][key], runs["bvh-2"][scene][key])
            grid, rt = runs["grid"][scene][key], runs["rtpipe"][scene][key]
            print(f"| {name if kind == 'primary' else ''} | {kind} | {kd:,.0f} | {bvh:,.0f} | "
                  f"{grid:,.0f} | {rt:,.0f} | {kd / bvh:.2f} | {kd / rt:.2f} |")
    print()
    print("| scene | triangles | kd-tree build ms | BVH build ms | kd-tree SAH | BVH SAH | "
          "kd-tree references per triangle |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for scene, bvh in runs["bvh"].items():
        kd = runs["kdtree"][scene]
        name = os.path.splitext(os.path.basename(scene))[0]
        if name == "scene":
            name = os.path.basename(os.path.dirname(scene))
        print(f"| {name} | {bvh['triangles']:,} | {kd['build_ms']:.0f} | {bvh['build_ms']:.0f} | "
              f"{kd['sah_cost']:.1f} | {bvh['sah_cost']:.1f} | "
              f"{kd['references'] / kd['triangles']:.2f} |")


if __name__ == "__main__":
    main()
