#!/usr/bin/env python3
"""The summary table of research/results/bvh-build-subnormal-2core.txt from its runs: min and median processor ms of
old and new per scene and thread count.   usage: bvh-build-subnormal-2core-table.py RUNS.txt"""
import re, sys, collections
d = collections.defaultdict(list)
loads = collections.defaultdict(list)
cur = None
for line in open(sys.argv[1]):
    m = re.match(r'== (old|new) (\S+) threads=(\d+) round (\d+) load (\S+)', line)
    if m:
        cur = (m.group(2), m.group(3), m.group(1)); loads[cur[:2]].append(float(m.group(5))); continue
    m = re.search(r'processor ([0-9.]+) ms', line)
    if m and cur:
        d[cur].append(float(m.group(1)))
print("| scene | threads | runs | old: min / median processor ms | new: min / median | old / new (min) | load (1-min) |")
print("|---|---:|---:|---:|---:|---:|---|")
for key in sorted({k[:2] for k in d}, key=lambda k: (int(k[1]), k[0])):
    o, n = sorted(d[key + ('old',)]), sorted(d[key + ('new',)])
    if not o or not n: continue
    med = lambda v: v[len(v)//2]
    r = f"{o[0]/n[0]:.2f}" if n[0] > 0 else "-"
    print(f"| {key[0]} | {key[1]} | {len(o)} + {len(n)} | {o[0]:,.1f} / {med(o):,.1f} | {n[0]:,.1f} / {med(n):,.1f} | {r} | {min(loads[key]):.1f}-{max(loads[key]):.1f} |")
