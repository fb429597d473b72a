#!/usr/bin/env python3
"""tools/validate_plastic.py - the elasto-plastic impact validation of
docs/validation-plastic.md: a granite sphere (elastic) on a von Mises
(elastic-perfectly-plastic) granite half-space, axisymmetric FE through
`rockfuzz impact --json`, against Hertz first yield (V_y), Thornton (1997)
and Johnson (1985) closed forms (shared docs plasticity_refs.md sec. 1).

Usage: tools/validate_plastic.py [rockfuzz-binary] [out-dir]
Writes out-dir/plastic_results.json, docs/img/plastic_rn.png and prints the
markdown tables of the doc.  ~5 min on one core (runs one impact at a time).
"""
import json
import math
import os
import subprocess
import sys

SRC = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = sys.argv[1] if len(sys.argv) > 1 else os.path.join(SRC, "build", "rockfuzz")
OUT = sys.argv[2] if len(sys.argv) > 2 else os.path.join(SRC, "build", "validation-plastic")
os.makedirs(OUT, exist_ok=True)

E, NU, RHO, R = 68.2e9, 0.25, 2600.0, 1.0
ESTAR = 1.0 / (2 * (1 - NU * NU) / E)   # the pair's E*
MASS = 4.0 / 3.0 * math.pi * R**3 * RHO


def first_yield(nu):
    """C = p0/Y at first yield and its depth z/a on the axis (Hertz axis stresses, Johnson 1985 eq. 3.45)."""
    best, depth = 0.0, 0.0
    for i in range(1, 40001):
        s = i * 5e-5
        sz = -1 / (1 + s * s)
        sr = -(1 + nu) * (1 - s * math.atan(1 / s)) + 0.5 / (1 + s * s)
        if abs(sr - sz) > best:
            best, depth = abs(sr - sz), s
    return 1 / best, depth


C, DEPTH = first_yield(NU)


def v_yield(Y):
    """V_y^2 = (pi^5/30) R^3 p_y^5 / (m E*^4), p_y = C Y (plasticity_refs.md 1.1)."""
    py = C * Y
    return math.sqrt(math.pi**5 / 30 * R**3 * py**5 / (MASS * ESTAR**4))


def yield_for(V, ratio):
    """Y such that V / V_y(Y) = ratio (V_y ~ Y^(5/2))."""
    return (V / ratio / v_yield(1.0)) ** 0.4


def thornton(ratio):
    r = 1.0 / ratio
    return math.sqrt(6 * math.sqrt(3) / 5) * math.sqrt(1 - r * r / 6) * \
        (r / (r + 2 * math.sqrt(6 / 5 - r * r / 5))) ** 0.25


def johnson(Y, V, pd_over_Y=3.0):
    """Fully plastic loading at mean pressure p_d, Hertz unloading (plasticity_refs.md 1.2)."""
    pd = pd_over_Y * Y
    return 1.718 * math.sqrt(pd / ESTAR) * (pd / (RHO * V * V)) ** 0.125


def run(V, Y=None, ref=10, extra=()):
    cmd = [BIN, "impact", "--velocity", repr(V), "--refinement", str(ref), "--domain-factor", "10",
           "--boundary", "absorbing", "--json", "--large-deformation", "off"]  # small strain: section 6e compares
    if Y is not None:
        cmd += ["--slope-material", "von_mises", "--slope-yield", repr(Y)]
    cmd += list(extra)
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    return json.loads(out)


