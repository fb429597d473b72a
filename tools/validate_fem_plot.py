#!/usr/bin/python3
"""validate_fem_plot.py - figures and tables of docs/validation.md from the
output of tools/validate_fem.sh.

Usage: /usr/bin/python3 tools/validate_fem_plot.py [validation-dir] [img-dir]
Needs python3-matplotlib (Debian package; apt-get install python3-matplotlib).
"""
import csv
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


rows = [parse(l) for l in open(os.path.join(vdir, "results.txt")) if l.startswith("case=")]
rows = [r for r in rows if "F" in r]


def sel(case, **kw):
    out = []
    for r in rows:
        if r["case"] != case:
            continue
        if all(r.get(k) == v for k, v in kw.items()):
            out.append(r)
    return out


def hist(name):
    with open(os.path.join(vdir, name)) as f:
        rd = csv.DictReader(f)
        cols = {k: [] for k in rd.fieldnames}
        for row in rd:
            for k in cols:
                cols[k].append(float(row[k]))
    return {k: np.array(v) for k, v in cols.items()}


# ---------------- Hertz deviation vs a/R
H = sorted(sel("hertz"), key=lambda r: r["a_over_R"])
x = np.array([r["a_over_R"] for r in H])
fig, ax = plt.subplots(figsize=(7, 4.5))
for key, lab, m in [("dF", "max force", "o"), ("dd", "max compression", "s"), ("dt_c", "contact duration", "^"),
                    ("da", "contact radius", "D")]:
    ax.plot(x, [100 * r[key] for r in H], m + "-", label=lab)
xx = np.linspace(0, x.max() * 1.05, 50)
ax.plot(xx, -19 * xx, "k:", label="-19 a/R % (fem_notes, compression)")
ax.axhline(0, color="grey", lw=0.5)
for r in H:
    ax.annotate("%g m/s" % r["v"], (r["a_over_R"], 100 * r["dd"]), textcoords="offset points", xytext=(4, -12),
                fontsize=7)
ax.set_xlabel("a / R (Hertz contact radius / boulder radius)")
ax.set_ylabel("FE / Hertz - 1  [%]")
ax.set_title("FE vs Hertz, a/h = 10, absorbing boundary at 10 r0")
ax.legend(fontsize=8)
fig.tight_layout()
fig.savefig(os.path.join(img, "fem_hertz_deviation.png"), dpi=110)

print("\n### Hertz comparison (a/h = 10, absorbing, domain 10 r0)\n")
print("| v (m/s) | a/R | F_max | compression | duration | contact radius | penetration / compression |")
print("|---|---|---|---|---|---|---|")
for r in H:
    print("| %g | %.4f | %+.2f %% | %+.2f %% | %+.2f %% | %+.2f %% | %.1e |" % (
        r["v"], r["a_over_R"], 100 * r["dF"], 100 * r["dd"], 100 * r["dt_c"], 100 * r["da"], r["pen_rel"]))

# ---------------- force-time curves vs the exact Hertz ODE
def hertz_ode():
    # x'' = -(5/4) x^(3/2), x(0) = 0, x'(0) = 1 (units delta_max, delta_max / V)
    dt = 1e-4
    x, v, t = 0.0, 1.0, 0.0
    T, X = [0.0], [0.0]
    while True:
        def acc(xx):
            return -1.25 * max(xx, 0) ** 1.5
        k1x, k1v = v, acc(x)
        k2x, k2v = v + 0.5 * dt * k1v, acc(x + 0.5 * dt * k1x)
        k3x, k3v = v + 0.5 * dt * k2v, acc(x + 0.5 * dt * k2x)
        k4x, k4v = v + dt * k3v, acc(x + dt * k3x)
        x += dt / 6 * (k1x + 2 * k2x + 2 * k3x + k4x)
        v += dt / 6 * (k1v + 2 * k2v + 2 * k3v + k4v)
        t += dt
        if x < 0:
            break
        T.append(t)
        X.append(x)
    T = np.array(T)
    return T / T[-1], np.array(X) ** 1.5


tt, ff = hertz_ode()
fig, ax = plt.subplots(figsize=(7, 4.5))
ax.plot(tt, ff, "k-", lw=2.5, alpha=0.35, label="Hertz (exact ODE)")
ax.plot(tt, np.sin(np.pi * tt) ** 1.5, "k:", label="sin^{3/2}(pi t / t_c)")
for v in [1, 10, 30]:
    r = sel("hertz", v=float(v))[0]
    h = hist("hist_hertz_v%s.csv" % v)
    tH = r["tc"] / (1 + r["dt_c"])
    FH = r["F"] / (1 + r["dF"])
    ax.plot(h["t"] / tH, h["force"] / FH, label="FE %g m/s (a/R = %.3f)" % (v, r["a_over_R"]))
ax.set_xlabel("t / t_Hertz")
ax.set_ylabel("F / F_Hertz")
ax.set_xlim(0, 1.05)
ax.legend(fontsize=8)
ax.set_title("Contact force history, a/h = 10, absorbing boundary")
fig.tight_layout()
fig.savefig(os.path.join(img, "fem_force_time.png"), dpi=110)

