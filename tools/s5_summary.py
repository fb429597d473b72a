#!/usr/bin/python3
"""tools/s5_summary.py - the tables and figures of study S5 (docs/studies.md)
from the three runs

    rockfuzz run examples/s5_v5.yaml  --out out/s5_v5  --tolerate-failures
    rockfuzz run examples/s5_v10.yaml --out out/s5_v10 --tolerate-failures
    rockfuzz run examples/s5_v20.yaml --out out/s5_v20 --tolerate-failures

Usage: /usr/bin/python3 tools/s5_summary.py [--suffix=S] [OUT-ROOT [IMG-DIR [ROCKFUZZ]]]
(S5r, the rough block: link its runs as OUT-ROOT/s5_v<v>_r and give --suffix=_r; a fuzzy
friction is then passed on to the energy-error reruns)
(defaults out, docs/img).  --suffix=S reads OUT-ROOT/s5_v<v>S (e.g. --suffix=_g for the
runs with gravity, out/s5_v5_g) and names the figures studies_s5S_*.png.  With ROCKFUZZ (the binary), also reruns the input
points where R_n, penetration_max, contact_force_max and plastic_work take
their level-0 bounds with `rockfuzz impact --json` and prints their energy
errors (the study outputs do not include it).  Reads each run's result.json (cuts, influence
measures) and store.sqlite (every evaluation, to classify them), prints
markdown tables and writes IMG-DIR/studies_s5_outputs.png and
IMG-DIR/studies_s5_influence.png.

Classification of an evaluation (r0 = 0.5 m in the S5 files).  The runs use
large deformation (`large_deformation: auto`, a plastic layer) and the automatic
end that waits for the impact to end (docs/validation-plastic.md sections 6e, 10a):
  not-ended  the run failed at the bound of the automatic end ("the impact has
             not ended"): the boulder is still in contact or still moving
             toward the slope; no R_n exists
  failed     the solver stopped with any other error
  at-rest    R_n = 0 exactly: the run ended by the rest rule of gravity (the
             block came to rest in its crater, docs/validation-plastic.md
             section 11); only with gravity
  no-rebound the run ended but R_n < 0 (should not happen with the new end
             rule; kept to catch it)
  deep       penetration_max >= 0.4 r0 = 0.2 m: a deep-penetration marker (the
             soil squeezed between block and granite, plastic strains of several
             units, R_n not mesh-converged: validation-plastic.md section 6e);
             with large deformation the kinematics follow it, so it no longer
             means "outside the model's kinematics"
  ok         otherwise
"""
import json
import os
import sqlite3
import struct
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

SPEEDS = (5, 10, 20)
R0 = 0.5
SHOW = ("R_n", "plastic_work", "penetration_max", "indentation_depth", "contact_force_max", "contact_duration")
TABLE = SHOW + ("equivalent_plastic_strain_max",)
UNIT = {"R_n": "-", "plastic_work": "of KE", "penetration_max": "m", "indentation_depth": "m",
        "contact_force_max": "N", "contact_duration": "s", "equivalent_plastic_strain_max": "-"}


def load(root, v, suffix=""):
    d = os.path.join(root, "s5_v%d%s" % (v, suffix))
    res = json.load(open(os.path.join(d, "result.json")))
    return res, load_store(d)


