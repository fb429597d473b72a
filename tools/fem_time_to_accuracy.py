#!/usr/bin/python3
"""fem_time_to_accuracy.py - converged values and time-to-accuracy curves of
the FE impact (issue 9, docs/fem-speed.md "Time to accuracy").

Usage: fem_time_to_accuracy.py [data-dir=tools/data] [img-dir=docs/img]

Reads
  fem_refinement_10ms.txt  refinement study (lines "model=3d|axi ref=A ... R_n=..
                           R_t=.. R_ke=..", the key=value format of bench/bench_tta)
  fem_tta_10ms.txt         timed runs of bench_tta (wall, cpu, ns per element-step)
prints the Richardson extrapolation of R_n, R_t, R_ke (3D: 10 m/s vertical on a
45 degree slope, f = 0.6) and of R_n (axisymmetric 10 m/s), and writes
fem_time_to_accuracy.png: error against wall and CPU time per run."""
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    rows = []
    with open(path) as f:
        for line in f:
            if "model=" not in line:
                continue
            d = {}
            for tok in line.split():
                if "=" in tok:
                    k, v = tok.split("=", 1)
                    try:
                        d[k] = float(v)
                    except ValueError:
                        d[k] = v
            rows.append(d)
    return rows


def richardson(a, r):
    """R(A) = R_inf + C A^-p through the three points (a[i], r[i]) (any
    ratios): p by bisection on the ratio of successive differences.  Returns
    (R_inf, p) or (None, None) when the differences change sign (no
    asymptotic range)."""
    d1, d2 = r[0] - r[1], r[1] - r[2]
    if d1 * d2 <= 0:
        return None, None
    q = d1 / d2

    def g(p):
        return (a[0] ** -p - a[1] ** -p) / (a[1] ** -p - a[2] ** -p) - q

    lo, hi = 0.05, 8.0
    if g(lo) * g(hi) > 0:
        return None, None
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if g(lo) * g(mid) <= 0:
            hi = mid
        else:
            lo = mid
    p = 0.5 * (lo + hi)
    rinf = r[2] - d2 * a[2] ** -p / (a[1] ** -p - a[2] ** -p)
    return rinf, p


def converged(rows, model, key, triples):
    by = {d["ref"]: d[key] for d in rows if d["model"] == model}
    out = []
    for t in triples:
        if all(x in by for x in t):
            rinf, p = richardson(list(t), [by[x] for x in t])
            out.append((t, rinf, p))
    return by, out


