#!/usr/bin/env python3
"""mc_error.py - the Monte Carlo error of the S7 outputs (docs/studies.md S7)
at the sample count of a study, from one `rockfuzz trajectory --out DIR` run
of the same file with the same samples and seed (the study's nominal point,
bit for bit).

    python3 mc_error.py DIR COLLECTOR RUNOUT_COLUMN

For the collector's total energy p95 (over the blocks that reach it), its
reach probability, and the p50 and p95 of RUNOUT_COLUMN of samples.csv
(runout_x_m on a profile, runout_m on terrain): the estimate (Hyndman-Fan
type 7, as rockfuzz), the bootstrap standard error (2000 resamples of the
samples, seed 1), and for the percentiles the distribution-free 95 %
interval of the order statistics (ranks n p -+ 1.96 sqrt(n p (1 - p))).
Plain python3, no numpy."""
import csv
import math
import random
import sys


def pct(values, p):
    v = sorted(values)
    if not v:
        return float("nan")
    r = p * (len(v) - 1)
    j = int(r)
    return v[j] + (r - j) * (v[j + 1] - v[j]) if j + 1 < len(v) else v[j]


def order_interval(values, p):
    v = sorted(values)
    n = len(v)
    half = 1.96 * math.sqrt(n * p * (1 - p))
    lo, hi = max(0, int(math.floor(n * p - half)) - 1), min(n - 1, int(math.ceil(n * p + half)) - 1)
    return v[lo], v[hi]


def boot(samples, stat, n_boot=2000):
    rng = random.Random(1)
    vals = []
    for _ in range(n_boot):
        vals.append(stat([samples[rng.randrange(len(samples))] for _ in samples]))
    vals = [x for x in vals if x == x]
    m = sum(vals) / len(vals)
    return math.sqrt(sum((x - m) ** 2 for x in vals) / (len(vals) - 1))


def main():
    run, coll, col = sys.argv[1], sys.argv[2], sys.argv[3]
    samples = {r["sample"]: float(r[col]) for r in csv.DictReader(open(run + "/samples.csv"))}
    key = "collector" if "collector" in open(run + "/crossings.csv").readline() else "barrier"
    energy = {r["sample"]: float(r["total_energy_J"]) if r["reached"] == "1" else None
              for r in csv.DictReader(open(run + "/crossings.csv")) if r[key] == coll}
    rows = [(samples[s], energy.get(s)) for s in samples]
    n = len(rows)
    reached = [e for _, e in rows if e is not None]
    print(f"{run}: {n} samples, {len(reached)} reach {coll}")
    e95 = pct(reached, 0.95)
    se = boot(rows, lambda rs: pct([e for _, e in rs if e is not None], 0.95))
    lo, hi = order_interval(reached, 0.95)
    print(f"  {coll} total energy p95 {e95 / 1e3:.1f} kJ, bootstrap s.e. {se / 1e3:.1f} kJ ({100 * se / e95:.1f} %), "
          f"order-statistic 95 % interval [{lo / 1e3:.1f}, {hi / 1e3:.1f}] kJ")
    rp = len(reached) / n
    print(f"  {coll} reach probability {rp:.3f}, binomial s.e. {math.sqrt(rp * (1 - rp) / n):.3f}")
    for p in (0.50, 0.95):
        r = [x for x, _ in rows]
        v = pct(r, p)
        se = boot(rows, lambda rs: pct([x for x, _ in rs], p))
        lo, hi = order_interval(r, p)
        print(f"  {col} p{round(100 * p)} {v:.1f} m, bootstrap s.e. {se:.1f} m ({100 * se / v:.1f} %), "
              f"order-statistic 95 % interval [{lo:.1f}, {hi:.1f}] m")


if __name__ == "__main__":
    main()
