#!/usr/bin/env python3
"""Collects every measurement in results/bench-*.txt that the binary logged with its CPU-pressure
figures and keeps the clean ones: the machine ≤ 10 % busy in the second before, and CPU pressure
(some task of the machine waiting for a CPU) < 10 % of the trace's wall time. Prints median and
range of those, per library."""
import glob, re, statistics
pat = re.compile(r"rep (\d+) (\S+)\s+build\s+([\d.]+) ms\s+trace\s+([\d.]+) s \(\s*[\d.]+ Mrays/s, cpu\s+([\d.]+) s\)\s+busy before (\d+)%\s+cpu-pressure build (\d+)% trace (\d+)%")
rows = {}
allrows = {}
for f in sorted(glob.glob("results/bench-*.txt")):
    for line in open(f):
        m = pat.search(line)
        if not m:
            continue
        _, lib, b, t, cpu, busy, pb, pt = m.groups()
        allrows.setdefault(lib, []).append(1)
        if int(busy) <= 10 and int(pt) < 10:
            rows.setdefault(lib, []).append((float(b), float(t), float(cpu), f))
N = 4194304
print("| library | clean runs (of all) | build ms median (min–max) | trace s, 2 threads, median (min–max) | Mrays/s (median) | trace CPU s median (min–max) |")
print("|---|---|---|---|---|---|")
for lib, r in rows.items():
    b = [x[0] for x in r]; t = [x[1] for x in r]; c = [x[2] for x in r]
    med = statistics.median
    print(f"| {lib} | {len(r)} ({len(allrows[lib])}) | {med(b):.0f} ({min(b):.0f}–{max(b):.0f}) | {med(t):.3f} ({min(t):.3f}–{max(t):.3f}) | {N/med(t)/1e6:.2f} | {med(c):.2f} ({min(c):.2f}–{max(c):.2f}) |")
