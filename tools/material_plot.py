#!/usr/bin/python3
"""material_plot.py - the figures of docs/materials.md: stress paths of the
`rockfuzz material` driver (markers, --history) against the closed forms
(lines) of the same document.

Usage: /usr/bin/python3 tools/material_plot.py [rockfuzz-binary] [img-dir]
Needs python3-matplotlib (Debian package).
"""
import csv
import io
import math
import os
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

binary = sys.argv[1] if len(sys.argv) > 1 else "build/rockfuzz"
img = sys.argv[2] if len(sys.argv) > 2 else "docs/img"
os.makedirs(img, exist_ok=True)


def history(*args):
    out = subprocess.run([binary, "material", *args, "--history"], check=True,
                         capture_output=True, text=True).stdout
    rows = list(csv.DictReader(io.StringIO(out)))
    return {k: [float(r[k]) for r in rows] for k in rows[0]}


def moduli(E, nu):
    return E / (2 * (1 + nu)), E / (3 * (1 - 2 * nu))


def cone(phi):
    s = math.sin(math.radians(phi))
    return 6 * s / (math.sqrt(3) * (3 - s)), 6 * math.cos(math.radians(phi)) / (math.sqrt(3) * (3 - s))


def sqrt_j2(h, i):
    sx, sy, sz, txy = h["stress_xx"][i], h["stress_yy"][i], h["stress_zz"][i], h["stress_xy"][i]
    return math.sqrt(((sx - sy) ** 2 + (sy - sz) ** 2 + (sz - sx) ** 2) / 6 + txy ** 2)


def j2_figure():
    E, nu, Y, H = 200e9, 0.3, 250e6, 20e9
    G, K = moduli(E, nu)
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10.5, 4.2))
    eps = [i * 1e-5 for i in range(0, 801)]
    for hard, col in ((0.0, "C0"), (H, "C1")):
        def closed(e):
            ep = max(0.0, (2 * G * e - Y) / (3 * G + hard))
            q = 2 * G * e - 3 * G * ep
            return K * e + 2 / 3 * q, q
        for ax, k in ((a1, 0), (a2, 1)):
            ax.plot([e * 100 for e in eps], [closed(e)[k] / 1e6 for e in eps], col, lw=1.2,
                    label=f"closed form, H = {hard / 1e9:g} GPa")
        for n, mk in ((8, "o"), (80, "x")):
            args = ["--model", "von_mises", "--E", str(E), "--poisson", str(nu), "--yield", str(Y),
                    "--hardening", str(hard), "--path", "uniaxial_strain", "--strain", "0.008",
                    "--increments", str(n)]
            h = history(*args)
            x = [s * 100 for s in h["strain"]]
            lab = f"driver, {n} increments" if hard == 0 else None
            a1.plot(x, [s / 1e6 for s in h["stress_xx"]], mk, color=col, ms=4, mfc="none", label=lab)
            a2.plot(x, [(a - b) / 1e6 for a, b in zip(h["stress_xx"], h["stress_yy"])], mk, color=col, ms=4,
                    mfc="none", label=lab)
    ey = Y / (2 * G)
    for ax in (a1, a2):
        ax.axvline(ey * 100, color="0.6", ls=":", lw=1)
        ax.set_xlabel("uniaxial strain $\\varepsilon_{xx}$ [%]")
        ax.legend(fontsize=8)
    a1.annotate("elastic limit $Y(1-\\nu)/(1-2\\nu)$", (ey * 100, Y * (1 - nu) / (1 - 2 * nu) / 1e6),
                xytext=(0.25, 900), arrowprops=dict(arrowstyle="->", color="0.4"), fontsize=8)
    a1.set_ylabel("$\\sigma_{xx}$ [MPa]")
    a2.set_ylabel("$\\sigma_{xx} - \\sigma_{yy}$ [MPa]  (= Y + H $\\varepsilon_p$ once plastic)")
    a2.set_ylim(0, 350)
    fig.suptitle("von Mises, uniaxial strain (E = 200 GPa, $\\nu$ = 0.3, Y = 250 MPa)", fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(img, "material_j2_uniaxial.png"), dpi=120)


