#!/usr/bin/env python3
"""s6_summary.py - the S6 tables of docs/studies.md from the studies' result.json.

Usage: tools/s6_summary.py OUT_DIR [OUT_DIR ...]
For each study: the core (mu = 1) value, the support (mu = 0) and the share of each
fuzzy input in the output's uncertainty (rho, influence analysis of the reduced form),
for R_n, R_t, R_ke, penetration_max [m], plastic_work [/ KE0] and contact_force_max [MN]; then the
evaluations, failures and model CPU seconds.
"""
import json
import sys

OUTPUTS = [("R_n", "R_n", 1), ("R_t", "R_t", 1), ("R_ke", "R_ke", 1), ("penetration_max", "depth [m]", 1),
           ("plastic_work", "W_p / KE0", 1), ("contact_force_max", "F_max [MN]", 1e-6)]


def rho(o, name):
    inf = o.get("influence", {})
    v = inf.get(name)
    if isinstance(v, dict):
        v = v.get("rho")
    return v


def table(path):
    d = json.load(open(path + "/result.json"))
    names = list(d["inputs"].keys())
    ev = d["evaluations"]
    print(f"### {d['name']} ({path}): {ev['evaluated']} evaluated, {ev['failed']} failed, "
          f"model CPU {ev['model_seconds']:.0f} s, wall {d['wall_seconds']:.0f} s")
    print("| output | core | support | " + " | ".join(names) + " |")
    print("|---" * (3 + len(names)) + "|")
    for key, label, scale in OUTPUTS:
        o = d["outputs"][key]
        core = o["lower"][-1] * scale
        sup = f"[{o['lower'][0] * scale:.3f}, {o['upper'][0] * scale:.3f}]"
        rs = " | ".join(f"{rho(o, n):.2f}" if rho(o, n) is not None else "-" for n in names)
        print(f"| {label} | {core:.3f} | {sup} | {rs} |")
    print()


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    for p in sys.argv[1:]:
        table(p)
