#!/usr/bin/env python3
"""tools/s4_fem_tables.py - the S4 FE tables of docs/studies.md from the runs' result.json.

Usage: tools/s4_fem_tables.py OUT_DIR_30 OUT_DIR_45 OUT_DIR_60 (a missing dir is skipped)
Prints markdown rows: results (nominal, support at mu = 0, cut at mu = 1/3), the rho
rankings, the contact outputs and the cost (the sum of OUT_DIR/../logs/time_s4_A*.txt,
GNU time -v, if present; per run over all 289 requested points).  Every number comes from result.json; nothing is computed but unit changes.
"""
import glob
import json
import os
import re
import sys


def load(d):
    p = os.path.join(d, "result.json")
    return json.load(open(p)) if os.path.exists(p) else None


def cut_index(o):
    return [k for k, m in enumerate(o["mu"]) if abs(m - 1 / 3) < 1e-6][0]


def fuzzy(o, fmt, scale=1.0):
    j = cut_index(o)
    f = lambda v: format(v * scale, fmt)
    return (f"{f(o['nominal'])}, [{f(o['lower'][0])}, {f(o['upper'][0])}], "
            f"[{f(o['lower'][j])}, {f(o['upper'][j])}]")


def ranking(o, floor=0.01):
    inf = sorted(((v["rho"], k) for k, v in o["influence"].items()), reverse=True)
    return ", ".join(f"{k} {r:.2f}" if r >= 0.095 else f"{k} {r:.3f}"
                     for r, k in inf if r >= floor)


def angle(d):
    return d["name"].split("slope")[-1]


def cost(outdir, n):
    """Sum of the GNU time -v logs logs/time_s4_A*.txt (a resumed run has several)."""
    stem = os.path.basename(outdir.rstrip("/")).replace("_fem_slope", "_")
    files = sorted(glob.glob(os.path.join(os.path.dirname(outdir.rstrip("/")), "logs",
                                          f"time_{stem}*.txt")))
    if not files:
        return None
    wall = user = sys_ = 0.0
    for tf in files:
        t = open(tf).read()
        user += float(re.search(r"User time \(seconds\): ([\d.]+)", t).group(1))
        sys_ += float(re.search(r"System time \(seconds\): ([\d.]+)", t).group(1))
        w = re.search(r"Elapsed \(wall clock\) time.*: (?:(\d+):)?(\d+):([\d.]+)", t)
        wall += int(w.group(1) or 0) * 3600 + int(w.group(2)) * 60 + float(w.group(3))
    return wall, user, sys_, (user + sys_) / n


def main(dirs):
    runs = [(d, load(d)) for d in dirs]
    runs = [(d, r) for d, r in runs if r]
    print("| slope | R_n: nominal, support (μ = 0), cut at μ = 1/3 | R_t: nominal, support, cut at μ = 1/3 | R_ke: nominal, support, cut at μ = 1/3 |")
    print("|---|---|---|---|")
    for d, r in runs:
        o = r["outputs"]
        print(f"| {angle(r)}° | {fuzzy(o['R_n'], '.5f')} | {fuzzy(o['R_t'], '.4f')} | {fuzzy(o['R_ke'], '.4f')} |")
    print()
    print("| slope | ρ for R_n | ρ for R_t | ρ for R_ke |")
    print("|---|---|---|---|")
    for d, r in runs:
        o = r["outputs"]
        print(f"| {angle(r)}° | {ranking(o['R_n'])} | {ranking(o['R_t'])} | {ranking(o['R_ke'])} |")
    print()
    print("friction at the bounds (support lower/upper, cut 1/3 lower/upper):")
    for d, r in runs:
        for q in ("R_n", "R_t", "R_ke"):
            o = r["outputs"][q]
            j = cut_index(o)
            print(f"  {angle(r)} {q}: {o['x_lower'][0]['friction']:.3g} {o['x_upper'][0]['friction']:.3g}"
                  f" | {o['x_lower'][j]['friction']:.3g} {o['x_upper'][j]['friction']:.3g}")
    print()
    contact = [("contact_force_max", "F_max [MN]", ".1f", 1e-6),
               ("compression_max", "δ_max [mm]", ".2f", 1e3),
               ("contact_duration", "t_c [ms]", ".3f", 1e3),
               ("contact_radius", "contact radius [m]", ".4f", 1.0)]
    have = [c for c in contact if runs and c[0] in runs[0][1]["outputs"]]
    print("| slope | " + " | ".join(c[1] for c in have) + " |")
    print("|---|" + "---|" * len(have))
    for d, r in runs:
        o = r["outputs"]
        cells = []
        for k, _, fmt, s in have:
            x = o[k]
            cells.append(f"{x['nominal'] * s:{fmt}}, [{x['lower'][0] * s:{fmt}}, {x['upper'][0] * s:{fmt}}]")
        print(f"| {angle(r)}° | " + " | ".join(cells) + " |")
    for d, r in runs:
        print(f"  {angle(r)} contact rho: " + "; ".join(
            f"{k}: {ranking(r['outputs'][k], 0.005)}" for k, *_ in have))
    print()
    print("| slope | evaluations (failed) | wall (2 jobs) [s] | CPU user + sys [s] | CPU per run [s] | warnings |")
    print("|---|---|---|---|---|---|")
    for d, r in runs:
        e = r["evaluations"]
        c = cost(d, e["requested"])
        cs = f"{c[0]:.0f} | {c[1]:.0f} + {c[2]:.0f} | {c[3]:.2f}" if c else f"{r['wall_seconds']:.0f} | ? | ?"
        print(f"| {angle(r)}° | {e['evaluated']} ({e['failed']}; {e['from_store']} from store) | {cs} | {len(r['warnings'])} |")


if __name__ == "__main__":
    main(sys.argv[1:])
