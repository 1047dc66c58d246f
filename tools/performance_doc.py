#!/usr/bin/env python3
"""Writes docs/performance.md from docs/performance.md.in and the JSON in bench/results/, so the
page's numbers are the measured ones. Run from the repository root after a benchmark run."""
import io
import json
import os
import re
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
    hits_equal = all(r["embree"]["hits"] == r["vkrt_auto"]["hits"] == r["vkrt_bvh"]["hits"] and
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
            "lavapipe table above (same scenes and size)" if same else
            "the lavapipe table above has no row of the same scene and size to compare with"),
        "@EMBREE_TABLE@": table_md,
        "@EMBREE_MACHINE@": f"{m['cpu']} (`lscpu`), {m['nproc']} cores (`nproc`), Linux "
                            f"{m['kernel']}; vkrt {m['vkrt_commit']}; Mesa {m['mesa']} "
                            f"({m['vulkan_device']}), "
                            f"LP_NUM_THREADS={m['lp_num_threads']}; Embree {vs['embree_version']} "
                            f"(Debian's libembree3-3), {vs['embree_threads']} threads",
        "@EMBREE_VERDICT@": "; ".join(parts),
        "@EMBREE_HITS@": ("Embree's hits and shadowed counts are vkrt's exactly on every scene"
                          if hits_equal else "Embree's hits / shadowed counts less vkrt's (accel auto): "
                          + ", ".join(hits)),
        "@EMBREE_OTHERS@": (f"{100 * min(busy):.0f}% to {100 * max(busy):.0f}%" if busy
                            else "an unrecorded share"),
    }


# ---------------------------------------------------------------- issue 8, the H200 runs

ISSUE8 = "bench/results/issue8-h200"
ISSUE8_SCENES = ["bunny", "sponza", "sibenik", "lost-empire"]
KINDS = ["primary", "shadow", "diffuse"]
TARGETS = {"primary": 4000, "shadow": 6000, "diffuse": 1500}


def scene_of(r):
    base = r["scene"].split("/")[-1].replace(".cfg", "")
    return r["scene"].split("/")[-2] if base == "scene" else base


def by_scene(path):
    return {scene_of(r): r for r in json.load(open(path, encoding="utf-8"))["results"]}


def vs_driver_table(vkrt_path, rtpipe_path, scenes=None):
    """Per scene and ray kind: vkrt, the driver's pipeline, and vkrt over the driver."""
    v, d = by_scene(vkrt_path), by_scene(rtpipe_path)
    names = scenes or sorted(v, key=lambda n: v[n]["triangles"])
    out = io.StringIO()
    out.write("| scene | triangles | " + " | ".join(f"{k} vkrt / driver" for k in KINDS) +
              " | hits, blocked: vkrt / driver |\n")
    out.write("|---|---:|" + "---:|" * len(KINDS) + "---|\n")
    for n in names:
        if n not in v or n not in d:
            continue
        cells = []
        for k in KINDS:
            a, b = v[n][f"{k}_mrays_per_s"], d[n][f"{k}_mrays_per_s"]
            mark = ""
            if n in ISSUE8_SCENES and a < TARGETS[k]:
                mark = " (below target)"
            cells.append(f"{a:,.0f} / {b:,.0f} ({a / b:.2f}x){mark}")
        hits = (f"{v[n]['hits']:,}, {v[n]['blocked']:,} / {d[n]['hits']:,}, {d[n]['blocked']:,}")
        out.write(f"| {n} | {v[n]['triangles']:,} | " + " | ".join(cells) + f" | {hits} |\n")
    return out.getvalue().strip()


def stats_table(path):
    rows = by_scene(path)
    out = io.StringIO()
    out.write("| scene | " + " | ".join(f"{k}: nodes, triangles, SIMD" for k in KINDS) + " |\n")
    out.write("|---|" + "---:|" * len(KINDS) + "\n")
    for n in ISSUE8_SCENES:
        r = rows[n]
        cells = [f"{r[k + '_nodes_per_ray']:.1f}, {r[k + '_triangles_per_ray']:.1f}, "
                 f"{100 * r[k + '_simd_utilisation']:.0f}%" for k in KINDS]
        out.write(f"| {n} | " + " | ".join(cells) + " |\n")
    return out.getvalue().strip()


def rates_table(first, rows, mib_scene=None, digits=0):
    """A row per (label, JSON path): primary / shadow / diffuse Mrays/s of each issue-8 scene,
    and with mib_scene the structure's MiB on that scene; first names the label column; digits
    after the point (lavapipe's rates need 2)."""
    out = io.StringIO()
    out.write(f"| {first} | " + " | ".join(ISSUE8_SCENES) +
              (f" | MiB, {mib_scene} |\n" if mib_scene else " |\n") + "|---|" +
              "---:|" * (len(ISSUE8_SCENES) + (1 if mib_scene else 0)) + "\n")
    for label, path in rows:
        run = by_scene(path)
        out.write(f"| {label} | " + " | ".join(
            " / ".join(f"{run[n][k + '_mrays_per_s']:,.{digits}f}" for k in KINDS)
            for n in ISSUE8_SCENES) +
            (f" | {run[mib_scene]['bytes'] / 2**20:.2f} |\n" if mib_scene else " |\n"))
    return out.getvalue().strip()


# The kernel variants measured on the H200, in the order they were tried: (what, JSON file).
VARIANTS = [
    ("binary tree, 32-byte nodes, parent then both children fetched (the kernel before issue 8)",
     "bench/results/h200-run3/kernel-old.json"),
    ("pairs (two float boxes, 64 bytes), leaves intersected inline at two places",
     "bench/results/h200-run1/kernel-new.json"),
    ("4-wide, quantized 8-bit boxes (64 bytes), leaves inline at four places",
     "bench/results/h200-run2/kernel-new.json"),
    ("4-wide, quantized, one place for leaves", "bench/results/h200-run3/kernel-new.json"),
    ("pairs, one place for leaves", "bench/results/h200-run3/kernel-width2.json"),
    ("pairs, one place for leaves, dynamic ray fetch", "bench/results/h200-run4/kernel-new.json"),
    ("pairs, one place for leaves, shadow rays unordered", "bench/results/h200-run4/kernel-static.json"),
    ("the same, primary rays in 8x8 tiles (the default now)", f"{ISSUE8}/vkrt-again.json"),
    ("4-wide, quantized, one place for leaves, 8x8 tiles", f"{ISSUE8}/vkrt-width4.json"),
    ("pairs, tiles, entry distances kept on the stack (popped subtrees beyond the hit dropped)",
     "bench/results/h200-run5/new-1.json"),
    ("the default again, in the same run", "bench/results/h200-run5/old-1.json"),
]


def variants_table():
    return rates_table("kernel", VARIANTS)


def whitted_profile(path=None):
    text = open(path or f"{ISSUE8}/whitted.txt", encoding="utf-8").read().splitlines()
    start = next(i for i, line in enumerate(text) if line.startswith("vkrt: profile"))
    end = next(i for i in range(start, len(text)) if text[i].lstrip().startswith("frame "))
    return "\n".join(text[start:end + 1])


