#!/usr/bin/python3
"""tools/drop_tests_plot.py - the table and the figure of
docs/validation-plastic.md section 8 from tools/drop_tests.sh's output.

Usage: /usr/bin/python3 tools/drop_tests_plot.py OUT-DIR [IMG-DIR]
Reads OUT-DIR/drop_tests.jsonl, prints a markdown table (model outputs and a
validity verdict per case), and draws IMG-DIR/drop_tests.png (default
docs/img): contact duration and penetration of each case against the
measured contact-duration bands of Caviezel & Gerber (2018).

Verdict (what the model can be trusted with):
  ok         R_n > 0 (rebound at separation), penetration < 0.4 r0
  rest       the block came to rest in its crater (gravity; the rest rule,
             docs/validation-plastic.md section 11): R_n = 0, penetration < 0.4 r0
  deep       penetration >= 0.4 r0: the contact nears the edge of the paired
             boulder surface (0.5 r0 above its lowest point), an indication only
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


def verdict(d):
    if "error" in d:
        return "failed"
    o = d["out"]
    if o["penetration_max"] >= 0.4 * d["radius"]:
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

    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
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
    a.axhline(0.4, color="0.5", ls="--", lw=1)
    a.text(0, 0.42, "0.4 r0: near the edge of the paired boulder surface", fontsize=7, color="0.4")
    a.set_xticks(range(len(rows)))
    a.set_xticklabels([d["case"] for d in rows], rotation=90, fontsize=7)
    a.set_ylabel("penetration_max / r0 [-]")
    a.set_title("model penetration and verdict")
    a.legend(fontsize=7, loc="upper right")
    fig.tight_layout()
    os.makedirs(img, exist_ok=True)
    fig.savefig(os.path.join(img, "drop_tests.png"), dpi=90)
    print("wrote", os.path.join(img, "drop_tests.png"))


if __name__ == "__main__":
    main()