def main():
    data = sys.argv[1] if len(sys.argv) > 1 else "tools/data"
    img = sys.argv[2] if len(sys.argv) > 2 else "docs/img"
    ref = read(os.path.join(data, "fem_refinement_10ms.txt"))
    tta = read(os.path.join(data, "fem_tta_10ms.txt"))
    conv = {}
    # 3D: a/h below 4 carry mesh-topology noise of +-3e-4 in R_n (the fine box's cell counts are rounded
    # up), so the fits use 4 ... 8; steps against the trend count from a/h = 5 (3D) and 10 (axi) on
    for model, keys, triples, a_trend in (
            ("3d", ("R_n", "R_t", "R_ke"), ((4, 5, 6), (4, 6, 8), (5, 6, 7), (5, 6, 8), (5, 7, 8), (6, 7, 8)), 5),
            ("axi", ("R_n",), ((10, 20, 40), (15, 20, 40), (20, 30, 40)), 10)):
        for key in keys:
            by, fits = converged(ref, model, key, triples)
            print(f"{model} {key}: " + "  ".join(f"a/h={a:g}: {v:.7f}" for a, v in sorted(by.items())))
            for t, rinf, p in fits:
                if rinf is None:
                    print(f"   Richardson {t}: no asymptotic range (differences change sign)")
                else:
                    flag = "" if 0.8 <= p <= 4 else "  (order outside [0.8, 4]: not used)"
                    print(f"   Richardson {t}: R_inf = {rinf:.7f}, order p = {p:.2f}{flag}")
            # accept fits with a plausible order (0.8 <= p <= 4: the schemes are first to second order;
            # a smaller or larger p means the three points are not in the asymptotic range)
            ok = [f for f in fits if f[1] is not None and 0.8 <= f[2] <= 4]
            a_max = max(by)
            finest = by[a_max]
            top = [f for f in ok if max(f[0]) == a_max]
            if top:  # the fit through the finest mesh, with the finest coarse points
                est = max(top, key=lambda f: min(f[0]))[1]
            else:  # no acceptable fit through the finest mesh: the finest value
                est = finest
            near = [f[1] for f in ok if max(f[0]) >= a_max - 1]
            a_sorted = sorted(by)
            d = [by[a_sorted[i + 1]] - by[a_sorted[i]] for i in range(len(a_sorted) - 1) if a_sorted[i] >= a_trend]
            trend = 1 if est > finest else -1
            wrong = max([-trend * x for x in d if trend * x < 0], default=0)  # steps against the trend
            unc = max([abs(est - finest) / 2, wrong] + [abs(g - est) for g in near])
            conv[(model, key)] = est
            print(f"   converged {model} {key} = {est:.6f} +- {unc:.1e}")

    fig, axes = plt.subplots(1, 2, figsize=(12, 4.8))
    ax = axes[0]
    tol = {"R_n": 1e-3, "R_t": 3e-3, "R_ke": 1e-3}
    colours = {"R_n": "C0", "R_t": "C1", "R_ke": "C2"}
    for key in ("R_n", "R_t", "R_ke"):
        for th, mk in ((1, "o"), (2, "s")):
            pts = sorted(((d["wall"], abs(d[key] - conv[("3d", key)]), d["ref"], d["cpu"], d["ns_cpu"])
                         for d in tta if d["model"] == "3d" and d["threads"] == th), key=lambda p: p[2])
            if not pts:
                continue
            ax.plot([p[0] for p in pts], [p[1] / tol[key] for p in pts], mk + "-", color=colours[key],
                    label=f"{key} / {tol[key]:g}, {th} thread{'s' if th > 1 else ''} (wall)")
            if th == 1:
                ax.plot([p[3] for p in pts], [p[1] / tol[key] for p in pts], mk + ":", color=colours[key],
                        alpha=0.5)
                for p in pts:
                    if key == "R_n":
                        ax.annotate(f"a/h={p[2]:g}\n{p[4]:.0f} ns", (p[3], p[1] / tol[key]), fontsize=7)
    ax.axhline(1, color="k", lw=0.8)
    ax.axvline(3, color="r", lw=0.8, ls="--")
    ax.set_xscale("log"), ax.set_yscale("log")
    ax.set_xlabel("time [s] (solid: wall on the loaded machine; dotted: CPU, 1 thread)")
    ax.set_ylabel("|error| / tolerance")
    ax.set_title("3D: 10 m/s on 45 deg, f = 0.6 (target: < 1 within 3 s)")
    ax.legend(fontsize=7)
    ax = axes[1]
    for th, mk in ((1, "o"), (2, "s")):
        pts = sorted(((d["wall"], abs(d["R_n"] - conv[("axi", "R_n")]), d["ref"], d["cpu"], d["ns_cpu"])
                     for d in tta if d["model"] == "axi" and d["threads"] == th), key=lambda p: p[2])
        if not pts:
            continue
        ax.plot([p[0] for p in pts], [p[1] for p in pts], mk + "-", color="C0" if th == 1 else "C3",
                label=f"{th} thread{'s' if th > 1 else ''}, wall")
        ax.plot([p[3] for p in pts], [p[1] for p in pts], mk + ":", color="C0" if th == 1 else "C3", alpha=0.5,
                label=f"{th} thread{'s' if th > 1 else ''}, CPU")
        if th == 1:
            for p in pts:
                ax.annotate(f"a/h={p[2]:g}\n{p[4]:.0f} ns", (p[3], p[1]), fontsize=7)
    ax.axhline(1e-4, color="k", lw=0.8)
    ax.axvline(0.3, color="r", lw=0.8, ls="--")
    ax.set_xscale("log"), ax.set_yscale("log")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("|R_n - converged|")
    ax.set_title("axisymmetric 10 m/s (target: < 1e-4 within 0.3 s)")
    ax.legend(fontsize=7)
    fig.tight_layout()
    out = os.path.join(img, "fem_time_to_accuracy.png")
    fig.savefig(out, dpi=110)
    print("wrote", out)


if __name__ == "__main__":
    main()
