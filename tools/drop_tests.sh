#!/bin/sh
# tools/drop_tests.sh - the model runs of docs/validation-plastic.md section 8
# ("Against drop tests"): `rockfuzz impact` (axisymmetric FE, default
# kinematics, rigid block, Drucker-Prager + cap soil layer, gravity
# $GRAVITY: default auto = 9.81 m/s^2 with the plastic layer) for the published test
# set-ups that could be read (the cases and their sources are listed in
# tools/data/drop_tests_cases.txt, one case a line).  No parameter is fitted:
# the soil values are the nominal ones of the docs/materials.md rows named in
# the cases file.  Writes OUT/drop_tests.jsonl (one JSON object per case: the
# case's inputs, then the model's outputs or its error message); then
#   /usr/bin/python3 tools/drop_tests_plot.py OUT docs/img
# draws docs/img/drop_tests.png and prints the tables of the section.
# ~1 min of CPU on one core.
# Usage: [GRAVITY=auto|G] [DILATANCY_CUTOFF=EPS] [FRICTION=MU] [REFINEMENT=A] [CASES=file] tools/drop_tests.sh [build-dir] [out-dir]
# (CASES: another case list of the same columns, e.g. a part of the default
# one to run parts in parallel and concatenate their drop_tests.jsonl)
set -e
src=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$src/build}
out=${2:-$build/drop-tests}
grav=${GRAVITY:-auto}
cutoff=${DILATANCY_CUTOFF:-0}   # the layer's dilatancy cutoff (docs/materials.md), 0 = none
friction=${FRICTION:-0}         # Coulomb friction of the block on the soil, 0 = frictionless
refinement=${REFINEMENT:-3}     # the FE refinement (a/h)
cases=${CASES:-$src/tools/data/drop_tests_cases.txt}
mkdir -p "$out"
cmake -S "$src" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j2 --target rockfuzz_cli >/dev/null
bin="$build/rockfuzz"
R="$out/drop_tests.jsonl"
: > "$R"
# columns: case group mass_kg radius_m v_ms layer_m soil bedrock
grep -v '^#' "$cases" | while read -r id group mass radius v layer soil bed; do
    [ -n "$id" ] || continue
    rho=$(python3 -c "import math; print('%.6g' % ($mass / (4 / 3 * math.pi * $radius ** 3)))")
    case $soil in # docs/materials.md rows (nominal = middle of each range); the cap from its oedometer table
    loose_sand)  s="--layer-density 1600 --layer-E 45e6 --layer-poisson 0.3 --layer-cohesion 1e3 --layer-friction-angle 31 --layer-dilatancy-angle 1.5 --layer-cap-pressure 20e3 --layer-cap-hardening 10e6" ;;
    dense_sand)  s="--layer-density 1850 --layer-E 200e6 --layer-poisson 0.3 --layer-cohesion 1e3 --layer-friction-angle 39 --layer-dilatancy-angle 9 --layer-cap-pressure 20e3 --layer-cap-hardening 37e6" ;;
    colluvium)   s="--layer-density 1900 --layer-E 100e6 --layer-poisson 0.3 --layer-cohesion 10e3 --layer-friction-angle 40 --layer-dilatancy-angle 5 --layer-cap-pressure 200e3 --layer-cap-hardening 40e6" ;;
    *) echo "unknown soil $soil" >&2; exit 2 ;;
    esac
    case $bed in
    concrete) b="--slope-E 30e9 --slope-poisson 0.2 --slope-density 2400" ;;
    granite)  b="" ;;
    *) echo "unknown bedrock $bed" >&2; exit 2 ;;
    esac
    # shellcheck disable=SC2086
    if res=$(nice "$bin" impact --boulder-material rigid --radius "$radius" --boulder-density "$rho" --velocity "$v" \
            --layer-thickness "$layer" --layer-material drucker_prager $s $b \
            --layer-dilatancy-cutoff "$cutoff" --friction "$friction" --refinement "$refinement" --boundary fixed --gravity "$grav" --json 2> "$out/err.txt"); then
        warn=$(tr '\n' ' ' < "$out/err.txt" | sed 's/"/\\"/g')
        echo "{\"case\": \"$id\", \"group\": \"$group\", \"mass\": $mass, \"radius\": $radius, \"velocity\": $v, \"layer\": $layer, \"soil\": \"$soil\", \"bedrock\": \"$bed\", \"warning\": \"$warn\", \"out\": $res}" >> "$R"
    else
        msg=$(tr '\n' ' ' < "$out/err.txt" | sed 's/"/\\"/g')
        echo "{\"case\": \"$id\", \"group\": \"$group\", \"mass\": $mass, \"radius\": $radius, \"velocity\": $v, \"layer\": $layer, \"soil\": \"$soil\", \"bedrock\": \"$bed\", \"error\": \"$msg\"}" >> "$R"
    fi
    echo "$id done"
done
echo "results in $R"
