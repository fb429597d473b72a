#!/usr/bin/python3
"""tools/drop_tests_plot.py - the table and the figure of
docs/validation-plastic.md section 8 from tools/drop_tests.sh's output.

Usage: /usr/bin/python3 tools/drop_tests_plot.py OUT-DIR [IMG-DIR]
Reads OUT-DIR/drop_tests.jsonl, prints a markdown table (model outputs and a
validity verdict per case), and draws IMG-DIR/drop_tests.png (default
docs/img): contact duration and penetration of each case against the
measured contact-duration bands of Caviezel & Gerber (2018), and the sand
cases' peak force against the Japanese design formula for sand cushions
(orientation only; second table).

Verdict (what the model can be trusted with):
  ok         R_n > 0 (rebound at separation), penetration < r0
  rest       the block came to rest in its crater (gravity; the rest rule,
             docs/validation-plastic.md section 11): R_n = 0, penetration < r0
  deep       penetration >= r0: the block's equator has sunk below the original
             surface; the contact pairs cover the block's lower half (up to its
             equator, docs/validation-plastic.md section 6e), and soil that would
             fold over the top cannot be represented: an indication only
  not-ended  R_n < 0 without rest: the boulder still moves down when the run
             stops (runs without gravity, before section 10a)
  failed     the solver stopped with an error (message shown)
The table's g column is the gravity the run used (m/s^2; absent in old outputs: 0).
"""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

CG18_SHORT = (8e-3, 15e-3)  # s, Caviezel & Gerber (2018), abstract
CG18_LONG = (50e-3, 70e-3)
G = 9.81  # m/s^2, for the drop height of the design formula
LAMBDA_FORMULA = 1000.0  # kN/m^2: reproduces the computed table on co-jsp.co.jp (section 8)


def formula_force(d):
    """Japanese design formula for a rock on a sand cushion, in kN:
    P = 2.108 W^(2/3) lambda^(2/5) H^(3/5) (W weight in kN, lambda in kN/m^2,
    H = v^2 / (2 g) in m); orientation only (source and range not read)."""
    W = d["mass"] * G / 1e3
    H = d["velocity"] ** 2 / (2 * G)
    return 2.108 * W ** (2.0 / 3) * LAMBDA_FORMULA ** 0.4 * H ** 0.6


def verdict(d):
    if "error" in d:
        return "failed"
    o = d["out"]
    if o["penetration_max"] >= d["radius"]:
        return "deep"
    if o.get("at_rest"):
        return "rest"
    if not o["R_n"] > 0:
        return "not-ended"
    return "ok"


def main():
    out = sys.argv[1]
    img = sys.argv[2] if len(sys.argv) > 2 else "docs/img"
    rows = [json.loads(line) for line in open(os.path.join(out, "drop_tests.jsonl")) if line.strip()]
    print("| case | m kg | r0 m | v m/s | layer m | soil | g | R_n | penetration m (/r0) | crater m | F_max kN | t_c ms | W_p/KE | energy error | verdict |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for d in rows:
        head = "| %s | %g | %g | %g | %g | %s |" % (d["case"], d["mass"], d["radius"], d["velocity"], d["layer"], d["soil"])
        if "error" in d:
            msg = d["error"].replace("rockfuzz impact: fem solver failed: ", "")
            print(head + " – | – | – | – | – | – | – | – | failed: %s |" % msg.strip()[:70])
            continue
        o = d["out"]
        print(head + " %g | %.3f | %.3f (%.2f) | %.3f | %.0f | %.1f | %.3f | %.1e | %s |" % (
            o.get("gravity", 0), o["R_n"], o["penetration_max"], o["penetration_max"] / d["radius"], o["indentation_depth"],
            o["contact_force_max"] / 1e3, o["contact_duration"] * 1e3, o["plastic_work"], o["energy_error"],
            verdict(d)))

    sand = [d for d in rows if d["soil"].endswith("sand")]
    print()
    print("| case | H = v^2/2g m | model F_max kN | formula P (lambda = 1000 kN/m^2) kN | model / formula |")
    print("|---|---|---|---|---|")
    for d in sand:
        P = formula_force(d)
        F = d["out"]["contact_force_max"] / 1e3 if "error" not in d else float("nan")
        print("| %s | %.1f | %.0f | %.0f | %.2f |" % (d["case"], d["velocity"] ** 2 / (2 * G), F, P, F / P))

    fig, ax = plt.subplots(1, 3, figsize=(14, 4))
    marks = {"ok": ("o", "tab:green"), "rest": ("D", "tab:blue"), "deep": ("s", "tab:orange"),
             "not-ended": ("v", "tab:red"), "failed": ("x", "k")}
    a = ax[0]
    a.axhspan(*(1e3 * x for x in CG18_SHORT), color="0.85", label="measured, short contacts (CG18)")
    a.axhspan(*(1e3 * x for x in CG18_LONG), color="0.7", label="measured, long contacts (CG18)")
    for i, d in enumerate(rows):
        if "error" in d:
            a.plot(i, 1, "x", color="k")
            continue
        mk, col = marks[verdict(d)]
        a.plot(i, 1e3 * d["out"]["contact_duration"], mk, color=col)
    a.set_xticks(range(len(rows)))
    a.set_xticklabels([d["case"] for d in rows], rotation=90, fontsize=7)
    a.set_ylabel("contact duration t_c [ms]")
    a.set_title("model t_c (symbols) vs field contacts")
    a.legend(fontsize=7, loc="upper left")
    a = ax[1]
    for v in sorted(marks):
        a.plot([], [], marks[v][0], color=marks[v][1], label=v)
    for i, d in enumerate(rows):
        if "error" in d:
            a.plot(i, 0, "x", color="k")
            continue
        mk, col = marks[verdict(d)]
        a.plot(i, d["out"]["penetration_max"] / d["radius"], mk, color=col)
    a.axhline(1.0, color="0.5", ls="--", lw=1)
    a.text(0, 1.02, "r0: equator below the surface", fontsize=7, color="0.4")
    a.set_xticks(range(len(rows)))
    a.set_xticklabels([d["case"] for d in rows], rotation=90, fontsize=7)
    a.set_ylabel("penetration_max / r0 [-]")
    a.set_title("model penetration and verdict")
    a.legend(fontsize=7, loc="upper right")
    a = ax[2]
    for d in sand:
        if "error" in d:
            continue
        mk, col = marks[verdict(d)]
        a.loglog(formula_force(d), d["out"]["contact_force_max"] / 1e3, mk, color=col)
        a.annotate(d["case"], (formula_force(d), d["out"]["contact_force_max"] / 1e3), fontsize=6)
    lim = [50, 5e4]
    a.loglog(lim, lim, "k--", lw=1, label="model = formula")
    a.set_xlabel("design formula P, lambda = 1000 kN/m^2 [kN]")
    a.set_ylabel("model F_max [kN]")
    a.set_title("sand cases vs the Japanese design formula\n(orientation only: not a measurement)", fontsize=9)
    a.legend(fontsize=7, loc="upper left")
    fig.tight_layout()
    os.makedirs(img, exist_ok=True)
    fig.savefig(os.path.join(img, "drop_tests.png"), dpi=90)
    print("wrote", os.path.join(img, "drop_tests.png"))


if __name__ == "__main__":
    main()
