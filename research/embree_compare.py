#!/usr/bin/env python3
"""vkrt on lavapipe beside Embree 3 on the same CPU (`research/cpu-run embree`).

  embree_compare.py merge RUN_DIR RESULTS_DIR   per-scene JSON of one run -> the result files
  embree_compare.py markdown VS.json            the comparison as a Markdown table (docs/; the
                                                machine and versions are in the JSON)

RUN_DIR holds the scenes' names in order in `scenes` and, per scene S, embree-S.json (research/yardsticks/embree-bench.c --json), auto-S.json and
bvh-S.json (vkrt bench --accel auto / bvh --json) and busy-S.txt (the share of CPU time other
processes took while S ran, from /proc/stat); RESULTS_DIR gets embree-lavapipe.json and
vkrt-lavapipe-vs-embree.json/.txt. The ratio is vkrt's primary Mrays/s over Embree's: the
target of issue 8 is at least 0.5."""
import json
import os
import platform
import subprocess
import sys

TRACES = ("primary", "shadow", "diffuse")


def command_output(args):
    try:
        return subprocess.run(args, check=True, capture_output=True, text=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def machine(vkrt_device):
    model = "unknown"
    for line in command_output(["lscpu"]).splitlines():
        if line.startswith("Model name:"):
            model = line.split(":", 1)[1].strip()
    return {
        "cpu": model,
        "nproc": int(command_output(["nproc"]) or 0),
        "kernel": platform.release(),
        "mesa": command_output(["dpkg-query", "-W", "-f=${Version}", "mesa-vulkan-drivers"]),
        "vulkan_device": vkrt_device,
        "lp_num_threads": os.environ.get("LP_NUM_THREADS", "unset (all cores)"),
        "vkrt_commit": command_output(["git", "describe", "--always", "--dirty"]),
    }


def rates(r):
    out = {k: r[k] for k in ("build_ms", "hits", "blocked")}
    for t in TRACES:
        out[f"{t}_mrays_per_s"] = r[f"{t}_mrays_per_s"]
        out[f"{t}_rays_timed"] = r[f"{t}_rays_timed"]
    return out


def scene_name(path):
    return os.path.splitext(os.path.basename(path))[0]


def merge(run_dir, results_dir):
    scenes = open(os.path.join(run_dir, "scenes"), encoding="utf-8").read().split()
    load = lambda name: json.load(open(os.path.join(run_dir, name), encoding="utf-8"))
    embree_runs = [load(f"embree-{s}.json") for s in scenes]
    vkrt_runs = {a: [load(f"{a}-{s}.json") for s in scenes] for a in ("auto", "bvh")}
    info = machine(vkrt_runs["auto"][0]["device"])
    embree = {k: v for k, v in embree_runs[0].items() if k != "results"}
    embree.update(machine=info, results=[r for run in embree_runs for r in run["results"]])
    rows = []
    for i, s in enumerate(scenes):
        e = embree_runs[i]["results"][0]
        row = {"scene": e["scene"], "triangles": e["triangles"], "width": e["width"],
               "height": e["height"], "embree": rates(e)}
        for a, runs in vkrt_runs.items():
            v = runs[i]["results"][0]
            row[f"vkrt_{a}"] = dict(accel=v["accel"], **rates(v))
            row[f"primary_ratio_{a}"] = v["primary_mrays_per_s"] / e["primary_mrays_per_s"]
        busy = os.path.join(run_dir, f"busy-{s}.txt")
        row["others_cpu_share"] = float(open(busy).read()) if os.path.exists(busy) else None
        rows.append(row)
    vs = {"machine": info, "embree_version": embree["embree_version"],
          "embree_threads": embree["threads"], "embree_build_quality": embree["build_quality"],
          "timed_runs": embree["timed_runs"], "statistic": "median", "target_primary_ratio": 0.5,
          "rows": rows}
    with open(os.path.join(results_dir, "embree-lavapipe.json"), "w", encoding="utf-8") as f:
        json.dump(embree, f, indent=1)
    with open(os.path.join(results_dir, "vkrt-lavapipe-vs-embree.json"), "w", encoding="utf-8") as f:
        json.dump(vs, f, indent=1)
    with open(os.path.join(results_dir, "vkrt-lavapipe-vs-embree.txt"), "w", encoding="utf-8") as f:
        f.write(text(vs))
    sys.stdout.write(text(vs))


def header(vs):
    m = vs["machine"]
    return (f"{m['cpu']}, {m['nproc']} cores; vkrt {m['vkrt_commit']} on {m['vulkan_device']}, "
            f"Mesa {m['mesa']}, LP_NUM_THREADS={m['lp_num_threads']}; Embree "
            f"{vs['embree_version']}, {vs['embree_threads']} threads, rtcIntersect1/rtcOccluded1, "
            f"build quality {vs['embree_build_quality']}. Mrays/s, {vs['statistic']} of "
            f"{vs['timed_runs']} timed runs.")


def tracers(row):
    yield "Embree", "-", row["embree"], None
    for a in ("auto", "bvh"):
        yield "vkrt", row[f"vkrt_{a}"]["accel"] + (" (auto)" if a == "auto" else ""), \
            row[f"vkrt_{a}"], row[f"primary_ratio_{a}"]


def rate(x):
    return f"{x:.3g}"


def text(vs):
    lines = [header(vs), "",
             f"{'scene':<12} {'triangles':>9} {'rays':<9}  {'tracer':<6} {'accel':<11} "
             f"{'build_ms':>8} {'primary':>8} {'shadow':>8} {'diffuse':>8} {'hits':>7} "
             f"{'blocked':>7} {'vs Embree':>9}"]
    for row in vs["rows"]:
        first = True
        for name, accel, r, ratio in tracers(row):
            lead = (f"{scene_name(row['scene']):<12} {row['triangles']:>9} "
                    f"{str(row['width']) + 'x' + str(row['height']):<9}" if first else " " * 32)
            lines.append(f"{lead}  {name:<6} {accel:<11} {r['build_ms']:>8.1f} "
                         f"{rate(r['primary_mrays_per_s']):>8} {rate(r['shadow_mrays_per_s']):>8} "
                         f"{rate(r['diffuse_mrays_per_s']):>8} {r['hits']:>7} {r['blocked']:>7} "
                         f"{(f'{ratio:.2f}x' if ratio is not None else ''):>9}")
            first = False
    return "\n".join(lines) + "\n"


def markdown(path):
    vs = json.load(open(path, encoding="utf-8"))
    print("| scene | triangles | rays | tracer | accel | build ms | primary Mrays/s | "
          "shadow Mrays/s | diffuse Mrays/s | hits | shadowed | primary vs Embree |")
    print("|---|---:|---|---|---|---:|---:|---:|---:|---:|---:|---:|")
    for row in vs["rows"]:
        for name, accel, r, ratio in tracers(row):
            print(f"| {scene_name(row['scene'])} | {row['triangles']} | "
                  f"{row['width']}x{row['height']} | {name} | {accel} | {r['build_ms']:.1f} | "
                  f"{rate(r['primary_mrays_per_s'])} | {rate(r['shadow_mrays_per_s'])} | "
                  f"{rate(r['diffuse_mrays_per_s'])} | {r['hits']} | {r['blocked']} | "
                  f"{f'{ratio:.2f}x' if ratio is not None else ''} |")


def main():
    if len(sys.argv) == 4 and sys.argv[1] == "merge":
        merge(sys.argv[2], sys.argv[3])
    elif len(sys.argv) == 3 and sys.argv[1] == "markdown":
        markdown(sys.argv[2])
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main()