def issue8_values():
    v = by_scene(f"{ISSUE8}/vkrt.json")
    k4 = by_scene(f"{ISSUE8}/vkrt-4k.json")
    d4 = by_scene(f"{ISSUE8}/rtpipe-4k.json")
    whole = by_scene(f"{ISSUE8}/vkrt-whole.json")
    again = by_scene(f"{ISSUE8}/vkrt-again.json")
    four_k = io.StringIO()
    four_k.write("| scene, size | " + " | ".join(f"{k} vkrt / driver" for k in KINDS) + " |\n")
    four_k.write("|---|" + "---:|" * len(KINDS) + "\n")
    for n in ["bunny", "sponza"]:
        for label, a, b in (("1920x1080", v, by_scene(f"{ISSUE8}/rtpipe.json")),
                            ("3840x2160", k4, d4)):
            cells = [f"{a[n][k + '_mrays_per_s']:,.0f} / {b[n][k + '_mrays_per_s']:,.0f}"
                     for k in KINDS]
            four_k.write(f"| {n}, {label}, {a[n]['shadow_rays_timed']:,} shadow rays | " +
                         " | ".join(cells) + " |\n")
    whole_rows = io.StringIO()
    whole_rows.write("| scene | geometry alone: " + ", ".join(KINDS) + " | whole scene: " +
                     ", ".join(KINDS) + " |\n|---|---:|---:|\n")
    for n in ISSUE8_SCENES:
        g = ", ".join(f"{again[n][k + '_mrays_per_s']:,.0f}" for k in KINDS)
        w = ", ".join(f"{whole[n][k + '_mrays_per_s']:,.0f}" for k in KINDS)
        whole_rows.write(f"| {n} | {g} | {w} |\n")
    return {
        "@H200_VS_DRIVER@": vs_driver_table(f"{ISSUE8}/vkrt.json", f"{ISSUE8}/rtpipe.json"),
        "@H200_4K@": four_k.getvalue().strip(),
        "@H200_STATS@": stats_table(f"{ISSUE8}/vkrt-stats.json"),
        "@H200_VARIANTS@": variants_table(),
        "@H200_WHITTED@": whitted_profile(),
        "@H200_WHOLE@": whole_rows.getvalue().strip(),
        "@H200_LOST_EMPIRE_BUILD@": f"{v['lost-empire']['build_ms']:.0f}",
        "@H200_BUNNY_BUILD@": f"{v['bunny']['build_ms']:.0f}",
    }


# ---------------------------------------------------------------- issue 8, second pass

PASS2 = "bench/results/issue8-h200-sort"


def pass2_values():
    base = by_scene(f"{PASS2}/sort/vkrt.json")
    driver = by_scene(f"{PASS2}/sort/rtpipe.json")
    driver8 = by_scene(f"{PASS2}/sort/rtpipe-sort8.json")
    gpu = {c: by_scene(f"{PASS2}/sort/vkrt-sort{c}.json") for c in (4, 8)}
    host = {c: by_scene(f"{PASS2}/levers/sort{c}.json") for c in (2, 4, 8, 16)}
    lever_base = by_scene(f"{PASS2}/levers/base.json")
    ballot = {c: by_scene(f"{PASS2}/sort2/sort{c}-1.json") for c in (4, 8)}

    def diffuse(r):
        return r["diffuse_mrays_per_s"]

    def trace_only(r):
        ms = r["diffuse_ms"] - r["diffuse_sort_ms"]
        return r["diffuse_rays_timed"] / (ms * 1e3)

    host_t = io.StringIO()
    host_t.write("| scene | diffuse rays | tile order | " +
                 " | ".join(f"{c}x{c} cells" for c in host) + " |\n")
    host_t.write("|---|---:|---:|" + "---:|" * len(host) + "\n")
    for n in ISSUE8_SCENES:
        host_t.write(f"| {n} | {lever_base[n]['diffuse_rays_timed']:,} | "
                     f"{diffuse(lever_base[n]):,.0f} | " +
                     " | ".join(f"{diffuse(host[c][n]):,.0f}" for c in host) + " |\n")

    simd = {k: by_scene(f"{PASS2}/levers/{f}.json")
            for k, f in (("tile", "stats"), (4, "stats-sort4"), (16, "stats-sort16"))}
    simd_t = io.StringIO()
    simd_t.write("| scene | tile order | 4x4 cells | 16x16 cells |\n|---|---:|---:|---:|\n")
    for n in ISSUE8_SCENES:
        simd_t.write(f"| {n} | " + " | ".join(f"{100 * simd[k][n]['diffuse_simd_utilisation']:.0f}%"
                                               for k in simd) + " |\n")

    gpu_t = io.StringIO()
    gpu_t.write("| scene | tile order | " +
                " | ".join(f"{c}x{c}: sort ms, trace alone, with the sort" for c in gpu) +
                " | driver: tile order, 8x8 order |\n")
    gpu_t.write("|---|---:|" + "---:|" * len(gpu) + "---:|\n")
    for n in ISSUE8_SCENES:
        cells = [f"{gpu[c][n]['diffuse_sort_ms']:.3f}, {trace_only(gpu[c][n]):,.0f}, "
                 f"**{diffuse(gpu[c][n]):,.0f}**" for c in gpu]
        gpu_t.write(f"| {n} | {diffuse(base[n]):,.0f} | " + " | ".join(cells) +
                    f" | {diffuse(driver[n]):,.0f}, {diffuse(driver8[n]):,.0f} |\n")

    ballot_t = ", ".join(f"{n} {gpu[4][n]['diffuse_sort_ms']:.3f} against "
                         f"{ballot[4][n]['diffuse_sort_ms']:.3f} ms" for n in ISSUE8_SCENES)

    sizes = ["320x180", "960x540", "1920x1080", "2560x1440", "3840x2160"]
    fixed = io.StringIO()
    fixed.write("| size | bunny: shadow rays, ms, Mrays/s | bunny: primary rays, ms | "
                "Cornell box: primary ms |\n|---|---:|---:|---:|\n")
    for size in sizes:
        r = by_scene(f"{PASS2}/levers/size-{size}.json")
        b, c = r["bunny"], r["cornell"]
        fixed.write(f"| {size} | {b['shadow_rays_timed']:,}, {1e3 * b['shadow_ms']:.0f} us, "
                    f"{b['shadow_mrays_per_s']:,.0f} | {1e3 * b['primary_ms']:.0f} us | "
                    f"{1e3 * c['primary_ms']:.0f} us |\n")

    shared_t = rates_table("stack", [
        ("local array (default)", f"{PASS2}/levers/base.json"),
        ("first 32 entries in shared memory, workgroup 64", f"{PASS2}/levers/shared-wg64.json"),
        ("the same, workgroup 128", f"{PASS2}/levers/shared-wg128.json")])

    def sah_table(run_dir, variants):
        return rates_table("build", [(label, f"{PASS2}/{run_dir}/{name}.json")
                                     for label, name in variants], "lost-empire")

    four_k = io.StringIO()
    v4, d4 = by_scene(f"{PASS2}/pass2/vkrt-4k.json"), by_scene(f"{PASS2}/pass2/rtpipe-4k.json")
    four_k.write("| scene, 3840x2160 | " + " | ".join(f"{k} vkrt / driver" for k in KINDS) +
                 " |\n|---|" + "---:|" * len(KINDS) + "\n")
    for n in ["bunny", "sponza"]:
        four_k.write(f"| {n}, {v4[n]['shadow_rays_timed']:,} shadow rays | " + " | ".join(
            f"{v4[n][k + '_mrays_per_s']:,.0f} / {d4[n][k + '_mrays_per_s']:,.0f}" for k in KINDS)
            + " |\n")

    final = by_scene(f"{PASS2}/pass2/vkrt.json")
    kernel = json.load(open(f"{PASS2}/sort/vkrt-kernel.json", encoding="utf-8"))["results"][0]
    return {
        "@PASS2_VS_DRIVER@": vs_driver_table(f"{PASS2}/pass2/vkrt.json",
                                             f"{PASS2}/pass2/rtpipe.json", None),
        "@PASS2_4K@": four_k.getvalue().strip(),
        "@PASS2_STATS@": stats_table(f"{PASS2}/pass2/vkrt-stats.json"),
        "@PASS2_WHITTED@": whitted_profile(f"{PASS2}/pass2/whitted.txt"),
        "@PASS2_SAH_FIRST@": sah_table("sah", [
            ("leaves of 8, node cost 1 (the old default)", "default"),
            ("node cost 0.5", "cost0.5"), ("node cost 2", "cost2"), ("node cost 3", "cost3"),
            ("leaves of 4", "leaf4"), ("leaves of 16, node cost 2", "leaf16-cost2"),
            ("**leaves of 2, node cost 0.5**", "leaf2-cost0.5"),
            ("the old default again", "default-again")]),
        "@PASS2_SAH_SECOND@": sah_table("pass2", [
            ("leaves of 8, node cost 1 (the old default)", "old-default"),
            ("**leaves of 2, node cost 0.5 (the default on GPUs now)**", "vkrt"),
            ("leaves of 1, node cost 0.5", "leaf1-cost0.5"),
            ("leaves of 2, node cost 0.25", "leaf2-cost0.25"),
            ("leaves of 3, node cost 0.75", "leaf3-cost0.75"),
            ("the default again", "vkrt-again")]),
        "@PASS2_GPU_BUILD_BUNNY@": f"{final['bunny']['build_ms']:.0f}",
        "@PASS2_GPU_BUILD_EMPIRE@": f"{final['lost-empire']['build_ms']:.0f}",
        "@PASS2_HOST_SORT@": host_t.getvalue().strip(),
        "@PASS2_SIMD@": simd_t.getvalue().strip(),
        "@PASS2_GPU_SORT@": gpu_t.getvalue().strip(),
        "@PASS2_BALLOT@": ballot_t,
        "@PASS2_FIXED@": fixed.getvalue().strip(),
        "@PASS2_SHARED@": shared_t,
        "@PASS2_TRACE_REGISTERS@": str(kernel["trace_kernel"]["Register Count"]),
        "@PASS2_OCCLUSION_REGISTERS@": str(kernel["occlusion_kernel"]["Register Count"]),
        "@PASS2_BUILD_BUNNY@": f"{base['bunny']['build_ms']:.0f}",
        "@PASS2_BUILD_EMPIRE@": f"{base['lost-empire']['build_ms']:.0f}",
    }


