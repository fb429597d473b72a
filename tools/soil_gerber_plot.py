#!/usr/bin/python3
"""soil_gerber_plot.py - the soil model's largest penetration against Gerber's
law d = 0.1 M^(1/3) M_E^(-0.4) V^0.8 (docs/soil-impacts.md).

    /usr/bin/python3 tools/soil_gerber_plot.py docs/data/soil_gerber_A.csv \
        docs/data/soil_gerber_B.csv docs/img/soil_gerber.png

Reads the CSV rows of build/bench_soil_gerber (one file per parameter
variant), prints a markdown table per file and a log-log least-squares fit of
the model's d to M^a M_E^b V^c, and draws model against law (both in m) with
the 1:1 line."""
import csv
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np



# The runs of docs/soil-impacts.md by what they hold fixed (the file names are the doc's A and B).
LABELS = {"soil_gerber_A": "A: strength and cap of the S5 colluvium",
          "soil_gerber_B": "B: cap hardening tied to M_E"}

def read(path):
    rows = [r for r in csv.DictReader(open(path)) if r["d_model_m"] not in ("failed", "")]
    return rows


def fit(rows):
    M = np.array([float(r["mass_kg"]) for r in rows])
    E = np.array([float(r["ME_Pa"]) / 1e3 for r in rows])
    V = np.array([float(r["V_m_s"]) for r in rows])
    d = np.array([float(r["d_model_m"]) for r in rows])
    A = np.c_[np.ones(len(d)), np.log(M), np.log(E), np.log(V)]
    c = np.linalg.lstsq(A, np.log(d), rcond=None)[0]
    return np.exp(c[0]), c[1], c[2], c[3]


def table(path, rows):
    print(f"\n{path}\n")
    print("| M kg | r0 m | V m/s | M_E MPa | E MPa | H_c MPa | d model m | d Gerber m | model/law | R_n | CPU s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {float(r['mass_kg']):g} | {float(r['r0_m']):.3f} | {float(r['V_m_s']):g} | "
              f"{float(r['ME_Pa'])/1e6:g} | {float(r['E_Pa'])/1e6:.1f} | {float(r['Hc_Pa'])/1e6:.1f} | "
              f"{float(r['d_model_m']):.3f} | {float(r['d_gerber_m']):.3f} | {float(r['ratio']):.2f} | "
              f"{float(r['R_n']):.3f} | {float(r['cpu_s']):.2f} |")
    k, a, b, c = fit(rows)
    ratio = np.array([float(r["ratio"]) for r in rows])
    print(f"\nfit: d = {k:.4f} M^{a:.3f} M_E^{b:.3f} V^{c:.3f} (law: 0.1 M^0.333 M_E^-0.400 V^0.800); "
          f"model/law {ratio.min():.2f}-{ratio.max():.2f}, geometric mean {np.exp(np.mean(np.log(ratio))):.2f}")


def main():
    paths, out = sys.argv[1:-1], sys.argv[-1]
    fig, ax = plt.subplots(figsize=(6.4, 5.4))
    marks = ["o", "s", "^", "D"]
    lo, hi = 1e9, 0
    for k, path in enumerate(paths):
        rows = read(path)
        table(path, rows)
        g = np.array([float(r["d_gerber_m"]) for r in rows])
        d = np.array([float(r["d_model_m"]) for r in rows])
        me = np.array([float(r["ME_Pa"]) / 1e6 for r in rows])
        sc = ax.scatter(g, d, c=np.log10(me), cmap="viridis", marker=marks[k % 4], s=36,
                        label=LABELS.get(path.split("/")[-1].replace(".csv", ""), path.split("/")[-1]),
                        edgecolors="k", linewidths=0.4)
        lo, hi = min(lo, g.min(), d.min()), max(hi, g.max(), d.max())
    x = np.array([lo * 0.8, hi * 1.25])
    ax.plot(x, x, "k-", lw=0.8, label="model = law")
    ax.plot(x, 2 * x, "k:", lw=0.8, label="model = 2 x law")
    ax.set_xscale("log"), ax.set_yscale("log")
    ax.set_xlabel("Gerber's law d [m]")
    ax.set_ylabel("FE model, largest penetration [m]")
    cb = fig.colorbar(sc, ax=ax)
    cb.set_label("log10 M_E [MPa]")
    ax.legend(fontsize=8, loc="upper left")
    ax.set_title("Rigid sphere on a thick DP + cap layer (axisymmetric, a/h 2)", fontsize=9)
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    main()
