#!/usr/bin/python3
"""architecture_plot.py - docs/img/architecture.png: the data flow of a study
and the stages of the FE core (docs/fem-internals.md).

Usage: /usr/bin/python3 tools/architecture_plot.py [img-dir]
"""
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import FancyBboxPatch  # noqa: E402

img = sys.argv[1] if len(sys.argv) > 1 else "docs/img"
os.makedirs(img, exist_ok=True)

fig, ax = plt.subplots(figsize=(11, 7.2))
ax.set_xlim(0, 11)
ax.set_ylim(0, 7.2)
ax.axis("off")


def box(x, y, w, h, title, body="", color="#dde8f5"):
    ax.add_patch(FancyBboxPatch((x, y), w, h, boxstyle="round,pad=0.03", fc=color, ec="#334", lw=0.9))
    ax.text(x + w / 2, y + h - 0.17, title, ha="center", va="top", fontsize=8.5, weight="bold")
    if body:
        ax.text(x + w / 2, y + h - 0.42, body, ha="center", va="top", fontsize=6.8, family="monospace")


def arrow(x0, y0, x1, y1, text=""):
    ax.annotate("", xy=(x1, y1), xytext=(x0, y0), arrowprops=dict(arrowstyle="->", lw=1.0, color="#333"))
    if text:
        ax.text((x0 + x1) / 2 + 0.05, (y0 + y1) / 2, text, fontsize=6.5, color="#444")


# the study pipeline, left column (top to bottom)
flow = [
    ("study", "src/study  study.h\nYAML -> rf_study"),
    ("TM", "src/tm  tm.h\nalpha-cuts, grids, cache"),
    ("runner", "src/study  runner.h\nthreads, MPI, SQLite store"),
    ("model", "src/model  model.h\nrf_model: x[] -> y[]"),
]
y = 6.2
for title, body in flow:
    box(0.3, y, 2.6, 0.8, title, body)
    if y < 6.2:
        arrow(1.6, y + 1.2, 1.6, y + 0.82)
    y -= 1.2
# outputs back up: analysis and report
box(0.3, 0.35, 2.6, 0.8, "analysis -> report", "src/tm analysis.h, src/study\nfuzzy outputs, influence,\nHTML/JSON/CSV, plots",
    color="#e8f0dc")
arrow(1.6, 2.6, 1.6, 1.17, "y[] -> retransformation")

# the impact model adapter
box(3.5, 2.6, 2.6, 1.6, "impact model", "src/model/impact_model.c\nimpact_model.h\nspec: solver + base input\n+ rf_fem_options\nrf_impact_solve (dispatch)\nbinding, identity, warnings",
    color="#f5e9d6")
arrow(2.92, 3.0, 3.48, 3.2)
# analytic solvers and the FE dispatch
box(6.6, 5.2, 2.1, 1.3, "analytic solvers", "src/impact\nHertz, Hunter,\nrigid oblique impact", color="#f5e9d6")
box(6.6, 3.2, 2.1, 1.5, "rf_fem_solve", "src/fem fem_dispatch.c\naxisymmetric or 3D\nfem_options.c: one\ndefault, one validation", color="#f5e9d6")
arrow(6.12, 3.9, 6.58, 5.5)
arrow(6.12, 3.6, 6.58, 3.9)

# FE core stages
stages = ["prepare: check, automatic settings", "sizing + mesh (fem_mesh / fem3d_mesh)",
          "assemble: masses, constraints, dashpots,\nkernels per body, contact pairs",
          "time step: 2/sqrt(lambda_max)",
          "loop: internal force (kernels) -> dashpots\n-> predictor -> contact -> energy -> stop",
          "extract: outputs, history, warnings"]
y = 2.55
box(6.3, 0.1, 4.5, 2.75, "FE core stages (fem_core.h)", "", color="#eeeeee")
for i, s in enumerate(stages):
    ax.text(6.45, y - 0.05 - i * 0.36, "%d. %s" % (i + 1, s), fontsize=6.6, va="top", family="monospace")
arrow(7.65, 3.18, 7.65, 2.87)
# material kernel
box(9.1, 3.2, 1.75, 1.5, "material kernels", "fem_kernel.h\nstiffness K_e (default)\nintegration points +\npoint law: linear;\nnext J2, DP-cap\n(src/material)", color="#fbe3e3")
ax.annotate("", xy=(9.5, 2.86), xytext=(9.8, 3.18), arrowprops=dict(arrowstyle="->", lw=1.0, color="#a33"))

# the problem, the low module
box(3.5, 0.35, 2.6, 1.5, "impact problem", "src/impact  impact.h\ninput + validation table\noutputs, Hertz reference,\nwave speeds", color="#dff0e8")
arrow(4.8, 2.58, 4.8, 1.87, "uses")
ax.annotate("", xy=(6.12, 1.3), xytext=(6.28, 1.3), arrowprops=dict(arrowstyle="->", lw=1.0, color="#333"))
ax.text(0.3, 0.05, "below everything: fem/ includes only impact.h (no model, TM, study headers)", fontsize=6.5,
        color="#444")
ax.set_title("rockfuzz: data flow of a study and the layers of the impact model", fontsize=10)
fig.tight_layout()
fig.savefig(os.path.join(img, "architecture.png"), dpi=110)
print("wrote", os.path.join(img, "architecture.png"))
