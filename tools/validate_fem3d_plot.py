#!/usr/bin/python3
"""validate_fem3d_plot.py - plots of docs/validation-3d.md from the output of
tools/validate_fem3d.sh.
Usage: validate_fem3d_plot.py results-dir [img-dir=docs/img]
Writes fem3d_sweep.png (R_t and spin against f over rigid-body theory and the
two-degree-of-freedom spring models), fem3d_energy.png (energy account of the
45 degree, f = 0.6 impact), fem3d_conv.png (mesh convergence on 45 degrees)."""
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fem3d_stick_ode as ode  # noqa: E402


def load(path):
    rows = []
    for line in open(path):
        d = {}
        for tok in line.split():
            if "=" in tok:
                k, v = tok.split("=", 1)
                try:
                    d[k] = float(v)
                except ValueError:
                    d[k] = v
        if "case" in d and "Rn" in d:
            rows.append(d)
    return rows


def rigid(alpha_deg, f, e_n, V=10.0, r=1.0):
    a = math.radians(alpha_deg)
    vn, vt = V * math.cos(a), V * math.sin(a)
    if f * (1 + e_n) * vn < 2 / 7 * vt:  # gross sliding
        return 1 - f * (1 + e_n) / math.tan(a), 2.5 * f * (1 + e_n) * vn / r
    return 5 / 7, 5 / 7 * vt / r


def main():
    res = sys.argv[1]
    img = sys.argv[2] if len(sys.argv) > 2 else "docs/img"
    os.makedirs(img, exist_ok=True)
    rows = load(os.path.join(res, "results.txt"))

    # --- sweep: R_t and omega r / v_t against f
    sweep = [d for d in rows if d["case"] == "sweep"]
    if sweep:
        fig, ax = plt.subplots(2, 3, figsize=(13, 7), sharex=True)
        for j, al in enumerate((30, 45, 60)):
            pts = sorted([d for d in sweep if abs(d["angle"] - al) < 1e-9], key=lambda d: d["f"])
            if not pts:
                continue
            vt = 10 * math.sin(math.radians(al))
            fs = [d["f"] for d in pts]
            en = pts[0]["Rn"]
            fl = [x / 100 for x in range(0, 101)] + [1.5, 2, 3, 4, 5]
            rt = [rigid(al, f, en) for f in fl]
            ax[0][j].plot(fl, [x[0] for x in rt], "k-", label="rigid body (4.1), FE e_n")
            ax[1][j].plot(fl, [x[1] / vt for x in rt], "k-", label="rigid body (4.1)")
            fo = [0.05, 0.1, 0.15, 0.2, 0.3, 0.45, 0.6, 0.8, 1.0, 2.0, 5.0]
            for law, sty in (("incremental", "b--"), ("secant", "g:")):
                o = [ode.run(al, 10, law, f) for f in fo]
                ax[0][j].plot(fo, [x[0] for x in o], sty, label=f"spring + Coulomb, {law}")
                ax[1][j].plot(fo, [x[1] / vt for x in o], sty, label=f"spring + Coulomb, {law}")
            ax[0][j].plot(fs, [d["Rt"] for d in pts], "ro", label="3D FE")
            ax[1][j].plot(fs, [d["w"] / vt for d in pts], "ro", label="3D FE")
            ax[0][j].set_title(f"slope {al} deg, V = 10 m/s")
            ax[1][j].set_xlabel("friction coefficient f")
            ax[0][j].set_xscale("symlog", linthresh=1)
            ax[0][j].grid(True, alpha=0.3)
            ax[1][j].grid(True, alpha=0.3)
        ax[0][0].set_ylabel("R_t = v_t'/v_t")
        ax[1][0].set_ylabel("omega' r / v_t")
        ax[0][0].legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(os.path.join(img, "fem3d_sweep.png"), dpi=110)
        plt.close(fig)

    # --- energy account of the 45 deg, f = 0.6 impact
    hp = os.path.join(res, "hist_45_f06.csv")
    if os.path.exists(hp):
        import csv

        h = list(csv.DictReader(open(hp)))
        t = [1e3 * float(x["t"]) for x in h]
        ke0 = float(h[0]["ke_b"]) + float(h[0]["ke_s"])
        fig, ax = plt.subplots(1, 2, figsize=(12, 4.5))
        for key, lab in (("ke_b", "boulder kinetic"), ("se_b", "boulder strain"), ("ke_s", "slope kinetic"),
                         ("se_s", "slope strain"), ("friction", "frictional work")):
            ax[0].plot(t, [float(x[key]) / ke0 for x in h], label=lab)
        ax[0].set_xlabel("t [ms]")
        ax[0].set_ylabel("energy / KE0")
        ax[0].legend(fontsize=8)
        ax[0].grid(True, alpha=0.3)
        ax[0].set_title("45 deg, f = 0.6, a/h = 6")
        ax[1].plot(t, [float(x["closure"]) / ke0 for x in h], label="closure (KE + strain + friction - KE0)")
        ax[1].plot(t, [float(x["contact_work"]) / ke0 for x in h], label="normal contact work")
        ax[1].set_xlabel("t [ms]")
        ax[1].set_ylabel("/ KE0")
        ax[1].legend(fontsize=8)
        ax[1].grid(True, alpha=0.3)
        fig.tight_layout()
        fig.savefig(os.path.join(img, "fem3d_energy.png"), dpi=110)
        plt.close(fig)

    # --- mesh convergence on 45 deg, f = 0.6
    conv = sorted([d for d in rows if d["case"] == "conv"], key=lambda d: d["ref"])
    if conv:
        fig, ax = plt.subplots(1, 3, figsize=(13, 4))
        x = [d["ref"] for d in conv]
        ax[0].plot(x, [d["Rt"] for d in conv], "ro-", label="R_t")
        ax[0].plot(x, [d["Rke"] for d in conv], "bs-", label="R_ke")
        ax[0].plot(x, [d["Rn"] for d in conv], "g^-", label="R_n")
        ax[0].set_xlabel("a/h")
        ax[0].legend()
        ax[0].grid(True, alpha=0.3)
        ax[1].plot(x, [d["w"] for d in conv], "ro-")
        ax[1].set_xlabel("a/h")
        ax[1].set_ylabel("omega' [rad/s]")
        ax[1].grid(True, alpha=0.3)
        ax[2].plot(x, [d["F"] / 1e6 for d in conv], "ko-")
        ax[2].set_xlabel("a/h")
        ax[2].set_ylabel("max normal force [MN]")
        ax[2].grid(True, alpha=0.3)
        fig.suptitle("mesh convergence, 45 deg slope, f = 0.6, V = 10 m/s")
        fig.tight_layout()
        fig.savefig(os.path.join(img, "fem3d_conv.png"), dpi=110)
        plt.close(fig)


if __name__ == "__main__":
    main()