# ---------------- convergence
print("\n### Mesh convergence (absorbing, domain 10 r0)\n")
print("| v | mesh | a/h | elements | steps | F_max (MN) | compression (mm) | duration (ms) | R_n | wall (s) |")
print("|---|---|---|---|---|---|---|---|---|---|")
fig, axs = plt.subplots(1, 3, figsize=(13, 4))
conv_summary = []
for i, v in enumerate([1.0, 10.0, 30.0]):
    ax = axs[i]
    for case, lab, ls in [("conv", "matching", "-"), ("convnm", "boulder 0.7 h", "--")]:
        C = sorted(sel(case, v=v), key=lambda r: r["ref"])
        if len(C) < 2:
            continue
        fin = C[-1]
        for r in C:
            print("| %g | %s | %g | %d | %d | %.4f | %.5f | %.5f | %.6f | %.1f |" % (
                v, lab, r["ref"], r["elems"], r["steps"], r["F"] / 1e6, r["delta"] * 1e3, r["tc"] * 1e3, r["Rn"],
                r["wall"]))
        refs = [r["ref"] for r in C[:-1]]
        for key, m in [("F", "o"), ("delta", "s"), ("tc", "^")]:
            ax.loglog(refs, [abs(r[key] / fin[key] - 1) + 1e-7 for r in C[:-1]], m + ls,
                      label="%s %s" % (key, lab))
        ax.loglog(refs, [abs(r["Rn"] - fin["Rn"]) + 1e-9 for r in C[:-1]], "x" + ls, label="R_n (abs) %s" % lab)
        a, b = C[-2], C[-1]
        conv_summary.append((v, lab, a["ref"], b["ref"], abs(b["F"] / a["F"] - 1), abs(b["delta"] / a["delta"] - 1),
                             abs(b["tc"] / a["tc"] - 1), abs(b["Rn"] - a["Rn"])))
    ax.axhline(2e-3, color="grey", lw=0.5)
    ax.axhline(1e-4, color="grey", lw=0.5, ls=":")
    ax.set_title("%g m/s: difference to the finest mesh" % v)
    ax.set_xlabel("a / h")
    if i == 0:
        ax.set_ylabel("relative (F, delta, t_c) / absolute (R_n)")
    ax.legend(fontsize=6)
fig.tight_layout()
fig.savefig(os.path.join(img, "fem_convergence.png"), dpi=110)
print("\n### Two finest meshes\n")
print("| v | mesh | a/h | F | compression | duration | R_n (abs) |")
print("|---|---|---|---|---|---|---|")
for s in conv_summary:
    print("| %g | %s | %g vs %g | %.3f %% | %.3f %% | %.3f %% | %.1e |" % (s[0], s[1], s[2], s[3], 100 * s[4],
                                                                       100 * s[5], 100 * s[6], s[7]))

# ---------------- energy account
fig, axs = plt.subplots(1, 2, figsize=(13, 4.5))
for ax, bc in zip(axs, ["fixed", "absorbing"]):
    h = hist("hist_%s_d10_v10.csv" % bc)
    ke0 = h["ke_boulder"][0] + h["se_boulder"][0] + h["ke_slope"][0] + h["se_slope"][0] + h["absorbed"][0] - \
        h["closure"][0]
    t = h["t"] * 1e3
    ax.plot(t, h["ke_boulder"] / ke0, label="kinetic, boulder")
    ax.plot(t, h["se_boulder"] / ke0, label="strain, boulder")
    ax.plot(t, h["ke_slope"] / ke0, label="kinetic, slope")
    ax.plot(t, h["se_slope"] / ke0, label="strain, slope")
    ax.plot(t, h["absorbed"] / ke0, label="absorbed by dashpots")
    ax.plot(t, 100 * h["closure"] / ke0, "k", label="closure error x 100")
    ax.set_xlabel("t (ms)")
    ax.set_ylabel("energy / KE0")
    ax.set_title("10 m/s, a/h = 10, %s boundary at 10 r0" % bc)
    ax.legend(fontsize=7)
fig.tight_layout()
fig.savefig(os.path.join(img, "fem_energy.png"), dpi=110)

# ---------------- R_n vs Hunter
c0 = math.sqrt(68.2e9 / 2600)
fig, ax = plt.subplots(figsize=(7, 4.5))
vv = np.logspace(-0.1, 1.55, 60)
for A, ls in [(1.04, ":"), (1.112, "--"), (1.171, "-.")]:
    ax.semilogx(vv, np.sqrt(1 - A * (vv / c0) ** 0.6), "k" + ls, lw=0.8, label="Hunter-type A = %g" % A)
print("\n### R_n against Hunter (a/h = 10)\n")
print("| v | fixed 10 r0 | fixed 40 r0 | absorbing 10 r0 | absorbing 40 r0 | Hunter A=1.04 | A=1.112 | A=1.171 |")
print("|---|---|---|---|---|---|---|---|")
series = {}
for r in sel("hunter"):
    series.setdefault((r["bc"], r["dom"]), []).append(r)
