#!/usr/bin/python3
"""validate_mdr_plot.py - plots of docs/validation-mdr.md from tools/validate_mdr.sh output.

Usage: /usr/bin/python3 tools/validate_mdr_plot.py OUT_DIR IMG_DIR
Reads OUT_DIR/{published,sweep,gap}.txt (lines "case=<tag> key=value ...") and
tools/data/chung_ooi_2011.txt; writes IMG_DIR/mdr_published.png, mdr_fe_sweep.png,
mdr_gap.png (those whose input exists) and prints the tables quoted in the docs.
"""
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))


def read_runs(path):
    runs = []
    if not os.path.exists(path):
        return runs
    for line in open(path):
        d = {}
        for tok in line.split():
            if "=" in tok:
                k, v = tok.split("=", 1)
                try:
                    d[k] = float(v)
                except ValueError:
                    d[k] = v
        runs.append(d)
    return runs


def read_published():
    sets = {}
    for line in open(os.path.join(HERE, "data", "chung_ooi_2011.txt")):
        if line.startswith("#") or not line.strip():
            continue
        name, x, y = line.split()
        sets.setdefault(name, []).append((float(x), float(y)))
    return sets


def kappa(nu):
    return 2 * (1 - nu) / (2 - nu)


def plot_published(runs, img):
    pub = read_published()
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(12, 4.8))
    mbf = sorted((r["psi1"], r["mdr_psi2"]) for r in runs if r["case"] == "mbf")
    ax1.plot(*zip(*mbf), "k-", label="MDR, chi = 1.5 (granite, nu = 0.25)")
    t5 = sorted((r["psi1"], r["mdr_psi2"]) for r in runs if r["case"] == "t5")
    ax1.plot(*zip(*t5), "b--", label="MDR, Test 5 set-up (nu = 0.3, chi = 1.44)")
    k5 = kappa(0.3)
    ax1.plot([k5 * x for x, _ in pub["t5_y1_fem"]], [k5 * y for _, y in pub["t5_y1_fem"]], "bs",
             mfc="none", label="Chung & Ooi 2011 Test 5, FEM")
    k4, mu4, e4 = kappa(0.23), 0.092, 0.98
    ax1.plot([k4 * math.tan(math.radians(a)) / mu4 for a, _ in pub["t4_reb_exp"]],
             [k4 * e4 * math.tan(math.radians(b)) / mu4 for _, b in pub["t4_reb_exp"]], "ro",
             label="Kharaz et al. 2001, experiment")
    t4 = sorted((r["psi1"], r["mdr_psi2"]) for r in runs if r["case"] == "t4_oxide")
    ax1.plot(*zip(*t4), "r:", label="MDR, Kharaz set-up (nu = 0.23)")
    p = [0.01 * i for i in range(1501)]
    ax1.plot(p, [max(0.0, x - 6.0) for x in p], color="0.6", lw=1, label="rigid body (chi = 1.5, e = 1)")
    ax1.set_xlim(0, 12)
    ax1.set_ylim(-3, 6)
    ax1.set_xlabel("psi1 = (G*/E*) v_c / (mu v_n)   (before)")
    ax1.set_ylabel("psi2 = (G*/E*) v_c' / (mu v_n)   (after)")
    ax1.grid(alpha=0.3)
    ax1.legend(fontsize=8)
    ax1.set_title("MBF diagram: contact-point velocity after vs before")
    for tag, style, label in (("t4_oxide", "r-", "MDR, alumina"), ("t4_alloy", "g--", "MDR, Al alloy")):
        pts = sorted((r["angle"], r["mdr_Rt"]) for r in runs if r["case"] == tag)
        ax2.plot(*zip(*pts), style, label=label)
    ax2.plot(*zip(*pub["t4_rt_oxide"]), "r^", mfc="none", label="Chung & Ooi Test 4 reference, alumina")
    ax2.plot(*zip(*pub["t4_rt_alloy"]), "gv", mfc="none", label="Chung & Ooi Test 4 reference, Al alloy")
    ax2.plot(*zip(*pub["t4_rt_exp"]), "ko", label="Kharaz et al. 2001, experiment (alumina)")
    ang = [0.5 + 0.25 * i for i in range(339)]
    ax2.plot(ang, [max(5 / 7, 1 - mu4 * (1 + e4) / math.tan(math.radians(a))) for a in ang], color="0.6",
             lw=1, label="rigid body")
    ax2.set_xlabel("incident angle from the normal [deg]  (3.9 m/s, mu = 0.092)")
    ax2.set_ylabel("R_t = v_t' / v_t")
    ax2.set_ylim(0.5, 1.0)
    ax2.grid(alpha=0.3)
    ax2.legend(fontsize=8)
    ax2.set_title("R_t against incidence (Kharaz et al. / Chung & Ooi Test 4)")
    fig.tight_layout()
    fig.savefig(os.path.join(img, "mdr_published.png"), dpi=110)
    print("published: angle  R_t(MDR alumina)  R_t(experiment, nearest angle)")
    for a, rt in pub["t4_rt_exp"]:
        best = min((r for r in runs if r["case"] == "t4_oxide"), key=lambda r: abs(r["angle"] - a))
        print("  %5.1f  %.3f (MDR at %.1f)  %.3f" % (a, best["mdr_Rt"], best["angle"], rt))