PASS3 = "bench/results/issue8-h200-pass3"
WALKS = "bench/results/walk-profile"


def walk_profile(path):
    """tools/walk_profile.c's output: per ray kind its counts, and the shadow rays' schedules."""
    kinds, kind = {}, None
    for line in open(path, encoding="utf-8"):
        m = re.match(r"(primary|shadow|diffuse): (\d+) rays, ([\d.]+) nodes, ([\d.]+) triangles, "
                     r"([\d.]+) iterations per ray, SIMD (\d+)%", line)
        if m:
            kind = m.group(1)
            kinds[kind] = {"rays": int(m.group(2)), "nodes": float(m.group(3)),
                           "triangles": float(m.group(4)), "simd": int(m.group(6))}
            continue
        r = kinds.get(kind)
        m = re.search(r"per subgroup \(its busiest lane\): median (\d+), 99% (\d+), longest (\d+) "
                      r"\(subgroup (\d+) of (\d+)\)", line)
        if m:
            r.update(group_median=int(m.group(1)), group_longest=int(m.group(3)),
                     longest_at=int(m.group(4)), groups=int(m.group(5)))
        m = re.search(r"dispatch order: (\d+) iterations, balanced (\d+)", line)
        if m:
            r.update(in_order=int(m.group(1)), balanced=int(m.group(2)))
        m = re.search(r"reverse order (\d+), longest first (\d+)", line)
        if m:
            r.update(reversed=int(m.group(1)), longest_first=int(m.group(2)))
        m = re.search(r"4-wide .*: ([\d.]+) iterations per ray, longest subgroup (\d+); on \d+ slots (\d+)",
                      line)
        if m:
            r.update(wide_iterations=float(m.group(1)), wide_longest=int(m.group(2)),
                     wide_in_order=int(m.group(3)))
        m = re.search(r"taking subtrees: ([\d.]+) iterations per subgroup, longest (\d+); on \d+ slots (\d+)",
                      line)
        if m:
            r.update(share_longest=int(m.group(2)), share_in_order=int(m.group(3)))
    return kinds


def frame_ms(path):
    text = open(path, encoding="utf-8").read()
    return float(re.search(r"frame ([\d.]+) ms", text).group(1))