def main():
    res = {"C": C, "depth": DEPTH, "vy": [], "rn": [], "conv": []}
    print(f"first yield: p0 = {C:.4f} Y at depth {DEPTH:.3f} a (nu = {NU})")
    # A. yield velocity at Y = 1 GPa
    Y = 1e9
    Vy = v_yield(Y)
    print(f"\nV_y = {Vy:.4f} m/s for Y = 1 GPa\n\n| V/V_y | V m/s | eps_p max | W_p / KE | energy error |\n|---|---|---|---|---|")
    for ratio in (0.8, 0.9, 0.95, 1.0, 1.05, 1.1, 1.25):
        o = run(ratio * Vy, Y)
        res["vy"].append({"ratio": ratio, **o})
        print(f"| {ratio} | {ratio * Vy:.4f} | {o['equivalent_plastic_strain_max']:.3g} | {o['plastic_work']:.3g} | "
              f"{o['energy_error']:.1e} |")
    # B. R_n against V/V_y at 10 m/s (Y varies)
    V = 10.0
    el = run(V)
    res["elastic"] = el
    print(f"\nelastic R_n at {V} m/s, same mesh: {el['R_n']:.5f} (wave loss)\n")
    print("| V/V_y | Y MPa | R_n FE | Thornton (p_y = C Y) | Johnson (p_d = 3Y) | W_p/KE | R_n^2 + W_p/KE | "
          "penetration mm | crater mm | eps_p max | energy error |\n|---|---|---|---|---|---|---|---|---|---|---|")
    for ratio in (10, 20, 50, 100, 200, 500, 1000):
        Yr = yield_for(V, ratio)
        o = run(V, Yr)
        row = {"ratio": ratio, "Y": Yr, "thornton": thornton(ratio), "johnson": johnson(Yr, V), **o}
        res["rn"].append(row)
        print(f"| {ratio} | {Yr / 1e6:.1f} | {o['R_n']:.4f} | {row['thornton']:.4f} | {row['johnson']:.4f} | "
              f"{o['plastic_work']:.4f} | {o['R_n']**2 + o['plastic_work']:.4f} | {1e3 * o['penetration_max']:.2f} | "
              f"{1e3 * o['indentation_depth']:.2f} | {o['equivalent_plastic_strain_max']:.3f} | "
              f"{o['energy_error']:.1e} |")
    # C. mesh convergence at V/V_y = 100
    Yr = yield_for(V, 100)
    print("\n| a/h | elements | R_n | crater mm | W_p/KE | energy error | wall s |\n|---|---|---|---|---|---|---|")
    for ref in (5, 10, 20):
        o = run(V, Yr, ref)
        res["conv"].append({"ref": ref, **o})
        print(f"| {ref} | {o['elements']:.0f} | {o['R_n']:.4f} | {1e3 * o['indentation_depth']:.2f} | "
              f"{o['plastic_work']:.4f} | {o['energy_error']:.1e} | {o['wall_seconds']:.1f} |")
    with open(os.path.join(OUT, "plastic_results.json"), "w") as f:
        json.dump(res, f, indent=1)
    plot(res)


def plot(res):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    xs = [10 ** (k / 20) for k in range(10, 66)]
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    ax.loglog(xs, [thornton(x) for x in xs], "k-", label="Thornton 1997 ($p_y$ = C Y)")
    ax.loglog(xs, [1.185 * x ** -0.25 for x in xs], "k:", label="Thornton high-speed limit")
    ax.loglog(xs, [min(1, 1.166 * 3 ** 0.625 * x ** -0.25) for x in xs], "b--",
              label="Johnson 1985 ($p_d$ = 3Y, Hertz unloading)")
    ax.loglog([r["ratio"] for r in res["rn"]], [r["R_n"] for r in res["rn"]], "ro", label="FE (a/h = 10), 10 m/s")
    ax.axhline(res["elastic"]["R_n"], color="gray", lw=0.8, label="FE elastic (wave loss only)")
    ax.set_xlabel("$V / V_y$")
    ax.set_ylabel("$R_n$")
    ax.set_title("Elastic sphere on an elastic-perfectly-plastic half-space")
    ax.legend(fontsize=8)
    ax.grid(True, which="both", lw=0.3)
    os.makedirs(os.path.join(SRC, "docs", "img"), exist_ok=True)
    fig.tight_layout()
    fig.savefig(os.path.join(SRC, "docs", "img", "plastic_rn.png"), dpi=110)


if __name__ == "__main__":
    main()