def plot_sweep(runs, img):
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.6))
    colors = {30: "tab:blue", 45: "tab:orange", 60: "tab:green"}
    print("| slope | f | psi1 | R_t FE | R_t MDR | R_t MDR, e_n = FE R_n | FE - MDR | finite-body MDR - MDR "
          "| omega' r/v_t FE / MDR | beta_t FE / MDR |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for a in (30, 45, 60):
        rr = sorted((r for r in runs if r.get("angle") == a and "fe_Rt" in r), key=lambda r: r["f"])
        if not rr:
            continue
        f = [r["f"] for r in rr]
        c = colors[a]
        axes[0].plot(f, [r["fe_Rt"] for r in rr], "o", color=c, label="FE %d deg" % a)
        axes[0].plot(f, [r["mdr_Rt"] for r in rr], "-", color=c, label="MDR %d deg" % a)
        axes[0].plot(f, [r["mdrfe_Rt"] for r in rr], ":", color=c)
        V = 10.0
        vt = V * math.sin(math.radians(a))
        axes[1].plot(f, [r["fe_w"] / vt for r in rr], "o", color=c)
        axes[1].plot(f, [r["mdr_w"] / vt for r in rr], "-", color=c, label="%d deg" % a)
        pos = [r for r in rr if r["f"] > 0]
        axes[2].plot([r["psi1"] for r in pos], [r["fe_beta"] for r in pos], "o", color=c, label="FE %d deg" % a)
        axes[2].plot([r["psi1"] for r in pos], [r["mdr_beta"] for r in pos], "x", color=c, ms=8,
                     label="MDR %d deg" % a)
        for r in rr:
            print("| %d | %g | %s | %.4f | %.4f | %.4f | %+.4f | %+.4f | %.3f / %.3f | %+.3f / %+.3f |" % (
                a, r["f"], "%.2f" % r["psi1"] if r["f"] > 0 else "inf", r["fe_Rt"], r["mdr_Rt"], r["mdrfe_Rt"],
                r["fe_Rt"] - r["mdr_Rt"], r.get("fbI_Rt", float("nan")) - r["mdr_Rt"], r["fe_w"] / vt,
                r["mdr_w"] / vt, r["fe_beta"], r["mdr_beta"]))
    mbf = sorted((r["psi1"], r["mdr_beta"]) for r in read_runs(os.path.join(sys.argv[1], "published.txt"))
                 if r["case"] == "mbf")
    if mbf:
        axes[2].plot(*zip(*mbf), "k-", lw=1, label="MDR, chi = 1.5")
    axes[0].set_xscale("symlog", linthresh=0.1)
    axes[1].set_xscale("symlog", linthresh=0.1)
    axes[0].axhline(5 / 7, color="0.6", lw=1)
    axes[0].set_xlabel("friction f")
    axes[0].set_ylabel("R_t")
    axes[0].set_title("R_t: FE a/h = 4 (dots), MDR (lines; dotted: e_n = FE R_n)", fontsize=10)
    axes[1].set_xlabel("friction f")
    axes[1].set_ylabel("omega' r / v_t")
    axes[1].set_title("spin after impact")
    axes[2].set_xscale("log")
    axes[2].set_xlabel("psi1")
    axes[2].set_ylabel("beta_t = v_c' / v_c")
    axes[2].set_title("contact-point velocity ratio against psi1")
    for ax in axes:
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(img, "mdr_fe_sweep.png"), dpi=110)


