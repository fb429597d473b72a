#!/bin/bash
# s6_points.sh - the S6 points of docs/studies.md: the S5 nominal soil (1 m of
# colluvium over granite), rigid boulder r0 = 0.5 m, 10 m/s vertical, gravity
# 0, on the 30/45/60 degree slopes with friction 0 and 1, in the 3D model in
# large deformation at a/h 2 (bench_fem3d_soil), and the same on bare granite
# (rockfuzz impact, a/h 3).  One thread per run; CPU seconds printed.
#   bash tools/s6_points.sh [BUILD_DIR]
B=${1:-build}
for a in 30 45 60; do
  for f in 0 1; do
    /usr/bin/time -f "  time: %U s user %e s wall" nice "$B"/bench_fem3d_soil model=3d large=1 angle=$a f=$f 2
    echo -n "granite angle=$a f=$f: "
    nice "$B"/rockfuzz impact --radius 0.5 --boulder-material rigid --slope-angle $a --friction $f \
      --refinement 3 --threads 1 --json | python3 -c "import json,sys; d=json.load(sys.stdin); \
print(' '.join(f'{k}={d[k]:.4g}' for k in ['R_n','R_t','R_ke','energy_error','elements','steps']))"
  done
done