def pass3_values():
    walks = {n: walk_profile(f"{WALKS}/{n}-1920x1080.txt") for n in ISSUE8_SCENES}
    gpu_stats = by_scene(f"{PASS3}/vkrt-stats.json")
    agree = io.StringIO()
    agree.write("| scene | " + " | ".join(f"{k}: walk-profile / GPU" for k in KINDS) + " |\n")
    agree.write("|---|" + "---:|" * len(KINDS) + "\n")
    for n in ISSUE8_SCENES:
        g = gpu_stats[n]
        cells = [f"{walks[n][k]['nodes']:.1f} / {g[k + '_nodes_per_ray']:.1f}, "
                 f"{walks[n][k]['triangles']:.1f} / {g[k + '_triangles_per_ray']:.1f}, "
                 f"{walks[n][k]['simd']}% / {100 * g[k + '_simd_utilisation']:.0f}%" for k in KINDS]
        agree.write(f"| {n} | " + " | ".join(cells) + " |\n")

    base, rev = by_scene(f"{PASS3}/vkrt.json"), by_scene(f"{PASS3}/reversed.json")
    tail = io.StringIO()
    tail.write("| scene | shadow subgroups | longest subgroup | balanced | in order | reversed | "
               "longest first | reversed, predicted | reversed, measured (Mrays/s) |\n")
    tail.write("|---|---:|---:|---:|---:|---:|---:|---:|---|\n")
    for n in ISSUE8_SCENES:
        w = walks[n]["shadow"]
        a, b = base[n]["shadow_mrays_per_s"], rev[n]["shadow_mrays_per_s"]
        tail.write(f"| {n} | {w['groups']:,} | {w['group_longest']} | {w['balanced']} | "
                   f"{w['in_order']} | {w['reversed']} | {w['longest_first']} | "
                   f"{w['in_order'] / w['reversed']:.2f}x | {a:,.0f} to {b:,.0f}: {b / a:.2f}x |\n")

    wide = io.StringIO()
    wide.write("| scene | pairs: longest subgroup, in order | 4-wide: iterations per ray, longest "
               "subgroup, in order | pairs, idle lanes taking subtrees: longest, in order |\n")
    wide.write("|---|---:|---:|---:|\n")
    for n in ISSUE8_SCENES:
        w = walks[n]["shadow"]
        wide.write(f"| {n} | {w['group_longest']}, {w['in_order']} | {w['wide_iterations']:.1f}, "
                   f"{w['wide_longest']}, {w['wide_in_order']} | {w['share_longest']}, "
                   f"{w['share_in_order']} |\n")

    runs = [("one loop, a branch for nodes and one for leaves (the default)", "vkrt"),
            ("while-while, speculative (`bench/variants/while-while.patch`)", "ww"),
            ("while-while, not speculative (`while-while-plain.patch`)", "ww-plain"),
            ("the default again", "vkrt-again"), ("while-while, speculative, again", "ww-again")]
    walk_t = rates_table("walk", [(label, f"{PASS3}/{name}.json") for label, name in runs])

    def slower(name):
        """The least and most a variant run lost against the default, in %, and its gains."""
        run, losses, gains = by_scene(f"{PASS3}/{name}.json"), [], []
        for n in ISSUE8_SCENES:
            for k in KINDS:
                f = run[n][k + "_mrays_per_s"] / base[n][k + "_mrays_per_s"]
                (losses if f < 1 else gains).append((100 * (1 - f), n, k))
        return min(losses)[0], max(losses)[0], gains

    ww_lo, ww_hi, ww_gains = slower("ww")
    plain_lo, plain_hi, plain_gains = slower("ww-plain")
    assert not ww_gains, ww_gains
    plain_except = "; ".join(f"{n}'s {k} rays {-g:.0f}% faster" for g, n, k in plain_gains)
    shadow = {n: walks[n]["shadow"] for n in ISSUE8_SCENES}
    bunny = walks["bunny"]["shadow"]
    bunny4k = walk_profile(f"{WALKS}/bunny-3840x2160.txt")["shadow"]
    v4k = by_scene(f"{PASS2}/pass2/vkrt-4k.json")["bunny"]
    fq_dir = f"{PASS3}/float-quads"
    fq_runs = [("pairs (the default)", "pairs"), ("4-wide, float boxes", "fq"),
               ("4-wide, float boxes, only the nearest child first", "fq-nearest"),
               ("4-wide, float boxes, leaves of 4, node cost 1", "fq-leaf4"),
               ("pairs again", "pairs-again"), ("4-wide, float boxes, again", "fq-again")]
    fq_t = rates_table("walk", [(label, f"{fq_dir}/{name}.json") for label, name in fq_runs],
                       "lost-empire")
    fq_stats = by_scene(f"{fq_dir}/fq-stats.json")
    fq_nodes = ", ".join(
        f"{n} {gpu_stats[n]['shadow_nodes_per_ray']:.1f} to {fq_stats[n]['shadow_nodes_per_ray']:.1f}"
        for n in ISSUE8_SCENES)
    fq_bunny = by_scene(f"{fq_dir}/fq.json")["bunny"]["shadow_mrays_per_s"]
    pairs_bunny = by_scene(f"{fq_dir}/pairs.json")["bunny"]["shadow_mrays_per_s"]
    fq_run, fq_base = by_scene(f"{fq_dir}/fq.json"), by_scene(f"{fq_dir}/pairs.json")

    def fq_change(kind):
        """Per scene, the float 4-wide walk's rate against the pairs' in the same run."""
        return ", ".join(f"{n} {100 * (fq_run[n][kind + '_mrays_per_s'] / fq_base[n][kind + '_mrays_per_s'] - 1):+.0f}%"
                         for n in ISSUE8_SCENES)

    return {
        "@PASS3_FQ_PRIMARY@": fq_change("primary"),
        "@PASS3_FQ_SHADOW@": fq_change("shadow"),
        "@PASS3_FQ_DIFFUSE@": fq_change("diffuse"),
        "@PASS3_FQ@": fq_t,
        "@PASS3_FQ_NODES@": fq_nodes,
        "@PASS3_FQ_BUNNY@": f"{fq_bunny:,.0f} against {pairs_bunny:,.0f}",
        "@PASS3_AGREEMENT@": agree.getvalue().strip(),
        "@PASS3_TAIL@": tail.getvalue().strip(),
        "@PASS3_WIDE@": wide.getvalue().strip(),
        "@PASS3_WALKS@": walk_t,
        "@PASS3_VS_DRIVER@": vs_driver_table(f"{PASS3}/vkrt.json", f"{PASS3}/rtpipe.json", None),
        "@PASS3_WHITTED_DEFAULT@": f"{frame_ms(f'{PASS3}/default/whitted.txt'):.2f}",
        "@PASS3_WHITTED_WW@": f"{frame_ms(f'{PASS3}/ww/whitted.txt'):.2f}",
        "@PASS3_WW_SLOWER@": f"{ww_lo:.0f}-{ww_hi:.0f}%",
        "@PASS3_PLAIN_SLOWER@": f"{plain_lo:.0f}-{plain_hi:.0f}%",
        "@PASS3_PLAIN_EXCEPT@": plain_except or "none",
        "@PASS3_WIDE_RATIO@": "{:.2f}-{:.2f}x".format(
            min(shadow[n]["wide_in_order"] / shadow[n]["in_order"] for n in ISSUE8_SCENES),
            max(shadow[n]["wide_in_order"] / shadow[n]["in_order"] for n in ISSUE8_SCENES)),
        "@PASS3_SHARE_SHORTER@": f"{100 * (1 - bunny['share_longest'] / bunny['group_longest']):.0f}%",
        "@PASS3_BUNNY_REV_PREDICTED@": f"{bunny['in_order'] / bunny['reversed']:.2f}",
        "@PASS3_BUNNY_REV_MEASURED@": f"{rev['bunny']['shadow_mrays_per_s'] / base['bunny']['shadow_mrays_per_s']:.2f}",
        "@PASS3_BUNNY_LONGEST@": str(bunny["group_longest"]),
        "@PASS3_BUNNY_AT@": f"{bunny['longest_at']:,}",
        "@PASS3_BUNNY_GROUPS@": f"{bunny['groups']:,}",
        "@PASS3_BUNNY_IN_ORDER@": str(bunny["in_order"]),
        "@PASS3_BUNNY_BALANCED@": str(bunny["balanced"]),
        "@PASS3_BUNNY_TAIL@": f"{bunny['in_order'] / bunny['balanced']:.2f}",
        "@PASS3_BUNNY_BEST@": str(bunny["longest_first"]),
        "@PASS3_BUNNY_BEST_GAIN@": f"{bunny['in_order'] / bunny['longest_first']:.2f}",
        "@PASS3_BUNNY_BEST_RATE@": f"{round(base['bunny']['shadow_mrays_per_s'] * bunny['in_order'] / bunny['longest_first'], -2):,.0f}",
        "@PASS3_BUNNY_4K_TAIL@": f"{bunny4k['in_order'] / bunny4k['balanced']:.2f}",
        "@PASS3_BUNNY_4K_RATIO@": f"{bunny4k['in_order'] / bunny['in_order']:.2f}",
        "@PASS3_BUNNY_GPU_RATIO@": f"{v4k['shadow_ms'] / by_scene(f'{PASS2}/pass2/vkrt.json')['bunny']['shadow_ms']:.2f}",
    }


