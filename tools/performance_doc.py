#!/usr/bin/env python3
"""Writes docs/performance.md from docs/performance.md.in and the JSON in bench/results/, so the
page's numbers are the measured ones. Run from the repository root after a benchmark run."""
import io
import json
import subprocess
import sys


def table(path):
    return subprocess.run([sys.executable, "tools/bench_table.py", path], check=True,
                          capture_output=True, text=True).stdout.strip()


def rate(run, scene, accel, key="primary_mrays_per_s"):
    for r in run["results"]:
        if scene in r["scene"] and r["accel"] == accel:
            return r[key]
    raise KeyError((scene, accel))


def density_table(path):
    runs = json.load(open(path, encoding="utf-8"))
    scenes = [r["scene"].split("/")[-1].replace(".cfg", "") for r in next(iter(runs.values()))["results"]]
    out = io.StringIO()
    out.write("| density | " + " | ".join(scenes) + " | MiB, lost-empire |\n")
    out.write("|---:|" + "---:|" * len(scenes) + "---:|\n")
    for density, run in runs.items():
        cells = [f"{r['primary_mrays_per_s']:.0f} / {r['shadow_mrays_per_s']:.0f}" for r in run["results"]]
        lost = [r for r in run["results"] if "lost-empire" in r["scene"]][0]
        out.write(f"| {density} | " + " | ".join(cells) + f" | {lost['bytes'] / 2**20:.2f} |\n")
    return out.getvalue().strip()


def embree_values(path, lavapipe):
    """The section on lavapipe against Embree 3: its table and the sentences on its numbers."""
    vs = json.load(open(path, encoding="utf-8"))
    table_md = subprocess.run([sys.executable, "tools/embree_compare.py", "markdown", path],
                              check=True, capture_output=True, text=True).stdout.strip()
    rows = vs["rows"]
    target = vs["target_primary_ratio"]
    name = lambda r: r["scene"].split("/")[-1].replace(".cfg", "")
    parts = []
    for a, label in (("auto", "`accel auto`"), ("bvh", "the BVH")):
        ratios = [r[f"primary_ratio_{a}"] for r in rows]
        met = sum(x >= target for x in ratios)
        each = ", ".join(f"{name(r)} {r[f'primary_ratio_{a}']:.2f}x"
                         + (f" ({r['vkrt_auto']['accel']})" if a == "auto" else "") for r in rows)
        parts.append(f"with {label} {each}: the target is met on {met} of {len(rows)} scenes")
    hits = []
    for r in rows:
        e, v = r["embree"], r["vkrt_auto"]
        hits.append(f"{name(r)} {e['hits'] - v['hits']:+d} / {e['blocked'] - v['blocked']:+d}")
    same = all(r["embree"]["hits"] == r["vkrt_auto"]["hits"] == r["vkrt_bvh"]["hits"] and
               r["embree"]["blocked"] == r["vkrt_auto"]["blocked"] == r["vkrt_bvh"]["blocked"]
               for r in rows)
    busy = [r["others_cpu_share"] for r in rows if r.get("others_cpu_share") is not None]
    # This run's vkrt BVH against the lavapipe table's, where the scene and size are the same: how
    # much the load of the moment took from lavapipe.
    same = []
    for r in rows:
        for q in lavapipe["results"]:
            if (q["scene"] == r["scene"] and q["accel"] == "bvh" and
                    (q["width"], q["height"]) == (r["width"], r["height"])):
                same.append(r["vkrt_bvh"]["primary_mrays_per_s"] / q["primary_mrays_per_s"])
    m = vs["machine"]
    return {
        "@EMBREE_VS_LAVAPIPE_TABLE@": (
            f"vkrt's BVH primary rates here are {min(same):.2f}x to {max(same):.2f}x those of the "
            "lavapipe table above (same scenes and size, a quieter machine)" if same else
            "the lavapipe table above has no row of the same scene and size to compare with"),
        "@EMBREE_TABLE@": table_md,
        "@EMBREE_MACHINE@": f"{m['cpu']} (`lscpu`), {m['nproc']} cores (`nproc`), Linux "
                            f"{m['kernel']}; vkrt {m['vkrt_commit']}; Mesa {m['mesa']} "
                            f"({m['vulkan_device']}), "
                            f"LP_NUM_THREADS={m['lp_num_threads']}; Embree {vs['embree_version']} "
                            f"(Debian's libembree3-3), {vs['embree_threads']} threads",
        "@EMBREE_VERDICT@": "; ".join(parts),
        "@EMBREE_HITS@": ("Embree's hits and shadowed counts are vkrt's exactly on every scene"
                          if same else "Embree's hits / shadowed counts less vkrt's (accel auto): "
                          + ", ".join(hits)),
        "@EMBREE_OTHERS@": (f"{100 * min(busy):.0f}% to {100 * max(busy):.0f}%" if busy
                            else "an unrecorded share"),
    }


def main():
    h100 = json.load(open("bench/results/bench-h100.json", encoding="utf-8"))
    lavapipe = json.load(open("bench/results/bench-lavapipe.json", encoding="utf-8"))
    text = open("docs/performance.md.in", encoding="utf-8").read()
    values = {
        "@H100_TABLE@": table("bench/results/bench-h100.json"),
        "@LAVAPIPE_TABLE@": table("bench/results/bench-lavapipe.json"),
        "@DENSITY_TABLE@": density_table("bench/results/density-h100.json"),
        "@BUNNY_RATIO@": f"{rate(lavapipe, 'bunny', 'bvh') / rate(lavapipe, 'bunny', 'brute'):.0f}",
        "@STADIUM_LAVAPIPE@": f"{rate(lavapipe, 'scene.cfg', 'bvh') / rate(lavapipe, 'scene.cfg', 'grid'):.0f}",
        "@STADIUM_H100@": f"{rate(h100, 'scene.cfg', 'bvh') / rate(h100, 'scene.cfg', 'grid'):.0f}",
    }
    values.update(embree_values("bench/results/vkrt-lavapipe-vs-embree.json", lavapipe))
    for key, value in values.items():
        text = text.replace(key, value)
    open("docs/performance.md", "w", encoding="utf-8").write(
        "<!-- Generated by tools/performance_doc.py from docs/performance.md.in and "
        "bench/results/: edit those. -->\n" + text)


if __name__ == "__main__":
    main()