def dp_figure():
    E, nu, c, phi = 30e6, 0.3, 2e3, 35
    X0, Hc = 50e3, 5e6
    G, K = moduli(E, nu)
    eta, xi = cone(phi)
    base = ["--model", "drucker_prager", "--E", str(E), "--poisson", str(nu), "--cohesion", str(c),
            "--friction-angle", str(phi)]
    cap = ["--cap-pressure", str(X0), "--cap-hardening", str(Hc)]
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10.5, 4.3))
    # p - sqrt(J2) plane, compression to the left.
    p_apex = xi * c / eta
    ps = [p_apex - i * 1e3 for i in range(0, 141)]
    a1.plot([p / 1e3 for p in ps], [(xi * c - eta * p) / 1e3 for p in ps], "k", lw=1.2,
            label="cone (outer, matched to Mohr-Coulomb)")
    paths = [
        ("simple shear from p0 = -60 kPa", base + ["--path", "simple_shear", "--strain", "0.03",
                                                   "--initial-mean-stress", "-6e4"], "C0"),
        ("hydrostatic tension -> apex", base + ["--path", "hydrostatic", "--strain", "2e-4"], "C2"),
        ("confined compression, cone only", base + ["--path", "uniaxial_strain", "--strain", "-0.01"], "C3"),
        ("confined compression, with cap", base + cap + ["--path", "uniaxial_strain", "--strain", "-0.01"],
         "C1"),
    ]
    results = {}
    for label, args, col in paths:
        h = history(*args, "--increments", "40")
        results[label] = h
        a1.plot([p / 1e3 for p in h["mean_stress"]], [sqrt_j2(h, i) / 1e3 for i in range(len(h["strain"]))],
                ".-", color=col, ms=4, lw=0.8, label=label)
        a1.plot([0 if "p0" not in label else -60], [0], "o", color=col, ms=3)
    h = results["confined compression, with cap"]
    X_end = -h["mean_stress"][-1]
    a1.plot([-X0 / 1e3] * 2, [0, (xi * c + eta * X0) / 1e3], "C1--", lw=1, label="initial cap $p = -X_0$")
    a1.plot([-X_end / 1e3] * 2, [0, (xi * c + eta * X_end) / 1e3], "C1:", lw=1, label="final (hardened) cap")
    a1.set_xlabel("mean stress p [kPa] (tension > 0)")
    a1.set_ylabel("$\\sqrt{J_2}$ [kPa]")
    a1.set_xlim(-140, 10)
    a1.set_ylim(0, 130)
    a1.set_title(f"Drucker-Prager, c = {c / 1e3:g} kPa, $\\phi$ = {phi}°, $\\nu$ = {nu}", fontsize=9)
    a1.legend(fontsize=7, loc="upper right")
    # Oedometer: sigma_xx and p against the closed forms.
    S = [i * 1e-4 for i in range(0, 101)]

    def closed(s):
        if K * s <= X0:
            return -(K + 4 * G / 3) * s, -K * s
        ec = (K * s - X0) / (K + Hc)
        X = X0 + Hc * ec
        sj2 = min(2 * G * s / math.sqrt(3), xi * c + eta * X)
        return -X - 2 / math.sqrt(3) * sj2, -X
    a2.plot([s * 100 for s in S], [-(K + 4 * G / 3) * s / 1e3 for s in S], "C3", lw=1.2,
            label="$\\sigma_{xx}$ closed form, cone only (elastic)")
    a2.plot([s * 100 for s in S], [closed(s)[0] / 1e3 for s in S], "C1", lw=1.2,
            label="$\\sigma_{xx}$ closed form, with cap")
    a2.plot([s * 100 for s in S], [closed(s)[1] / 1e3 for s in S], "C1--", lw=1, label="p closed form, with cap")
    for label, col in (("confined compression, cone only", "C3"), ("confined compression, with cap", "C1")):
        h = results[label]
        a2.plot([-s * 100 for s in h["strain"]], [s / 1e3 for s in h["stress_xx"]], "o", color=col, ms=3.5,
                mfc="none")
    h = results["confined compression, with cap"]
    a2.plot([-s * 100 for s in h["strain"]], [s / 1e3 for s in h["mean_stress"]], "x", color="C1", ms=3.5,
            label="driver (40 increments)")
    a2.set_xlabel("compressive uniaxial strain $-\\varepsilon_{xx}$ [%]")
    a2.set_ylabel("stress [kPa]")
    a2.set_title(f"confined compression; cap X0 = {X0 / 1e3:g} kPa, H_c = {Hc / 1e6:g} MPa", fontsize=9)
    a2.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(img, "material_dp_paths.png"), dpi=120)


j2_figure()
dp_figure()
print("wrote", os.path.join(img, "material_j2_uniaxial.png"), os.path.join(img, "material_dp_paths.png"))
