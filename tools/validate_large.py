#!/usr/bin/env python3
"""tools/validate_large.py - small strain against large deformation in the
axisymmetric elasto-plastic FE impact (docs/validation-plastic.md section 6e):
the same impacts with `--large-deformation off` and `on`, through
`rockfuzz impact --json`:
  A. granite sphere on a von Mises granite half-space at 10 m/s, V/V_y = 10,
     100, 1000 (Y from section 5), a/h = 5 and 10, absorbing, 10 r0;
  B. rigid boulder at 5 m/s on the soft Drucker-Prager + cap soil of
     section 6 (rho 1800, E 50 MPa, nu 0.3, c 5 kPa, phi 35, psi 5,
     X0 100 kPa, H_c 20 MPa), a/h = 3, 5, 8, default (fixed, automatic) domain;
  C. the same soil as a 0.5 m layer over granite, 10 and 20 m/s, a/h = 3.

Usage: tools/validate_large.py [rockfuzz-binary] [out-dir] [parts, e.g. ABC]
Writes out-dir/large_results.json, docs/img/plastic_large.png and prints the
markdown tables.  ~15 min of CPU on one core.
"""
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from validate_plastic import yield_for  # noqa: E402  (Y for a given V/V_y, section 5)

SRC = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = sys.argv[1] if len(sys.argv) > 1 else os.path.join(SRC, "build", "rockfuzz")
OUT = sys.argv[2] if len(sys.argv) > 2 else os.path.join(SRC, "build", "validation-large")
PARTS = sys.argv[3] if len(sys.argv) > 3 else "ABC"
os.makedirs(OUT, exist_ok=True)

SOIL = ["--density", "1800", "--E", "50e6", "--poisson", "0.3", "--material", "drucker_prager",
        "--cohesion", "5e3", "--friction-angle", "35", "--dilatancy-angle", "5",
        "--cap-pressure", "100e3", "--cap-hardening", "20e6"]


def soil(body):
    """The soil's options for body 'slope' or 'layer'."""
    return [a.replace("--", "--" + body + "-") if a.startswith("--") else a for a in SOIL]


def run(args, ld):
    cmd = ["nice", BIN, "impact", "--json", "--large-deformation", ld] + args
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    return json.loads(out)


def pair(args):
    r = {ld: run(args, ld) for ld in ("off", "on")}
    return r


def row(label, r):
    s, l = r["off"], r["on"]
    d = l["R_n"] / s["R_n"] - 1 if s["R_n"] else float("nan")
    return (f"| {label} | {s['R_n']:.4f} | {l['R_n']:.4f} | {100 * d:+.1f} % "
            f"| {1e3 * s['penetration_max']:.1f} / {1e3 * l['penetration_max']:.1f} "
            f"| {1e3 * s['indentation_depth']:.1f} / {1e3 * l['indentation_depth']:.1f} "
            f"| {s['plastic_work']:.3f} / {l['plastic_work']:.3f} "
            f"| {s['equivalent_plastic_strain_max']:.3f} / {l['equivalent_plastic_strain_max']:.3f} "
            f"| {s['energy_error']:.1e} / {l['energy_error']:.1e} "
            f"| {s['steps']} / {l['steps']} | {s['wall_seconds']:.1f} / {l['wall_seconds']:.1f} |")


HEAD = ("| case | R_n off | R_n on | dR_n/R_n | penetration mm off / on | crater mm off / on "
        "| W_p/KE off / on | eps_p max off / on | energy error off / on | steps off / on | wall s off / on |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|")


def main():
    res = {}
    path = os.path.join(OUT, "large_results.json")
    if os.path.exists(path):
        res = json.load(open(path))
    if "A" in PARTS:
        res["A"] = []
        for ratio in (10, 100, 1000):
            Y = yield_for(10.0, ratio)
            for ref in (5, 10):
                args = ["--velocity", "10", "--refinement", str(ref), "--domain-factor", "10",
                        "--boundary", "absorbing", "--slope-material", "von_mises", "--slope-yield", repr(Y)]
                res["A"].append({"ratio": ratio, "Y": Y, "ref": ref, "r": pair(args)})
                json.dump(res, open(path, "w"), indent=1)
    if "B" in PARTS:
        res["B"] = []
        for ref in (3, 5, 8):
            args = ["--boulder-material", "rigid", "--velocity", "5", "--refinement", str(ref)] + soil("slope")
            res["B"].append({"ref": ref, "r": pair(args)})
            json.dump(res, open(path, "w"), indent=1)
    if "C" in PARTS:
        res["C"] = []
        for V in (10, 20):
            for ref in (3,):
                args = ["--boulder-material", "rigid", "--velocity", str(V), "--refinement", str(ref),
                        "--layer-thickness", "0.5"] + soil("layer")
                try:
                    res["C"].append({"V": V, "ref": ref, "r": pair(args)})
                except subprocess.CalledProcessError as e:
                    res["C"].append({"V": V, "ref": ref, "failed": e.stderr})
                json.dump(res, open(path, "w"), indent=1)
    print(HEAD)
    for c in res.get("A", []):
        print(row(f"J2 V/V_y = {c['ratio']} (Y {c['Y'] / 1e6:.0f} MPa), a/h {c['ref']}", c["r"]))
    for c in res.get("B", []):
        print(row(f"soil 5 m/s, a/h {c['ref']}", c["r"]))
    for c in res.get("C", []):
        if "r" in c:
            print(row(f"0.5 m soil on granite {c['V']} m/s, a/h {c['ref']}", c["r"]))
        else:
            print(f"| 0.5 m soil on granite {c['V']} m/s | failed: {c['failed'].strip()} |")
    plot(res)


def plot(res):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    fig, ax = plt.subplots(figsize=(6, 4))
    for key, mark, lab in (("A", "o", "J2 sphere, 10 m/s"), ("B", "s", "rigid boulder on soil, 5 m/s"),
                           ("C", "^", "soil layer on granite")):
        xs, ys = [], []
        for c in res.get(key, []):
            if "r" not in c:
                continue
            s, l = c["r"]["off"], c["r"]["on"]
            xs.append(l["equivalent_plastic_strain_max"])
            ys.append(100 * abs(l["R_n"] - s["R_n"]) / max(abs(s["R_n"]), 1e-3))
        if xs:
            ax.loglog(xs, ys, mark, label=lab)
    ax.axhline(1, color="grey", lw=0.8, ls="--")
    ax.set_xlabel("largest equivalent plastic strain (large deformation)")
    ax.set_ylabel("|R_n(on) - R_n(off)| / R_n(off)  [%]")
    ax.legend(fontsize=8)
    ax.grid(True, which="both", lw=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(SRC, "docs", "img", "plastic_large.png"), dpi=110)


if __name__ == "__main__":
    main()
