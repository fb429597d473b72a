#!/usr/bin/env python3
"""trajectory_validation.py - the validation figure of docs/trajectories.md:
rockfuzz's trajectory of the geometric series of bounces on flat ground
(dropped from h = 5 m at U = 3 m/s, R_n = 0.6, R_t = 0.9) against the closed
form x_k = U T0 + (2 U v0 / g) sum_{j=1}^{k-1} (R_n R_t)^j, and the
relative error of every impact position.  Reads only `rockfuzz trajectory
--json` and `--out` (trajectories.csv).
Usage: tools/trajectory_validation.py BUILD_DIR OUT.png"""
import csv, json, math, os, subprocess, sys, tempfile
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

build, out = sys.argv[1], sys.argv[2]
yaml = """name: bounce-series
profile: {points: [[-1, 0], [14, 0]], material: m}
materials: {m: {R_n: 0.6, R_t: 0.9, friction_angle: 45}}
block: {shape: point, mass: 1}
release: {x: 0, y: 5, vx: 3, vy: 0}
bounce: {law: constant, contact_speed: 0.001}
stop: {v_stop: 0}
"""
g, Rn, Rt, U, h = 9.81, 0.6, 0.9, 3.0, 5.0
with tempfile.TemporaryDirectory() as d:
    f = os.path.join(d, "b.yaml")
    open(f, "w").write(yaml)
    j = json.loads(subprocess.check_output([os.path.join(build, "rockfuzz"), "trajectory", f, "--json",
                                            "--out", d, "--no-plots"]))
    rows = list(csv.DictReader(open(os.path.join(d, "trajectories.csv"))))
imp = j["trajectories"][0]["impacts"]
v0 = math.sqrt(2 * g * h); T0 = v0 / g
xs, x, vn, vt = [], U * T0, v0, U
for k in range(len(imp)):
    xs.append(x); vn *= Rn; vt *= Rt; x += vt * 2 * vn / g
err = [abs(i["x"] - c) / c for i, c in zip(imp, xs)]
fig, ax = plt.subplots(2, 1, figsize=(8, 6.5))
ax[0].plot([float(r["x_m"]) for r in rows], [float(r["y_m"]) for r in rows], lw=1, label="rockfuzz (exact parabolas)")
ax[0].plot(xs, [0] * len(xs), "o", mfc="none", color="C3", label="closed form: impact points")
xinf = U * T0 + 2 * U * v0 / g * Rn * Rt / (1 - Rn * Rt)
ax[0].axvline(xinf, color="grey", ls="--", lw=0.8, label="limit of the series x_inf = %.4f m" % xinf)
ax[0].set_xlabel("x [m]"); ax[0].set_ylabel("y [m]"); ax[0].legend(fontsize=8)
ax[0].set_title("bounces on flat ground: R_n = 0.6, R_t = 0.9, dropped from 5 m at 3 m/s")
ax[1].semilogy(range(1, len(err) + 1), [max(e, 1e-17) for e in err], "o-", ms=3)
ax[1].set_xlabel("impact number"); ax[1].set_ylabel("|x - x_closed| / x_closed")
ax[1].set_title("relative error of the impact positions (%d impacts; exact 0 drawn at 1e-17)" % len(err))
fig.tight_layout(); fig.savefig(out, dpi=110)
print("max relative error %.3g over %d impacts; rest x %.6f (x_inf %.6f)" % (max(err), len(err),
      j["trajectories"][0]["rest"]["x"], xinf))
