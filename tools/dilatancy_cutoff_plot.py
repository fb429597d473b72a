#!/usr/bin/python3
"""tools/dilatancy_cutoff_plot.py - the figure of docs/validation-plastic.md
sections 8c-8d: the 117 kg block's drop tests on 1 m of dense sand (SWEEP-5..20
and JGGE24-s1 at 25.4 m/s) in several settings of the model.

Usage: /usr/bin/python3 tools/dilatancy_cutoff_plot.py DIR=LABEL [DIR=LABEL ...] [--img IMG-DIR]
DIR: an output of tools/drop_tests.sh (its drop_tests.jsonl), e.g. run without
and with DILATANCY_CUTOFF and FRICTION; LABEL its legend.  Draws
IMG-DIR/drop_tests_cutoff.png (default docs/img): penetration / r0 and peak
force against the impact speed, a failed run drawn as a cross at the bottom of
the panel.  Prints the points.
"""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

CASES = ["SWEEP-5", "SWEEP-10", "SWEEP-15", "SWEEP-20", "JGGE24-s1"]


def load(path):
    rows = {}
    with open(os.path.join(path, "drop_tests.jsonl")) as f:
        for line in f:
            d = json.loads(line)
            rows[d["case"]] = d
    return rows


def series(rows):
    """(speeds, penetration / r0, F_max kN, failed speeds) of CASES."""
    v, pen, force, failed = [], [], [], []
    for c in CASES:
        d = rows.get(c)
        if d is None:
            continue
        if "out" not in d:
            failed.append(d["velocity"])
            continue
        v.append(d["velocity"])
        pen.append(d["out"]["penetration_max"] / d["radius"])
        force.append(d["out"]["contact_force_max"] / 1e3)
    return v, pen, force, failed


def main():
    args, img = sys.argv[1:], "docs/img"
    if "--img" in args:
        k = args.index("--img")
        img = args[k + 1]
        del args[k:k + 2]
    if not args or any("=" not in a for a in args):
        sys.exit(__doc__)
    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    styles = ["o-", "s--", "^-.", "v:"]
    for k, arg in enumerate(args):
        path, label = arg.split("=", 1)
        v, pen, force, failed = series(load(path))
        print(label, "speeds", v, "penetration/r0", [round(p, 3) for p in pen],
              "F_max kN", [round(f) for f in force], "failed at", failed)
        line = ax[0].plot(v, pen, styles[k % len(styles)], label=label)[0]
        ax[1].plot(v, force, styles[k % len(styles)], color=line.get_color(), label=label)
        for a in ax:
            a.plot(failed, [0] * len(failed), "x", color=line.get_color(), markersize=10,
                   label=label + ": run failed" if failed else None)
    ax[0].axhline(1.0, color="grey", lw=0.8)
    ax[0].set_ylabel("penetration / r0")
    ax[1].set_ylabel("peak contact force (kN)")
    for a in ax:
        a.set_xlabel("impact speed (m/s)")
        a.legend(fontsize=8)
        a.grid(alpha=0.3)
    fig.suptitle("117 kg rigid block (r0 0.21 m) on 1 m of dense sand over concrete, a/h 3", fontsize=10)
    fig.tight_layout()
    os.makedirs(img, exist_ok=True)
    fig.savefig(os.path.join(img, "drop_tests_cutoff.png"), dpi=90)
    print("wrote", os.path.join(img, "drop_tests_cutoff.png"))


if __name__ == "__main__":
    main()