def plot_gap(runs, sweep, img):
    fig, ax = plt.subplots(1, 1, figsize=(7, 4.8))
    print("| case | v [m/s] | rho_b | f | a/h | a/R | R_t FE | R_t MDR | FE - MDR | normal finite-body MDR - MDR "
          "| all finite-body MDR - MDR | FE compression / Hertz - 1 | R_n FE |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    base = [r for r in sweep if r.get("angle") == 45 and r.get("f") in (0.6, 5.0)]
    allr = runs + base
    for f, mk in ((5.0, "o"), (0.6, "s")):
        vel = sorted((r for r in allr if r.get("f") == f and r.get("case") in ("vel", "v1", "sweep")
                      and "rho_b" not in r and r.get("ref", 4) == 4), key=lambda r: r["v"])
        if vel:
            x = [r["hertz_a_over_R"] for r in vel]
            ax.plot(x, [r["fe_Rt"] - r["mdr_Rt"] for r in vel], mk + "-", color="tab:red",
                    label="FE - MDR, f = %g (velocity 0.3-30 m/s)" % f)
            ax.plot(x, [r["fbI_Rt"] - r["mdr_Rt"] for r in vel], mk + "--", color="tab:blue", mfc="none",
                    label="finite-body MDR - MDR, f = %g" % f)
        dens = [r for r in allr if r.get("case") == "dens" and r.get("f") == f]
        for r in dens:
            ax.plot(r["hertz_a_over_R"], r["fe_Rt"] - r["mdr_Rt"], "k" + mk, mfc="none", ms=10)
    ax.plot([], [], "ko", mfc="none", ms=10, label="FE, boulder density x10 / x0.1 (same a/R)")
    ax.axhline(0, color="0.5", lw=1)
    ax.set_xlabel("a/R (Hertz contact radius / boulder radius)")
    ax.set_ylabel("R_t difference")
    ax.set_title("45 deg slope: FE - MDR against a/R")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(img, "mdr_gap.png"), dpi=110)
    for r in sorted(allr, key=lambda r: (r.get("case", ""), r.get("f", 0), r.get("v", 0))):
        if "fe_Rt" not in r or r.get("angle") != 45:
            continue
        print("| %s | %.3g | %g | %g | %g | %.3f | %.4f | %.4f | %+.4f | %+.4f | %+.4f | %+.2f %% | %.4f |" % (
            r["case"], r["v"], r.get("rho_b", 2600), r["f"], r.get("ref", 4), r["hertz_a_over_R"], r["fe_Rt"],
            r["mdr_Rt"], r["fe_Rt"] - r["mdr_Rt"], r.get("body_Rt", float("nan")) - r["mdr_Rt"],
            r.get("fbI_Rt", float("nan")) - r["mdr_Rt"], 100 * (r["fe_comp"] / r["hertz_comp"] - 1), r["fe_Rn"]))


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: validate_mdr_plot.py OUT_DIR IMG_DIR")
    out, img = sys.argv[1], sys.argv[2]
    os.makedirs(img, exist_ok=True)
    published = read_runs(os.path.join(out, "published.txt"))
    if published:
        plot_published(published, img)
    sweep = read_runs(os.path.join(out, "sweep.txt"))
    if sweep:
        plot_sweep(sweep, img)
    gap = read_runs(os.path.join(out, "gap.txt"))
    if gap or sweep:
        plot_gap(gap, sweep, img)


if __name__ == "__main__":
    main()