def loads_values():
    """Texel loads against storage loads: lavapipe (this session's cpu-run-embree.sh against the
    run before texel loads, kept in bench/results/lavapipe-storage-loads/) and the H200."""
    def rows(path):
        return {r["scene"].split("/")[-1].replace(".cfg", ""): r
                for r in json.load(open(path, encoding="utf-8"))["rows"]}
    old = rows("bench/results/lavapipe-storage-loads/vkrt-lavapipe-vs-embree.json")
    new = rows("bench/results/lavapipe-texel-one-loop/vkrt-lavapipe-vs-embree.json")
    lp = io.StringIO()
    lp.write("| scene | BVH, storage loads | BVH, texel loads | texel over storage | "
             "grid, texel loads | BVH over grid |\n|---|---:|---:|---:|---:|---:|\n")
    grids = by_scene("bench/results/lavapipe-grid-texel-loads.json")
    gains, over_grid = [], []
    for n in ISSUE8_SCENES:
        a, b = old[n]["vkrt_bvh"], new[n]["vkrt_bvh"]
        g = grids.get(n)
        cells = " / ".join(f"{a[k + '_mrays_per_s']:.2f}" for k in KINDS)
        cells2 = " / ".join(f"{b[k + '_mrays_per_s']:.2f}" for k in KINDS)
        ratio = " / ".join(f"{b[k + '_mrays_per_s'] / a[k + '_mrays_per_s']:.1f}x" for k in KINDS)
        gains += [b[k + "_mrays_per_s"] / a[k + "_mrays_per_s"] for k in KINDS]
        if g:
            grid_cells = " / ".join(f"{g[k + '_mrays_per_s']:.2f}" for k in KINDS)
            vs_grid = " / ".join(f"{b[k + '_mrays_per_s'] / g[k + '_mrays_per_s']:.1f}x" for k in KINDS)
            over_grid += [b[k + "_mrays_per_s"] / g[k + "_mrays_per_s"] for k in KINDS]
        else:
            grid_cells = vs_grid = "(not run)"
        lp.write(f"| {n} | {cells} | {cells2} | {ratio} | {grid_cells} | {vs_grid} |\n")
    h200 = rates_table("loads", [("storage (the default on GPUs)", f"{PASS3}/loads/storage.json"),
                                 ("texel", f"{PASS3}/loads/texel.json"),
                                 ("storage again", f"{PASS3}/loads/storage-again.json"),
                                 ("texel again", f"{PASS3}/loads/texel-again.json")])
    st, tx = by_scene(f"{PASS3}/loads/storage.json"), by_scene(f"{PASS3}/loads/texel.json")
    change = lambda k: ", ".join(
        f"{n} {100 * (tx[n][k + '_mrays_per_s'] / st[n][k + '_mrays_per_s'] - 1):+.0f}%"
        for n in ISSUE8_SCENES)
    return {
        "@LOADS_LAVAPIPE@": lp.getvalue().strip(),
        "@LOADS_GAIN@": f"{min(gains):.1f}-{max(gains):.1f}x",
        "@LOADS_OVER_GRID@": f"{min(over_grid):.1f}-{max(over_grid):.1f}x" if over_grid else "(not run)",
        "@LOADS_OLD_COMMIT@": json.load(open(
            "bench/results/lavapipe-storage-loads/vkrt-lavapipe-vs-embree.json",
            encoding="utf-8"))["machine"]["vkrt_commit"],
        "@LOADS_H200@": h200,
        "@LOADS_H200_PRIMARY@": change("primary"),
        "@LOADS_H200_SHADOW@": change("shadow"),
        "@LOADS_H200_DIFFUSE@": change("diffuse"),
    }


# ---------------------------------------------------------------- issue 8, fourth pass

LAVAPIPE_WALKS = "bench/results/lavapipe-walks"
PASS4 = "bench/results/issue8-h200-pass4"
# (label, file name without round and .json) of bench/cpu-run-walks.sh's runs.
CPU_WALK_RUNS = [("pairs, one loop (the default before)", "2-one-loop"),
             ("pairs, nested", "2-nested"),
             ("quads, one loop", "4-one-loop"),
             ("quads, nested (the default on CPU devices now)", "4-nested")]


def change(a, b):
    """Per ray kind, the range over the issue's scenes of a's rate against b's (by_scene runs)."""
    parts = []
    for k in KINDS:
        d = [100 * (a[n][k + "_mrays_per_s"] / b[n][k + "_mrays_per_s"] - 1)
             for n in ISSUE8_SCENES]
        parts.append(f"{k} {min(d):+.1f}% to {max(d):+.1f}%")
    return ", ".join(parts)


def walks_values():
    """The BVH's walks on lavapipe (bench/cpu-run-walks.sh) and on the H200
    (bench/gpu-run-walks.sh), and the probe of a branch no lane takes."""
    rows = [(f"{label}, round {r}", f"{LAVAPIPE_WALKS}/{name}-{r}.json")
            for r in (1, 2) for label, name in CPU_WALK_RUNS]
    mean = lambda name, n, k: sum(by_scene(f"{LAVAPIPE_WALKS}/{name}-{r}.json")[n][k + "_mrays_per_s"]
                                  for r in (1, 2)) / 2
    gain = lambda k: ", ".join(f"{n} {mean('4-nested', n, k) / mean('2-one-loop', n, k):.2f}x"
                               for n in ISSUE8_SCENES)
    probe = [float(line.split()[6]) for line in open(f"{LAVAPIPE_WALKS}/dead-branch.txt", encoding="utf-8")
             if line.startswith("scenes/")]
    as_is, patched = probe[0::2], probe[1::2]
    values = {
        "@WALKS_LAVAPIPE@": rates_table("walk, round", rows, mib_scene="sponza", digits=2),
        "@WALKS_GAIN_PRIMARY@": gain("primary"),
        "@WALKS_GAIN_SHADOW@": gain("shadow"),
        "@WALKS_GAIN_DIFFUSE@": gain("diffuse"),
        "@WALKS_PROBE@": (f"{' and '.join(f'{x:.2f}' for x in as_is)} Mrays/s as it is, "
                          f"{' and '.join(f'{x:.2f}' for x in patched)} with the branch "
                          f"({100 * (sum(patched) / sum(as_is) - 1):+.0f}%)"),
    }
    text = open("bench/results/walk-profile/bunny-1920x1080.txt", encoding="utf-8").read()
    shadow = text[text.index("shadow:"):text.index("diffuse:")]
    in_order = re.search(r"dispatch order: (\d+) iterations", shadow).group(1)
    reversed_ = re.search(r"reverse order (\d+)", shadow).group(1)
    splits = re.findall(r"split in (\d), (part|ray) major: [\d.]+ iterations per ray, longest "
                        r"subgroup \d+; on \d+ slots (\d+), reversed (\d+)", shadow)
    values["@WALKS_SPLIT@"] = (
        f"the bunny's 1080p shadow dispatch takes {in_order} iterations in dispatch order and "
        f"{reversed_} reversed; split, " + "; ".join(
            f"in {n} with each {'part' if m == 'part' else 'ray'}'s "
            f"{'rays in a run of their own' if m == 'part' else 'parts side by side'}, "
            f"{a} in order and {b} reversed" for n, m, a, b in splits) +
        " (`bench/results/walk-profile/bunny-1920x1080.txt`)")
    gpu = [("pairs, one loop, written with the nested walk's stack (first call)", "one-loop"),
           ("pairs, nested", "nested"), ("quads, nested", "nested-width4"),
           ("quads, one loop", "one-loop-width4"), ("pairs, one loop again", "one-loop-again")]
    values["@WALKS_H200@"] = rates_table("walk", [(label, f"{PASS4}/{name}.json")
                                                  for label, name in gpu])
    ab = [(f"{label}, round {r}", f"{PASS4}/ab/{name}-{r}.json") for r in (1, 2)
          for label, name in (("one loop, the nested walk's stack", "refactored"),
                              ("the third pass's kernels", "pass3"),
                              ("one loop, a stack of its own (committed)", "local"))]
    ab += [("committed, last call", f"{PASS4}/final/final.json"),
           ("committed, nested walk, last call", f"{PASS4}/final/final-nested.json")]
    values["@WALKS_H200_AB@"] = rates_table("kernels", ab)

    runs = lambda name: [by_scene(f"{PASS4}/ab/{name}-{r}.json") for r in (1, 2)]
    ref, old, local = runs("refactored"), runs("pass3"), runs("local")
    final = by_scene(f"{PASS4}/final/final.json")
    values["@WALKS_H200_REFACTORED@"] = change(ref[0], old[0]) + " (round 1); " + \
        change(ref[1], old[1]) + " (round 2)"
    values["@WALKS_H200_LOCAL@"] = change(local[0], old[0]) + " (round 1); " + \
        change(local[1], old[1]) + " (round 2)"
    values["@WALKS_H200_VS_PASS3@"] = change(final, by_scene(f"{PASS3}/vkrt.json"))
    values["@WALKS_H200_NESTED@"] = change(by_scene(f"{PASS4}/final/final-nested.json"), final)
    return values


