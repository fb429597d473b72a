#!/usr/bin/python3
"""axi_default_check.py - can the axisymmetric FE model's default refinement
(RF_FEM_REFINEMENT_AXI) be lowered?  (issue 9, docs/fem-speed.md "Time to
accuracy", docs/validation.md section 4.)

Usage: axi_default_check.py [rockfuzz=build/rockfuzz] [coarse=7,8,10]
                            [fine=20,30] [repeats=3]

For each case (normal impact at 1, 3, 10, 30 m/s on the default model:
automatic domain, fixed boundary, 1 thread; and the c = 1.1 m spheroid of S3
at 10 m/s) runs `rockfuzz impact --json --refinement A` at every coarse and
fine a/h and prints one key=value line per run: R_n, R_ke, F_max,
compression, t_c, contact radius, elements, steps, wall and CPU seconds (the
best of `repeats` runs for the coarse meshes, one run for the fine ones).
R_t is n/a (a normal impact has no tangential velocity).

Then, per case and coarse a/h, the deviation from the finest mesh
(relative for F_max, compression, t_c, contact radius; absolute for R_n and
R_ke) next to the difference between the two fine meshes, which bounds how
well the finest one is converged.  Nothing here is a pass/fail test: the
numbers are compared with the claims of docs/validation.md by hand."""
import json
import resource
import subprocess
import sys
import time

CASES = [("1ms", ["--velocity", "1"]), ("3ms", ["--velocity", "3"]), ("10ms", ["--velocity", "10"]),
         ("30ms", ["--velocity", "30"]), ("spheroid_c1.1", ["--velocity", "10", "--c", "1.1"])]
FIELDS = [("R_n", "R_n", "abs"), ("R_ke", "R_ke", "abs"), ("F_max", "contact_force_max", "rel"),
          ("compression", "compression_max", "rel"), ("t_c", "contact_duration", "rel"),
          ("a_c", "contact_radius", "rel")]


def run(exe, args, a):
    """One impact: its JSON output, wall and CPU seconds of the child."""
    cmd = [exe, "impact", "--json", "--threads", "1", "--refinement", str(a)] + args
    c0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.monotonic()
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    wall = time.monotonic() - t0
    c1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (c1.ru_utime - c0.ru_utime) + (c1.ru_stime - c0.ru_stime)
    return json.loads(out), wall, cpu


def measure(exe, name, args, a, repeats):
    best = None
    for _ in range(repeats):
        o, wall, cpu = run(exe, args, a)
        if best is None:
            best = [o, wall, cpu]
        best[1], best[2] = min(best[1], wall), min(best[2], cpu)
    o, wall, cpu = best
    line = "case=%s ref=%g elements=%d steps=%d wall=%.3f cpu=%.3f" % (name, a, o["elements"], o["steps"], wall, cpu)
    line += "".join(" %s=%.9g" % (k, o[j]) for k, j, _ in FIELDS)
    print(line, flush=True)
    return o


def dev(o, ref, key, kind):
    return o[key] - ref[key] if kind == "abs" else o[key] / ref[key] - 1


def summary(name, res, coarse, fine):
    ref, ref2 = res[fine[-1]], res[fine[-2]] if len(fine) > 1 else None
    print("# %s: deviation from a/h = %g (R_n, R_ke absolute; others relative)" % (name, fine[-1]))
    rows = [(str(a), res[a]) for a in coarse]
    if ref2 is not None:
        rows.append(("%g (fine-fine)" % fine[-2], ref2))
    for label, o in rows:
        print("#   a/h %-14s" % label + "".join(" %s %+.2e" % (k, dev(o, ref, j, t)) for k, j, t in FIELDS))


def main():
    exe = sys.argv[1] if len(sys.argv) > 1 else "build/rockfuzz"
    coarse = [float(x) for x in (sys.argv[2] if len(sys.argv) > 2 else "7,8,10").split(",")]
    fine = [float(x) for x in (sys.argv[3] if len(sys.argv) > 3 else "20,30").split(",")]
    repeats = int(sys.argv[4]) if len(sys.argv) > 4 else 3
    print("# load average at start: " + " ".join(open("/proc/loadavg").read().split()[:3]))
    for name, args in CASES:
        res = {a: measure(exe, name, args, a, repeats) for a in coarse}
        res.update({a: measure(exe, name, args, a, 1) for a in fine})
        summary(name, res, coarse, fine)
    print("# load average at end: " + " ".join(open("/proc/loadavg").read().split()[:3]))


if __name__ == "__main__":
    main()