def load_store(d):
    con = sqlite3.connect("file:%s?mode=ro" % os.path.join(d, "store.sqlite"), uri=True)
    names = dict(con.execute("select key, value from meta"))["outputs"].split(",")
    evals = []
    for x_text, ok, y, err, sec in con.execute("select x_text, ok, y, error, seconds from results"):
        row = {"x": x_text, "ok": ok, "seconds": sec or 0.0, "error": err}
        if ok and y is not None:
            row.update(zip(names, struct.unpack("<%dd" % (len(y) // 8), y)))
        evals.append(row)
    con.close()
    return evals


def classify(e):
    if not e["ok"]:
        return "not-ended" if "has not ended" in (e["error"] or "") else "failed"
    if e["R_n"] == 0:
        return "at-rest"
    if not e["R_n"] > 0:
        return "no-rebound"
    if e["penetration_max"] >= 0.4 * R0:
        return "deep"
    return "ok"


def energy_errors(binary, runs):
    """Energy error of `rockfuzz impact` at the level-0 bound points of four outputs."""
    print("### energy error at the level-0 bound points\n")
    for v, (res, _) in runs.items():
        crisp = res["model_identity"]
        pts = set()
        for o in ("R_n", "penetration_max", "contact_force_max", "plastic_work"):
            for k in ("x_lower", "x_upper"):
                x = res["outputs"][o][k][0]
                pts.add(tuple(x[n] for n in ("layer_E", "layer_cohesion", "layer_friction_angle",
                                             "layer_cap_pressure", "layer_thickness")) + (x.get("friction", 0.0),))
        bnd = "fixed" if "boundary=fixed" in crisp else "absorbing"
        grav = crisp.split("gravity=")[1].split(",")[0].split(";")[0].split(" ")[0] if "gravity=" in crisp else "0"
        worst = 0.0
        for E, c, phi, x0, t, mu in sorted(pts):
            cmd = [binary, "impact", "--boulder-material", "rigid", "--radius", "0.5", "--velocity", str(v),
                   "--layer-thickness", repr(t), "--layer-material", "drucker_prager", "--layer-density", "1900",
                   "--layer-E", repr(E), "--layer-poisson", "0.3", "--layer-cohesion", repr(c),
                   "--layer-friction-angle", repr(phi), "--layer-dilatancy-angle", "5",
                   "--layer-cap-pressure", repr(x0), "--layer-cap-hardening", "40e6", "--refinement", "3",
                   "--boundary", bnd, "--gravity", grav, "--friction", repr(mu), "--json"]
            r = subprocess.run(cmd, capture_output=True, text=True)
            if r.returncode != 0:
                print("v = %d, x = %s: failed: %s" % (v, (E, c, phi, x0, t, mu), r.stderr.strip()[:80]))
                continue
            e = abs(json.loads(r.stdout)["energy_error"])
            worst = max(worst, e)
        print("v = %d m/s: %d points, largest |energy error| %.2g of KE" % (v, len(pts), worst))
    print()


NOMINAL = "100000000, 10000, 40, 200000, 1"  # x_text of the nominal point (E, c, phi, X0, t)


def partial(root, suffix, speeds):
    """A run stopped before its end (no result.json): what its store holds."""
    for v in speeds:
        d = os.path.join(root, "s5_v%d%s" % (v, suffix))
        if not os.path.exists(os.path.join(d, "store.sqlite")):
            continue
        ev = load_store(d)
        cls = [classify(e) if e["ok"] != -1 else "unfinished" for e in ev]
        done = [e for e, c in zip(ev, cls) if c != "unfinished"]
        print("### %d m/s, unfinished run: its store\n" % v)
        print("%d evaluations stored, %d more started and not finished (running, or killed): ok %d, deep %d, at rest %d, "
              "no rebound %d, not ended %d, failed %d; model seconds summed %.0f" % (
                  len(done), cls.count("unfinished"), cls.count("ok"), cls.count("deep"), cls.count("at-rest"),
                  cls.count("no-rebound"), cls.count("not-ended"), cls.count("failed"),
                  sum(e["seconds"] for e in done)))
        okv = [e for e in done if e["ok"] == 1]
        if okv:
            print("over the %d ended points: R_n in [%.3g, %.3g], penetration_max in [%.3g, %.3g] m, "
                  "W_p/KE0 in [%.3g, %.3g], F_max in [%.3g, %.3g] N" % (
                      len(okv), min(e["R_n"] for e in okv), max(e["R_n"] for e in okv),
                      min(e["penetration_max"] for e in okv), max(e["penetration_max"] for e in okv),
                      min(e["plastic_work"] for e in okv), max(e["plastic_work"] for e in okv),
                      min(e["contact_force_max"] for e in okv), max(e["contact_force_max"] for e in okv)))
        for e in done:
            if e["x"] == NOMINAL and e["ok"] == 1:
                print("nominal point: " + ", ".join("%s %s" % (o, fmt(e[o])) for o in TABLE))
        for e in done:
            if e["ok"] != 1:
                print("failed at (E, c, phi, X0, t) = (%s): %s" % (e["x"], (e["error"] or "?")[:160]))
        print()


def fmt(x):
    return "%.3g" % x


def main():
    suffix = ""
    args = sys.argv[1:]
    if args and args[0].startswith("--suffix="):
        suffix = args.pop(0)[len("--suffix="):]
    root = args[0] if len(args) > 0 else "out"
    img = args[1] if len(args) > 1 else "docs/img"
    binary = args[2] if len(args) > 2 else None
    speeds = [v for v in SPEEDS if os.path.exists(os.path.join(root, "s5_v%d%s" % (v, suffix), "result.json"))]
    for v in SPEEDS:
        if v not in speeds:
            print("note: %s has no result.json (run unfinished): %d m/s left out\n"
                  % (os.path.join(root, "s5_v%d%s" % (v, suffix)), v))
    runs = {v: load(root, v, suffix) for v in speeds}
    partial(root, suffix, [v for v in SPEEDS if v not in speeds])

    print("### evaluations and cost\n")
    print("| v m/s | evaluations | ok | deep (pen >= 0.4 r0) | at rest (R_n = 0) | no rebound (R_n < 0)"
          " | not ended (failed at the bound) | failed (other) | model s (summed) | wall s |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for v, (res, ev) in runs.items():
        cls = [classify(e) for e in ev]
        print("| %d | %d | %d | %d | %d | %d | %d | %d | %.0f | %.0f |" % (
            v, len(ev), cls.count("ok"), cls.count("deep"), cls.count("at-rest"), cls.count("no-rebound"),
            cls.count("not-ended"),
            cls.count("failed"),
            sum(e["seconds"] for e in ev), res["wall_seconds"]))
    print()
    for v, (res, ev) in runs.items():
        msgs = {}
        for e in ev:
            if not e["ok"]:
                m = (e["error"] or "?")
                m = m.split(": ")[1] if "has not ended" in m else m.split(": ")[-1]
                m = m.split(" (")[0].split(" at t")[0]
                msgs.setdefault(m, []).append(e["x"])
        for m, xs in msgs.items():
            print("v = %d: %d x '%s', e.g. at (E, c, phi, X0, t) = (%s)" % (v, len(xs), m, xs[0]))
    print()

    print("### energy balance over the stores: R_n^2 + W_p/KE0 (<= 1 + W_g/KE0; W_g, gravity's work, is not\n"
          "an output: m g penetration_max / KE0 = 2 g pen / V^2 is the block's part, an estimate)\n")
    for v, (res, ev) in runs.items():
        g = float(res["model_identity"].split("gravity=")[1].split()[0]) if "gravity=" in res["model_identity"] else 0.0
        bal = [e["R_n"] ** 2 + e["plastic_work"] for e in ev if e["ok"]]
        net = [e["R_n"] ** 2 + e["plastic_work"] - 2 * g * e["penetration_max"] / v ** 2 for e in ev if e["ok"]]
        print("v = %d m/s (g = %g): R_n^2 + W_p/KE0 in [%.3f, %.3f]; less 2 g pen / V^2: [%.3f, %.3f]"
              % (v, g, min(bal), max(bal), min(net), max(net)))
    print()

    print("### supports (mu = 0), the mu = 0.5 cut and the nominal value (mu = 1)\n")
    print("| output | unit | " + " | ".join("%d m/s: support; mu=0.5; nominal" % v for v in speeds) + " |")
    print("|---|---|" + "---|" * len(speeds))
    for o in TABLE:
        cells = []
        for v in speeds:
            out = runs[v][0]["outputs"][o]
            lo, up, mu = out["lower"], out["upper"], out["mu"]
            h = mu.index(0.5) if 0.5 in mu else len(mu) // 2
            cells.append("[%s, %s]; [%s, %s]; %s" % (fmt(lo[0]), fmt(up[0]), fmt(lo[h]), fmt(up[h]),
                                                      fmt(out["nominal"])))
        print("| %s | %s | %s |" % (o, UNIT[o], " | ".join(cells)))
    print()

    print("### influence rho (Hanss), largest first\n")
    print("| output | " + " | ".join("%d m/s" % v for v in speeds) + " |")
    print("|---|" + "---|" * len(speeds))
    for o in SHOW:
        cells = []
        for v in speeds:
            inf = runs[v][0]["outputs"][o]["influence"]
            rho = {k: (val["rho"] if val["rho"] is not None else float("nan")) for k, val in inf.items()}
            order = sorted(rho, key=lambda k: -(rho[k] if rho[k] == rho[k] else -1))
            cells.append(", ".join("%s %.2f" % (k.replace("layer_", ""), rho[k]) for k in order))
        print("| %s | %s |" % (o, " | ".join(cells)))
    print()

    if binary:
        energy_errors(binary, runs)

    fig, axs = plt.subplots(2, 3, figsize=(12, 6.5))
    cols = {5: "tab:blue", 10: "tab:green", 20: "tab:red"}
    for a, o in zip(axs.flat, SHOW):
        for v in speeds:
            out = runs[v][0]["outputs"][o]
            xs = out["lower"] + out["upper"][::-1]
            ys = out["mu"] + out["mu"][::-1]
            a.plot(xs, ys, "-o", ms=3, color=cols[v], label="%d m/s" % v)
        a.set_xlabel("%s [%s]" % (o, UNIT[o]))
        a.set_ylabel("membership")
        a.grid(alpha=0.3)
    axs[0][0].legend(fontsize=8)
    grav = " ".join(sorted({"gravity=" + r[0]["model_identity"].split("gravity=")[1].split()[0][:4]
                            for r in runs.values() if "gravity=" in r[0]["model_identity"]}))
    fig.suptitle("S5: rigid boulder r0 = 0.5 m on a DP-cap colluvium layer over granite (large deformation%s)"
                 % (", " + grav if grav else ""))
    fig.tight_layout()
    os.makedirs(img, exist_ok=True)
    fig.savefig(os.path.join(img, "studies_s5%s_outputs.png" % suffix), dpi=80)

    names = list(runs[speeds[0]][0]["inputs"].keys())
    fig, axs = plt.subplots(1, 3, figsize=(12, 3.6))
    for a, o in zip(axs, ("R_n", "penetration_max", "contact_force_max")):
        w = 0.75 / len(speeds)
        for i, v in enumerate(speeds):
            inf = runs[v][0]["outputs"][o]["influence"]
            a.bar([k + (i - (len(speeds) - 1) / 2) * w for k in range(len(names))], [inf[n]["rho"] or 0 for n in names], w,
                  color=cols[v], label="%d m/s%s" % (v, "" if inf[names[0]]["rho"] is not None else " (rho n/a)"))
        a.set_xticks(range(len(names)))
        a.set_xticklabels([n.replace("layer_", "") for n in names], rotation=30, fontsize=8)
        a.set_title("rho for %s" % o)
        a.set_ylim(0, 1)
    axs[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(img, "studies_s5%s_influence.png" % suffix), dpi=80)
    print("wrote", os.path.join(img, "studies_s5%s_outputs.png" % suffix),
          os.path.join(img, "studies_s5%s_influence.png" % suffix))


if __name__ == "__main__":
    main()