# ---------------------------------------------------------------- issue 8, fifth pass

PASS5 = "bench/results/issue8-h200-pass5"


def whitted_frame(path):
    """(frame ms, frame over trace + light) from a --profile output's first frame line."""
    m = re.search(r"frame ([\d.]+) ms .*costs ([\d.]+)x its tracing", open(path, encoding="utf-8").read())
    return float(m.group(1)), float(m.group(2))


def kernel_registers(path):
    r = json.load(open(path, encoding="utf-8"))["results"][0]
    return r["trace_kernel"]["Register Count"], r["occlusion_kernel"]["Register Count"]


def pass5_values():
    """The fifth pass: where every target stands (bench/gpu-run-pass5.sh, one call), and the fma
    slab tests against the fourth pass's kernels (bench/gpu-run-fma-ab.sh)."""
    final = f"{PASS5}/final"
    v, d = by_scene(f"{final}/vkrt.json"), by_scene(f"{final}/rtpipe.json")
    k4 = by_scene(f"{final}/vkrt-4k.json")
    frame, over = whitted_frame(f"{final}/whitted.txt")
    build_2core = re.search(r"build and pairs layout: min ([\d.]+) ms, median ([\d.]+) ms",
                            open("bench/results/bvh-build-2core-pass5.txt", encoding="utf-8").read())
    embree = json.load(open("bench/results/vkrt-lavapipe-vs-embree.json", encoding="utf-8"))
    ratios = [(r["scene"].split("/")[-1].replace(".cfg", ""), r["primary_ratio_auto"])
              for r in embree["rows"]]
    rows = []
    for k in KINDS:
        cells = ", ".join(f"{n} {v[n][k + '_mrays_per_s']:,.0f}" for n in ISSUE8_SCENES)
        met = [n for n in ISSUE8_SCENES if v[n][k + "_mrays_per_s"] >= TARGETS[k]]
        status = f"met on {len(met)} of {len(ISSUE8_SCENES)}"
        if k == "shadow" and "bunny" not in met:
            status += (f"; **missed on the bunny**, which reaches "
                       f"{k4['bunny']['shadow_mrays_per_s']:,.0f} at 3840x2160")
        rows.append((f"{k} rays at 1920x1080, at least {TARGETS[k]:,} Mrays/s", cells, status))
    over_driver = ", ".join(
        f"{k} {min(v[n][k + '_mrays_per_s'] / d[n][k + '_mrays_per_s'] for n in ISSUE8_SCENES):.2f}x"
        for k in KINDS)
    rows.append(("at least the driver's ray tracing pipeline, each ray kind, same rays",
                 f"vkrt over the driver, the lowest of the four scenes: {over_driver}", "met"))
    rows.append(("the Whitted Sponza frame at 1080p: under 5 ms, at most 1.3x its tracing",
                 f"{frame:.2f} ms, {over:.2f}x", "met" if frame < 5 and over <= 1.3 else "missed"))
    rows.append(("BVH build of 225k triangles (Lost Empire) under 100 ms, CPU (2 cores) or GPU",
                 f"2 cores of the dev machine: median {build_2core.group(2)} ms, least "
                 f"{build_2core.group(1)} ms over 20 runs in one process (`bench/results/bvh-build-2core-pass5.txt`)",
                 "met"))
    low = sum(x >= embree["target_primary_ratio"] for _, x in ratios)
    rows.append(("lavapipe: at least half Embree 3's primary rays per second",
                 ", ".join(f"{n} {x:.2f}x" for n, x in ratios),
                 f"**missed** (met on {low} of {len(ratios)})" if low < len(ratios) else "met"))
    targets = io.StringIO()
    targets.write("| target | measured | |\n|---|---|---|\n")
    for t, m, st in rows:
        targets.write(f"| {t} | {m} | {st} |\n")
    ab = [(f"{label}, round {r}", f"{PASS5}/fma-ab/{name}-{r}.json") for r in (1, 2)
          for label, name in (("one fma per plane (committed)", "fma"),
                              ("the fourth pass's kernels", "pass4"))]
    ab += [("one fma per plane, 4-wide nodes", f"{PASS5}/fma-ab/fma-width4.json"),
           ("the fourth pass's kernels, 4-wide nodes", f"{PASS5}/fma-ab/pass4-width4.json")]
    runs = lambda name: [by_scene(f"{PASS5}/fma-ab/{name}-{r}.json") for r in (1, 2)]
    fma, old = runs("fma"), runs("pass4")
    new_regs, old_regs = (kernel_registers(f"{PASS5}/fma-ab/{n}-kernel.json") for n in ("fma", "pass4"))
    again_v, again_d = by_scene(f"{final}/vkrt-again.json"), by_scene(f"{final}/rtpipe-again.json")
    rows_ab = [(f"{label}, {call} call, round {r}", f"{PASS5}/shear-rows/{sub}{name}-{r}.json")
               for call, sub, names in (("first", "", (("committed", "committed"),
                                                      ("rows written through the index", "rows"))),
                                        ("second", "second/", (("committed", "committed"),
                                                               ("rows written through the index", "rows"),
                                                               ("rows from one-hot axes", "onehot"))))
               for r in (1, 2) for label, name in names]
    second = lambda name: [by_scene(f"{PASS5}/shear-rows/second/{name}-{r}.json") for r in (1, 2)]
    onehot, before = second("onehot"), second("committed")
    rows_regs = kernel_registers(f"{PASS5}/shear-rows/second/onehot-kernel.json")
    s4 = lambda name: by_scene(f"{PASS5}/sponza-4k/{name}.json")["sponza"]
    final_4k = by_scene(f"{final}/vkrt-4k.json")["sponza"]
    return {
        "@PASS5_TARGETS@": targets.getvalue().strip(),
        "@PASS5_VS_DRIVER@": vs_driver_table(f"{final}/vkrt.json", f"{final}/rtpipe.json"),
        "@ROWS_AB@": rates_table("kernels", rows_ab),
        "@ROWS_CHANGE@": (change(onehot[0], before[0]) + " (round 1); " +
                          change(onehot[1], before[1]) + " (round 2)"),
        "@ROWS_REGISTERS@": (f"{new_regs[0]} to {rows_regs[0]} registers for the closest-hit kernel "
                             f"and {new_regs[1]} to {rows_regs[1]} for the shadow-ray one"),
        "@ROWS_LAVAPIPE@": variant_summary("shear-rows-onehot"),
        "@SPONZA_4K@": (f"{final_4k['shadow_ms']:.3f} ms (least {final_4k['shadow_ms_min']:.3f}, most "
                        f"{final_4k['shadow_ms_max']:.3f}), {final_4k['shadow_mrays_per_s']:,.0f} Mrays/s"),
        "@SPONZA_4K_AGAIN@": ", ".join(
            f"{label} {s4(f'{name}-4k-{r}')['shadow_mrays_per_s']:,.0f}"
            for r in (1, 2) for label, name in (("committed", "committed"), ("the fma kernels", "fma"))),
        "@PASS5_AGAIN@": (f"vkrt's second run against its first: {change(again_v, v)}; the "
                          f"driver's: {change(again_d, d)}"),
        "@PASS5_FMA_AB@": rates_table("kernels", ab),
        "@PASS5_FMA_CHANGE@": (change(fma[0], old[0]) + " (round 1); " +
                               change(fma[1], old[1]) + " (round 2); 4-wide nodes: " +
                               change(by_scene(f"{PASS5}/fma-ab/fma-width4.json"),
                                      by_scene(f"{PASS5}/fma-ab/pass4-width4.json"))),
        "@PASS5_REGISTERS@": (f"{old_regs[0]} to {new_regs[0]} registers for the closest-hit "
                              f"kernel and {old_regs[1]} to {new_regs[1]} for the shadow-ray one"),
        "@PASS5_WHITTED@": whitted_profile(f"{final}/whitted.txt"),
        "@PASS5_BUNNY_SHADOW@": f"{by_scene(f'{PASS5}/vkrt.json')['bunny']['shadow_mrays_per_s']:,.0f}",
        "@PASS5_BUNNY_SHADOW_4K@": f"{by_scene(f'{PASS5}/vkrt-4k.json')['bunny']['shadow_mrays_per_s']:,.0f}",
        "@FINAL_BUNNY_SHADOW@": f"{v['bunny']['shadow_mrays_per_s']:,.0f}",
        "@FINAL_BUNNY_SHADOW_4K@": f"{k4['bunny']['shadow_mrays_per_s']:,.0f}",
        "@PASS5_LAVAPIPE_AB@": variant_summary("slab-sub-mul"),
        **mesa25_values(),
        "@PASS5_GROUP_STACK@": variant_summary("group-stack"),
    }


