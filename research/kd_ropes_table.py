#!/usr/bin/env python3
"""research/kd_ropes_table.py DIR: the kd-tree's rope walk against its stack walk from vkrt bench
JSON in DIR (bench-{stack,ropes}-{1,2,...}.json, bench-{stack,ropes}-stats.json): per scene and
ray kind, each round's Mrays/s (the median run), the ratio ropes / stack per round, and the ratio
of the best runs over all rounds (each variant's fastest of its 11 x rounds runs: the load of a
shared machine only ever slows a run); then the traversal work per ray with --stats."""
import glob
import json
import os
import sys

KINDS = ("primary", "shadow", "diffuse")


def load(path):
    with open(path) as f:
        return {os.path.basename(r["scene"]).replace(".cfg", "") if "slivers" not in r["scene"]
                else "slivers": r for r in json.load(f)["results"]}


def main():
    d = sys.argv[1]
    rounds = sorted({p.rsplit("-", 1)[1][:-5] for p in glob.glob(f"{d}/bench-stack-*.json")
                     if p.rsplit("-", 1)[1][:-5].isdigit()})
    runs = {(v, r): load(f"{d}/bench-{v}-{r}.json") for v in ("stack", "ropes") for r in rounds
            if os.path.exists(f"{d}/bench-{v}-{r}.json")}
    rounds = [r for r in rounds if ("stack", r) in runs and ("ropes", r) in runs]
    scenes = list(runs[("stack", rounds[0])])
    print("| scene | rays | " + " | ".join(f"stack / ropes r{r}" for r in rounds) +
          " | " + " | ".join(f"ropes/stack r{r}" for r in rounds) + " | best of all runs |")
    print("|---|---|" + "---:|" * (2 * len(rounds) + 1))
    for s in scenes:
        for k in KINDS:
            cells, ratios = [], []
            for r in rounds:
                a, b = runs[("stack", r)][s][f"{k}_mrays_per_s"], runs[("ropes", r)][s][f"{k}_mrays_per_s"]
                cells.append(f"{a:.3g} / {b:.3g}")
                ratios.append(f"{b / a:.2f}")
            best = {v: min(runs[(v, r)][s][f"{k}_ms_min"] for r in rounds) for v in ("stack", "ropes")}
            print(f"| {s if k == 'primary' else ''} | {k} | " + " | ".join(cells) + " | " +
                  " | ".join(ratios) + f" | {best['stack'] / best['ropes']:.2f} |")
    stats = {v: f"{d}/bench-{v}-stats.json" for v in ("stack", "ropes")}
    if all(os.path.exists(p) for p in stats.values()):
        st = {v: load(p) for v, p in stats.items()}
        print("\nTraversal work per ray (--stats): inner nodes stepped / triangle tests\n")
        print("| scene | rays | stack | ropes |")
        print("|---|---|---|---|")
        for s in scenes:
            for k in KINDS:
                row = []
                for v in ("stack", "ropes"):
                    r = st[v][s]
                    row.append(" / ".join(f"{r.get(f'{k}_{w}', float('nan')):.1f}"
                                          for w in ("nodes_per_ray", "triangles_per_ray")))
                print(f"| {s if k == 'primary' else ''} | {k} | {row[0]} | {row[1]} |")


if __name__ == "__main__":
    main()
