#!/usr/bin/python3
"""validate_fem_domain_plot.py - docs/img/fem_restitution.png and the tables
of docs/validation.md section 8 from tools/validate_fem_domain.sh: R_n of the
fixed and absorbing boundaries at 10 and 40 r0 and of the default
(automatic, fixed) domain against Hunter-type wave loss.

Usage: /usr/bin/python3 tools/validate_fem_domain_plot.py [validation-dir] [img-dir]
"""
import math
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

vdir = sys.argv[1] if len(sys.argv) > 1 else "build-fem/validation"
img = sys.argv[2] if len(sys.argv) > 2 else "docs/img"
os.makedirs(img, exist_ok=True)


def parse(line):
    d = {}
    for k, v in re.findall(r'(\w+)=("[^"]*"|\S+)', line):
        v = v.strip('"')
        try:
            d[k] = float(v)
        except ValueError:
            d[k] = v
    return d


rows = [parse(l) for l in open(os.path.join(vdir, "results_domain.txt")) if l.startswith("case=")]
rows = [r for r in rows if "Rn" in r]


def key(r):
    return "automatic" if r.get("auto", 0) == 1 else "%s %g r0" % (r["bc"], r["dom"])


c0 = math.sqrt(68.2e9 / 2600)
fig, ax = plt.subplots(figsize=(7, 4.5))
vv = np.logspace(-0.1, 1.55, 60)
for A, ls in [(1.04, ":"), (1.112, "--"), (1.171, "-.")]:
    ax.semilogx(vv, np.sqrt(1 - A * (vv / c0) ** 0.6), "k" + ls, lw=0.8, label="Hunter-type A = %g" % A)
series = {}
for r in rows:
    series.setdefault(key(r), []).append(r)
style = {"fixed 10 r0": "s--", "fixed 40 r0": "s-", "absorbing 10 r0": "o--", "absorbing 40 r0": "o-",
         "automatic": "D-"}
for k in ["fixed 10 r0", "absorbing 10 r0", "fixed 40 r0", "absorbing 40 r0", "automatic"]:
    L = sorted(series.get(k, []), key=lambda r: r["v"])
    if not L:
        continue
    label = "FE " + (k if k != "automatic" else "default: fixed, automatic domain (%s r0)" %
                     "/".join("%g" % r["dom"] for r in L))
    ax.semilogx([r["v"] for r in L], [r["Rn"] for r in L], style[k], ms=4 if k != "automatic" else 6,
                mfc="none" if k == "automatic" else None, label=label)
ax.set_xlabel("impact speed (m/s)")
ax.set_ylabel("R_n")
ax.legend(fontsize=7)
ax.set_title("Normal COR: FE (a/h = 10) vs Hunter-type wave loss")
fig.tight_layout()
fig.savefig(os.path.join(img, "fem_restitution.png"), dpi=110)

cols = ["fixed 10 r0", "fixed 40 r0", "absorbing 10 r0", "absorbing 40 r0", "automatic"]
print("### R_n against Hunter (a/h = 10)\n")
print("| v | " + " | ".join(cols) + " (domain) | Hunter A=1.04 | A=1.112 | A=1.171 |")
print("|---" * (len(cols) + 4) + "|")
for v in sorted({r["v"] for r in rows}):
    vals = []
    for k in cols:
        m = [r for r in series.get(k, []) if r["v"] == v]
        vals.append(("%.5f" % m[0]["Rn"] + (" (%g r0)" % m[0]["dom"] if k == "automatic" else "")) if m else "-")
    hun = ["%.5f" % math.sqrt(1 - A * (v / c0) ** 0.6) for A in (1.04, 1.112, 1.171)]
    print("| %g | %s | %s |" % (v, " | ".join(vals), " | ".join(hun)))
print("\n### wave loss 1 - R_n^2 and A_FE = (1 - R_n^2) / (v/c0)^(3/5); cost\n")
print("| v | model | 1 - R_n^2 | A_FE | 1.112 (F/F_H)^2 (t_H/t_c) | elements | steps | wall (s) | warning |")
print("|---|---|---|---|---|---|---|---|---|")
for v in sorted({r["v"] for r in rows}):
    for k in cols:
        for r in [r for r in series.get(k, []) if r["v"] == v]:
            loss = 1 - r["Rn"] ** 2
            pulse = 1.112 * (1 + r["dF"]) ** 2 / (1 + r["dt_c"])
            name = k if k != "automatic" else "automatic (%g r0)" % r["dom"]
            print("| %g | %s | %.5f | %.3f | %.3f | %d | %d | %.2f | %s |" % (
                v, name, loss, loss / (v / c0) ** 0.6, pulse, r["elems"], r["steps"], r["wall"],
                "reflection" if "reflected" in str(r.get("warning", "")) else ""))