PASS6 = "bench/results/issue8-h200-pass6"
ORACLE_ORDERS = ("in order", "subgroups reversed", "subgroups longest first", "rays longest first")
ORACLE_LINE = re.compile(r"oracle \S+/(\S+)\.cfg shadow, (.+?): ([\d.e+]+) Mrays/s \(median ([\d.]+) "
                         r"ms, fastest ([\d.]+) ms\), blocked (\d+), SIMD (\d+)%, longest subgroup (\d+)")


def oracle_runs(path):
    """bench/gpu-run-oracle.sh's log: {(run name, width, height, scene): {order: its figures}}."""
    runs, run = {}, None
    for line in open(path, encoding="utf-8"):
        head = re.match(r"== (\S+) (\d+)x(\d+):", line)
        if head:
            run = (head.group(1), int(head.group(2)), int(head.group(3)))
            continue
        m = ORACLE_LINE.match(line)
        if m:
            runs.setdefault(run + (m.group(1),), {})[m.group(2)] = {
                "mrays": float(m.group(3)), "ms": float(m.group(4)), "blocked": int(m.group(6)),
                "simd": int(m.group(7)), "longest": int(m.group(8))}
    return runs


def pass6_values():
    """The sixth pass: the shadow rays in orders known only after tracing them
    (bench/gpu-run-oracle.sh), and lavapipe on this session's machine (bench/cpu-run-pass6.sh)."""
    runs = oracle_runs(f"{PASS6}/oracle-log.txt")
    rows = io.StringIO()
    rows.write("| scene, size | shadow rays | longest subgroup | " + " | ".join(ORACLE_ORDERS) +
               " | best over in order |\n|---|---:|---:|" + "---:|" * (len(ORACLE_ORDERS) + 1) + "\n")
    for (name, w, h, scene), orders in runs.items():
        rays = by_scene(f"{PASS6}/oracle/{name}.json")[scene]["shadow_rays_timed"]
        blocked = {o["blocked"] for o in orders.values()}
        assert len(blocked) == 1, f"{scene} {w}x{h}: the orders blocked different rays"
        best = max(o["mrays"] for o in orders.values())
        rows.write(f"| {scene}, {w}x{h} | {rays:,} | {orders['in order']['longest']} | " +
                   " | ".join(f"{orders[o]['mrays']:,.0f}" for o in ORACLE_ORDERS) +
                   f" | {best / orders['in order']['mrays']:.2f}x |\n")
    bunny = runs[("oracle-1080", 1920, 1080, "bunny")]
    first = bunny["subgroups longest first"]
    committed = [by_scene(f"{PASS6}/oracle/{n}.json") for n in ("committed", "committed-again")]
    rays = committed[0]["bunny"]["shadow_rays_timed"]
    shadow = lambda n: " and ".join(f"{c[n]['shadow_mrays_per_s']:,.0f}" for c in committed)
    model = walk_profile("bench/results/walk-profile/bunny-1920x1080.txt")["shadow"]
    reversed_ = bunny["subgroups reversed"]["mrays"] / bunny["in order"]["mrays"]
    qhd, uhd = runs[("oracle-1440", 2560, 1440, "bunny")], runs[("oracle-4k", 3840, 2160, "bunny")]
    return {
        "@PASS6_MODEL@": (f"{model['longest_first']} against {model['in_order']} iterations, "
                          f"{model['in_order'] / model['longest_first']:.2f}x"),
        "@PASS6_MODEL_REVERSED@": (f"{model['in_order'] / model['reversed']:.2f}x predicted, "
                                   f"{reversed_:.2f}x measured"),
        "@PASS6_1440@": (f"{qhd['in order']['mrays']:,.0f} Mrays/s in dispatch order and "
                         f"{qhd['subgroups longest first']['mrays']:,.0f} longest first"),
        "@PASS6_4K@": f"{uhd['in order']['mrays']:,.0f} Mrays/s in dispatch order",
        "@PASS6_ORACLE@": rows.getvalue().strip(),
        "@PASS6_BUNNY_BEST@": f"{first['mrays']:,.0f} Mrays/s ({first['ms']:.4f} ms)",
        "@PASS6_BUNNY_NEEDED@": f"{rays / (TARGETS['shadow'] * 1e3):.4f} ms",
        "@PASS6_SHORT@": f"{TARGETS['shadow'] / first['mrays']:.2f}x",
        "@PASS6_BUNNY_GAIN@": f"{first['mrays'] / bunny['in order']['mrays']:.2f}x",
        "@PASS6_COMMITTED@": ", ".join(f"{n} {shadow(n)}" for n in ISSUE8_SCENES),
    }


