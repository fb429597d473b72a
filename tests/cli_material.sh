#!/usr/bin/env bash
# cli_material.sh - `rockfuzz material` from the shell: JSON keys, values
# against the closed forms of docs/materials.md (J2 uniaxial strain, DP
# simple shear, apex, cap in confined compression), and bad input rejected
# with a message naming the option and value.
# Usage: bash cli_material.sh ROCKFUZZ SOURCE_DIR
set -u
. "${BASH_SOURCE[0]%/*}/cli_lib.sh"

# check 'python assertion over o (the JSON object)' args...
check() {
    local expr=$1 out
    shift
    out=$("$bin" material "$@" --json) || { fail "'$*' exit $?"; return; }
    python3 - "$out" "$expr" <<'PY' || fail "'$*': $out"
import json, math, sys
o = json.loads(sys.argv[1])
keys = ["model", "path", "strain", "increments", "stress_xx", "stress_yy", "stress_zz", "stress_xy",
        "mean_stress", "equivalent_plastic_strain", "plastic_volumetric_strain", "plastic_work"]
assert list(o) == keys, list(o)
def close(a, b, rtol=1e-9):
    return abs(a - b) <= rtol * max(abs(a), abs(b), 1e-300)
E, nu = 200e9, 0.3
G, K = E / (2 * (1 + nu)), E / (3 * (1 - 2 * nu))
def dp(phi):
    s = math.sin(math.radians(phi))
    return 6 * s / (math.sqrt(3) * (3 - s)), 6 * math.cos(math.radians(phi)) / (math.sqrt(3) * (3 - s))
assert eval(sys.argv[2]), sys.argv[2]
PY
}

if command -v python3 >/dev/null; then
    # J2, uniaxial strain 1 %: eps_p = (2 G eps - Y)/(3G + H), sxx - syy = Y + H eps_p
    vm="--model von_mises --E 200e9 --poisson 0.3 --yield 250e6 --hardening 1e9 --path uniaxial_strain --strain 0.01"
    j2='close(o["stress_xx"] - o["stress_yy"], 250e6 + 1e9 * (2*G*0.01 - 250e6) / (3*G + 1e9)) and close(o["mean_stress"], K * 0.01)'
    check "$j2" $vm
    check "$j2" $vm --increments 1
    check "$j2" $vm --increments=5000
    # elastic limit: sigma_xx = Y (1 - nu)/(1 - 2 nu) at eps = Y/(2G)
    check 'close(o["stress_xx"], 250e6 * 0.7 / 0.4) and o["equivalent_plastic_strain"] == 0' \
        --model von_mises --E 200e9 --poisson 0.3 --yield 250e6 --path uniaxial_strain --strain 0.0016249999999
    # elastic model
    check 'close(o["stress_xy"], G * 1e-3) and o["plastic_work"] == 0' \
        --model elastic --E 200e9 --poisson 0.3 --path simple_shear --strain 1e-3
    # DP simple shear from p0 = -100 kPa: tau = xi c - eta p0
    check 'close(o["stress_xy"], dp(32)[1] * 1e3 + dp(32)[0] * 1e5) and close(o["mean_stress"], -1e5)' \
        --model drucker_prager --E 20e6 --poisson 0.3 --cohesion 1e3 --friction-angle 32 \
        --path simple_shear --strain 0.05 --initial-mean-stress -1e5 --increments 3
    # DP dilatant simple shear at constant volume with a dilatancy cutoff of 1 %: the dilation
    # stops there, p = p0 - K 0.01, tau = xi c - eta p (the critical state)
    check 'close(o["plastic_volumetric_strain"], 0.01) and close(o["mean_stress"], -1e5 - K / 1e4 * 0.01) and close(o["stress_xy"], dp(35)[1] * 1e3 - dp(35)[0] * (-1e5 - K / 1e4 * 0.01))' \
        --model drucker_prager --E 20e6 --poisson 0.3 --cohesion 1e3 --friction-angle 35 --dilatancy-angle 10 \
        --dilatancy-cutoff 0.01 --path simple_shear --strain 0.5 --initial-mean-stress -1e5 --increments 7
    # DP hydrostatic tension: apex c cot(phi)
    check 'close(o["mean_stress"], 1e3 / math.tan(math.radians(32))) and o["stress_xy"] == 0' \
        --model drucker_prager --E 20e6 --poisson 0.3 --cohesion 1e3 --friction-angle 32 --dilatancy-angle 10 \
        --path hydrostatic --strain 0.01
    # confined compression: plain cone elastic; the cap yields, p = -(X0 + Hc eps_c)
    check 'o["equivalent_plastic_strain"] == 0 and close(o["stress_xx"], -0.01 * (K + 4 * G / 3) / 1e4)' \
        --model drucker_prager --E 20e6 --poisson 0.3 --cohesion 1e3 --friction-angle 35 \
        --path uniaxial_strain --strain -0.01
    check 'close(o["mean_stress"], -(4e4 + 2e6 * ((K / 1e4 * 0.005 - 4e4) / (K / 1e4 + 2e6))))' \
        --model drucker_prager --E 20e6 --poisson 0.3 --cohesion 1e3 --friction-angle 35 \
        --cap-pressure 4e4 --cap-hardening 2e6 --path uniaxial_strain --strain -0.005
    # virgin confined compression along the cone-cap corner, c = 0: lateral/axial
    # stress = Mohr-Coulomb's active ratio (1 - sin phi)/(1 + sin phi)
    check 'close(o["stress_yy"] / o["stress_xx"], (1 - math.sin(math.radians(35))) / (1 + math.sin(math.radians(35))))' \
        --model drucker_prager --E 20e6 --poisson 0.3 --cohesion 0 --friction-angle 35 \
        --cap-pressure 2e4 --cap-hardening 5e6 --path uniaxial_strain --strain -0.05
