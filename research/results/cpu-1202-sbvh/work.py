#!/usr/bin/env python3
"""work.py: the traversal work per ray of the BVH without and with spatial splits, from trace.sh's
--stats JSON (stats-off/on.json: lavapipe's tree, leaves of 8, node cost 1; stats-gpu-tree-*.json:
the GPUs' tree, leaves of 2, node cost 0.5). Work is the SAH's own measure summed over a primary,
a shadow and a diffuse ray: node cost x nodes + triangles. Also the trace throughput of
trace-*.json (on / off of each round, median and range). Standard library only."""
import glob
import json
import os
import statistics

HERE = os.path.dirname(os.path.abspath(__file__))
KINDS = ("primary", "shadow", "diffuse")


def load(name):
    with open(os.path.join(HERE, name)) as f:
        return {os.path.basename(r["scene"]): r for r in json.load(f)["results"]}


for tree, suffix in (("lavapipe's tree (leaf 8, node cost 1)", ""),
                     ("the GPUs' tree (leaf 2, node cost 0.5)", "gpu-tree-")):
    off, on = load("stats-%soff.json" % suffix), load("stats-%son.json" % suffix)
    print("%s: scene, SAH off -> on (change), references, work off -> on (change)" % tree)
    for scene, a in off.items():
        b = on[scene]
        cost = a["bvh_traversal_cost"]
        work = [sum(cost * r[k + "_nodes_per_ray"] + r[k + "_triangles_per_ray"] for k in KINDS)
                for r in (a, b)]
        print("  %-18s SAH %6.2f -> %6.2f (%+5.1f%%), +%4.1f%% refs, work %6.2f -> %6.2f (%+5.1f%%)"
              % (scene, a["sah_cost"], b["sah_cost"], 100 * (b["sah_cost"] / a["sah_cost"] - 1),
                 100 * (b["references"] / a["references"] - 1), work[0], work[1],
                 100 * (work[1] / work[0] - 1)))

rounds = {}
for path in glob.glob(os.path.join(HERE, "trace-*.json")):
    splits, rnd = os.path.basename(path)[len("trace-"):-len(".json")].split("-")
    for scene, r in load(os.path.basename(path)).items():
        rounds.setdefault(scene, {}).setdefault(int(rnd), {})[splits] = r
print("lavapipe throughput, on / off of each round (Mrays/s):")
for scene, by_round in sorted(rounds.items()):
    for k in KINDS:
        ratios = [v["on"][k + "_mrays_per_s"] / v["off"][k + "_mrays_per_s"]
                  for _, v in sorted(by_round.items())]
        print("  %-18s %-8s median %.2f, range %.2f-%.2f over %d rounds"
              % (scene, k, statistics.median(ratios), min(ratios), max(ratios), len(ratios)))