for (bc, dom), L in sorted(series.items()):
    L.sort(key=lambda r: r["v"])
    ax.semilogx([r["v"] for r in L], [r["Rn"] for r in L], "o-" if bc == "absorbing" else "s--",
                label="FE %s, %g r0" % (bc, dom))
for v in sorted({r["v"] for r in sel("hunter")}):
    vals = []
    for key in [("fixed", 10.0), ("fixed", 40.0), ("absorbing", 10.0), ("absorbing", 40.0)]:
        m = [r for r in series.get(key, []) if r["v"] == v]
        vals.append("%.5f" % m[0]["Rn"] if m else "-")
    hun = ["%.5f" % math.sqrt(1 - A * (v / c0) ** 0.6) for A in (1.04, 1.112, 1.171)]
    print("| %g | %s | %s |" % (v, " | ".join(vals), " | ".join(hun)))
ax.set_xlabel("impact speed (m/s)")
ax.set_ylabel("R_n")
ax.legend(fontsize=7)
ax.set_title("Normal COR: FE vs Hunter-type wave loss")
fig.tight_layout()
fig.savefig(os.path.join(img, "fem_restitution.png"), dpi=110)

# ---------------- spheroid, scale, dt scan, energy split
print("\n### Spheroid (10 m/s, a/h = 10, absorbing)\n")
print("| c | d | a/R (R = c^2/d) | contact radius | F_max | compression | duration | R_n |")
print("|---|---|---|---|---|---|---|---|")
for r in sel("spheroid"):
    print("| %g | %.4f | %.4f | %+.2f %% | %+.2f %% | %+.2f %% | %+.2f %% | %.6f |" % (
        r["c"], r["d"], r["a_over_R"], 100 * r["da"], 100 * r["dF"], 100 * r["dd"], 100 * r["dt_c"], r["Rn"]))
print("\n### Scale (10 m/s, a/h = 10, absorbing)\n")
for r in sel("scale"):
    print("- r0 = %g m: R_n = %.9f, duration = %.6e s, elements %d, steps %d" % (r["r0"], r["Rn"], r["tc"], r["elems"],
                                                                                r["steps"]))
print("\n### Time step: safety factor on the element eigenvalue bound\n")
for r in [r for r in open(os.path.join(vdir, "results.txt")) if r.startswith("case=dtscan")]:
    print("- " + r.strip()[:160])
print("\n### Energy split at the end (a/h = 10)\n")
print("| case | lost by boulder | slope (KE+strain) | absorbed | boulder vibration | lost - (slope + absorbed + vibration) |")
print("|---|---|---|---|---|---|")
for r in sorted(sel("hunter"), key=lambda r: (r["bc"], r["dom"], r["v"])):
    h = hist("hist_%s_d%g_v%g.csv" % (r["bc"], r["dom"], r["v"]))
    ke0 = h["ke_boulder"][0] + h["se_boulder"][0] + h["ke_slope"][0] + h["se_slope"][0] + h["absorbed"][0] - \
        h["closure"][0]
    ab = h["absorbed"][-1] / ke0
    print("| %g m/s %s %g r0 | %.4e | %.4e | %.4e | %.2e | %+.1e |" % (
        r["v"], r["bc"], r["dom"], r["lost"], r["slope_E"], ab, r["vib"], r["lost"] - r["slope_E"] - ab - r["vib"]))

# ---------------- mesh picture from the first VTK frame
vtu = os.path.join(vdir, "vtk", "fem_0000.vtu")
if os.path.exists(vtu):
    txt = open(vtu).read()
    pts = re.search(r"<Points>\s*<DataArray[^>]*>(.*?)</DataArray>", txt, re.S).group(1).split()
    P = np.array(pts, dtype=float).reshape(-1, 3)
    con = re.search(r'Name="connectivity"[^>]*>(.*?)</DataArray>', txt, re.S).group(1).split()
    Cn = np.array(con, dtype=int).reshape(-1, 4)
    body = re.search(r'Name="body"[^>]*>(.*?)</DataArray>', txt, re.S).group(1).split()
    from matplotlib.collections import PolyCollection
    fig, axs = plt.subplots(1, 2, figsize=(13, 6.5))
    for ax, lim in zip(axs, [(0, 10.5, -10.5, 2.2), (0, 0.9, -0.5, 0.9)]):
        polys = [P[c, :2] for c in Cn]
        cols = ["C0" if b == "0" else "C1" for b in body]
        ax.add_collection(PolyCollection(polys, facecolors="none", edgecolors=cols, linewidths=0.3))
        ax.set_xlim(lim[0], lim[1])
        ax.set_ylim(lim[2], lim[3])
        ax.set_aspect("equal")
        ax.set_xlabel("r (m)")
        ax.set_ylabel("z (m)")
    axs[0].set_title("whole mesh, 10 m/s, a/h = 5 (%d elements)" % len(Cn))
    axs[1].set_title("contact zone (Hertz a = 0.123 m)")
    fig.tight_layout()
    fig.savefig(os.path.join(img, "fem_mesh.png"), dpi=110)
print("\nfigures written to", img)