fi

# --history: a header and one row per increment
n=$("$bin" material --model elastic --E 1e9 --poisson 0.2 --path hydrostatic --strain 1e-3 --increments 7 --history | wc -l)
[ "$n" -eq 8 ] || fail "--history printed $n lines, want 8"
"$bin" material --model elastic --E 1e9 --poisson 0.2 --path hydrostatic --strain 1e-3 | grep -q 'mean_stress .* Pa' \
    || fail "summary lacks units"
"$bin" material --help | grep -q -- '--cap-pressure PA' || fail "help lacks --cap-pressure"
"$bin" --help | grep -q 'material' || fail "rockfuzz --help lacks material"

# --- bad input: exit 2, message names the option and value ---
expect_error() { # expected-text args...
    local text=$1 err status
    shift
    err=$("$bin" material "$@" 2>&1 >/dev/null)
    status=$?
    [ "$status" -eq 2 ] || fail "'$*' exited $status, want 2"
    case "$err" in *"$text"*) ;; *) fail "'$*' message '$err' lacks '$text'" ;; esac
}
base="--E 1e9 --poisson 0.3 --path uniaxial_strain --strain -0.01"
expect_error "--model: material model 'cam_clay'" --model cam_clay $base
expect_error "--E -1e9" --model elastic --E -1e9 --poisson 0.3 --path hydrostatic --strain 0.01
expect_error "--poisson 0.5" --model elastic --E 1e9 --poisson 0.5 --path hydrostatic --strain 0.01
expect_error "--E 'abc'" --model elastic --E abc --poisson 0.3 --path hydrostatic --strain 0.01
expect_error "--model is required" $base
expect_error "--strain is required" --model elastic --E 1e9 --poisson 0.3 --path hydrostatic
expect_error "--yield is required" --model von_mises $base
expect_error "--yield 0" --model von_mises --yield 0 $base
expect_error "--hardening -5" --model von_mises --yield 1e6 --hardening -5 $base
expect_error "--cohesion 1e3: not an option of --model von_mises" --model von_mises --yield 1e6 --cohesion 1e3 $base
expect_error "--friction-angle is required" --model drucker_prager --cohesion 1e3 $base
expect_error "--friction-angle 95" --model drucker_prager --cohesion 1e3 --friction-angle 95 $base
expect_error "--dilatancy-angle 40" --model drucker_prager --cohesion 1e3 --friction-angle 30 --dilatancy-angle 40 $base
expect_error "--cohesion -1" --model drucker_prager --cohesion -1 --friction-angle 30 $base
expect_error "--cap-pressure 1e4: the cap needs both" --model drucker_prager --cohesion 1e3 --friction-angle 30 --cap-pressure 1e4 $base
expect_error "--cap-pressure 0" --model drucker_prager --cohesion 1e3 --friction-angle 30 --cap-pressure 0 --cap-hardening 1e6 $base
expect_error "--dilatancy-cutoff 0: must be" --model drucker_prager --cohesion 1e3 --friction-angle 30 --dilatancy-cutoff 0 $base
expect_error "--dilatancy-cutoff -0.1" --model drucker_prager --cohesion 1e3 --friction-angle 30 --dilatancy-cutoff -0.1 $base
expect_error "--cap-hardening -1" --model drucker_prager --cohesion 1e3 --friction-angle 30 --cap-pressure 1e4 --cap-hardening -1 $base
expect_error "--path 'triaxial'" --model elastic --E 1e9 --poisson 0.3 --path triaxial --strain 0.01
expect_error "--strain 2" --model elastic --E 1e9 --poisson 0.3 --path hydrostatic --strain 2
expect_error "--increments '0'" --model elastic --E 1e9 --poisson 0.3 --path hydrostatic --strain 0.01 --increments 0
expect_error "--initial-mean-stress 1e5" --model drucker_prager --cohesion 1e3 --friction-angle 30 --initial-mean-stress 1e5 $base
expect_error "--initial-mean-stress -1e5" --model drucker_prager --cohesion 1e3 --friction-angle 30 --cap-pressure 5e4 --cap-hardening 1e6 --initial-mean-stress -1e5 $base
expect_error "unknown option '--frobnicate'" --frobnicate 3
expect_error "'--strain' needs a value" --model elastic --E 1e9 --poisson 0.3 --path hydrostatic --strain
expect_error "exclude each other" --model elastic --E 1e9 --poisson 0.3 --path hydrostatic --strain 0.01 --json --history

if [ $fails -ne 0 ]; then
    echo "$fails failure(s)" >&2
    exit 1
fi
echo "cli_material: all checks passed"