def refill_values():
    """bench/gpu-run-refill.sh: dynamic ray fetch with the idle count taken every K steps and a
    refill once 1/S of the subgroup is idle, against the committed one ray per invocation."""
    rows = [(f"{label}, round {r}", f"{PASS6}/refill/{name}-{r}.json") for r in (1, 2)
            for label, name in [("one ray per invocation (committed)", "static")] +
            [(f"dynamic fetch, every {'step' if k == 1 else f'{k} steps'}, at 1/{d} idle",
              f"k{k}-s{d}") for k in (1, 4, 16) for d in (2, 4)]]
    counts = {(n, r[n]["hits"], r[n]["blocked"], r[n]["diffuse_hits"])
              for _, path in rows for r in [by_scene(path)] for n in ISSUE8_SCENES}
    assert len(counts) == len(ISSUE8_SCENES), "the refill variants traced other hits"
    static = [by_scene(f"{PASS6}/refill/static-{r}.json") for r in (1, 2)]
    best = lambda name: [by_scene(f"{PASS6}/refill/{name}-{r}.json") for r in (1, 2)]
    return {"@PASS6_REFILL@": rates_table("trace kernels, round", rows),
            "@PASS6_REFILL_FIRST@": change(best("k1-s2")[1], static[1]),
            "@PASS6_REFILL_BEST@": change(best("k16-s2")[1], static[1]),
            "@PASS6_REFILL_CADENCE@": change(best("k16-s2")[1], best("k1-s2")[1])}


LAVAPIPE6 = "bench/results/lavapipe-pass6"


def lavapipe6_values():
    """bench/cpu-run-pass6.sh: Embree and vkrt at three llvmpipe vector widths, two rounds; and
    against the fifth pass's machine (bench/results/vkrt-lavapipe-vs-embree.json), each tracer's
    primary rates here over its rates there."""
    widths = (("256", "vkrt, 256 bits (llvmpipe's own choice)"),
              ("512", "vkrt, 512 bits (LP_NATIVE_VECTOR_WIDTH=512)"),
              ("128", "vkrt, 128 bits (GALLIUM_OVERRIDE_CPU_CAPS=sse4.1)"))
    rows = []
    for r in (1, 2):
        rows.append((f"Embree 3, round {r}", f"{LAVAPIPE6}/embree-{r}.json"))
        rows += [(f"{label}, round {r}", f"{LAVAPIPE6}/vkrt-{w}-{r}.json") for w, label in widths]
    primary = lambda run: {n: run[n]["primary_mrays_per_s"] for n in ISSUE8_SCENES}
    embree = [primary(by_scene(f"{LAVAPIPE6}/embree-{r}.json")) for r in (1, 2)]
    vkrt = [primary(by_scene(f"{LAVAPIPE6}/vkrt-256-{r}.json")) for r in (1, 2)]
    before = json.load(open("bench/results/vkrt-lavapipe-vs-embree.json", encoding="utf-8"))
    then = {scene_of(r): r for r in before["rows"]}
    span = lambda xs: f"{min(xs):.2f}-{max(xs):.2f}x"
    ratio = lambda a, b: [a[n] / b[n] for n in ISSUE8_SCENES]
    then_rates = lambda tracer: {n: then[n][tracer]["primary_mrays_per_s"] for n in ISSUE8_SCENES}
    ours = [x for v in vkrt for x in ratio(v, then_rates("vkrt_bvh"))]
    theirs = [x for e in embree for x in ratio(e, then_rates("embree"))]
    machine = open(f"{LAVAPIPE6}/log.txt", encoding="utf-8").read().split("\n==")[0].strip()
    return {
        "@LAVAPIPE6_TABLE@": rates_table("tracer, round", rows, digits=2),
        "@LAVAPIPE6_RATIO@": "; ".join(
            f"round {r + 1}: " + ", ".join(f"{n} {x:.2f}x" for n, x in
                                           zip(ISSUE8_SCENES, ratio(vkrt[r], embree[r])))
            for r in (0, 1)),
        "@LAVAPIPE6_RANGE@": span([x for r in (0, 1) for x in ratio(vkrt[r], embree[r])]),
        "@LAVAPIPE6_VS_PASS5@": (f"vkrt's primary rays ran at {span(ours)} of the fifth pass's "
                                 f"and Embree's at {span(theirs)} of its"),
        "@LAVAPIPE6_PASS5_RATIO@": span([r["primary_ratio_auto"] for r in before["rows"]]),
        "@LAVAPIPE6_MACHINE@": machine,
    }


MESA25 = "bench/results/lavapipe-mesa25"


def mesa25_values():
    """Debian 12's lavapipe against Mesa 25.0's from bookworm-backports (bench/cpu-run-mesa25.sh),
    and each one's best primary rate over the two rounds against Embree's of the same day."""
    ways = (("4-nested", "4-wide, nested (the CPU default)"), ("2-one-loop", "pairs, one loop"))
    rows = [(f"Mesa {m / 10:.1f}, {label}, round {r}", f"{MESA25}/mesa{m // 10}-{way}-{r}.json")
            for r in (1, 2) for m in (223, 250) for way, label in ways]
    embree = by_scene("bench/results/embree-lavapipe.json")
    best = []
    for m in (22, 25):
        runs = [by_scene(f"{MESA25}/mesa{m}-{way}-{r}.json") for way, _ in ways for r in (1, 2)]
        best.append(f"Mesa {'22.3' if m == 22 else '25.0'}: " + ", ".join(
            f"{n} {max(x[n]['primary_mrays_per_s'] for x in runs) / embree[n]['primary_mrays_per_s']:.2f}x"
            for n in ISSUE8_SCENES))
    return {"@MESA25_TABLE@": rates_table("lavapipe, layout and walk, round", rows, digits=2),
            "@MESA25_BEST@": "; ".join(best)}


def variant_summary(name):
    """The machine line and the medians of a bench/cpu-run-variant.sh result."""
    lines = open(f"bench/results/lavapipe-variants/{name}.txt", encoding="utf-8").read().splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("median"))
    return "\n".join(lines[:2] + lines[start:])


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
    values.update(issue8_values())
    values.update(pass2_values())
    values.update(pass3_values())
    values.update(loads_values())
    values.update(walks_values())
    values.update(pass5_values())
    values.update(pass6_values())
    values.update(refill_values())
    values.update(lavapipe6_values())
    for key, value in values.items():
        text = text.replace(key, value)
    open("docs/performance.md", "w", encoding="utf-8").write(
        "<!-- Generated by tools/performance_doc.py from docs/performance.md.in and "
        "bench/results/: edit those. -->\n" + text)


if __name__ == "__main__":
    main()
