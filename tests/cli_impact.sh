#!/usr/bin/env bash
# cli_impact.sh - `rockfuzz impact` from the shell: JSON output against the
# Hertz numbers of impact_refs.md sec. 1.2, and bad input rejected with a
# message naming the option.  Usage: bash cli_impact.sh ROCKFUZZ SOURCE_DIR
set -u
. "${BASH_SOURCE[0]%/*}/cli_lib.sh"

# --- JSON output parses and matches Hertz at 1, 10, 30 m/s ---
check_hertz() { # velocity F delta t_c a
    local out
    out=$("$bin" impact --solver hertz --velocity "$1" --json) || { fail "hertz $1 m/s exit $?"; return; }
    if command -v python3 >/dev/null; then
        python3 - "$out" "$@" <<'PY' || fail "hertz $1 m/s: $out"
import json, sys
o = json.loads(sys.argv[1])
want = dict(zip(["contact_force_max", "compression_max", "contact_duration", "contact_radius"],
                map(float, sys.argv[3:7])))
keys = ["contact_force_max", "compression_max", "contact_duration", "contact_radius", "R_n", "R_t",
        "R_ke", "energy_error", "plastic_work", "penetration_max", "indentation_depth",
        "equivalent_plastic_strain_max", "nodes", "elements", "steps", "gravity", "at_rest", "wall_seconds"]
assert list(o) == keys, list(o)
for k, w in want.items():
    assert abs(o[k] / w - 1) < 1e-3, (k, o[k], w)
assert o["R_n"] == 1 and o["R_ke"] == 1 and o["R_t"] is None, o
PY
    else
        echo "$out" | grep -q '"R_t": null' || fail "hertz JSON: $out"
    fi
}
check_hertz 1 5.6842e6 2.3950e-3 7.0491e-3 0.04894
check_hertz 10 9.0089e7 1.51112e-2 4.4477e-3 0.12293
check_hertz 30 3.3668e8 3.63913e-2 3.5703e-3 0.19077

# --- rigid sliding row of impact_refs.md sec. 4.1 ---
out=$("$bin" impact --solver rigid --e-n 0.98 --slope-angle 60 --friction=0.2 --json) || fail "rigid exit"
echo "$out" | grep -q '"R_t": 0.7713' || fail "rigid R_t: $out"
echo "$out" | grep -q '"contact_force_max": null' || fail "rigid force should be null: $out"

# --- human summary has units ---
out=$("$bin" impact --solver hunter) || fail "hunter summary exit"
echo "$out" | grep -q 'max contact force .* N' || fail "summary lacks units: $out"
"$bin" impact --help | grep -q -- '--slope-angle DEG' || fail "help lacks --slope-angle"

# --- bad input: non-zero exit, message names the option and value ---
expect_error() { # expected-status expected-text args...
    local want=$1 text=$2 err status
    shift 2
    err=$("$bin" impact "$@" 2>&1 >/dev/null)
    status=$?
    [ "$status" -eq "$want" ] || fail "'$*' exited $status, want $want"
    case "$err" in *"$text"*) ;; *) fail "'$*' message '$err' lacks '$text'" ;; esac
}
expect_error 2 "--radius 'abc'" --solver hertz --radius abc
expect_error 2 "--velocity '10x'" --solver hertz --velocity 10x
expect_error 2 "--boulder-poisson 0.5" --solver hertz --boulder-poisson 0.5
expect_error 2 "Poisson's ratio" --solver hertz --slope-poisson 0.7
expect_error 2 "--slope-E -68e9" --solver hertz --slope-E -68e9
expect_error 2 "--boulder-E 'inf'" --solver hertz --boulder-E inf
expect_error 2 "unknown option '--frobnicate'" --frobnicate 3
expect_error 2 "solver 'abaqus'" --solver abaqus
expect_error 2 "--slope-angle 90" --solver rigid --slope-angle 90
expect_error 2 "--friction -0.2" --solver rigid --friction -0.2
expect_error 2 "'--velocity' needs a value" --solver hertz --velocity
expect_error 2 "--threads '-1'" --threads -1
expect_error 1 "horizontal_axis" --solver hertz --c 1.2 --slope-angle 30
# materials: the option and value named
expect_error 2 "--slope-material 'clay'" --slope-material clay
expect_error 2 "--boulder-material 'drucker_prager'" --boulder-material drucker_prager
expect_error 2 "slope_yield = 0" --slope-material von_mises
expect_error 2 "--slope-yield -5" --slope-material von_mises --slope-yield -5
expect_error 2 "--slope-dilatancy-angle 40" --slope-material drucker_prager --slope-cohesion 1e4 \
    --slope-friction-angle 30 --slope-dilatancy-angle 40
expect_error 2 "--slope-cap-pressure -1" --slope-material drucker_prager --slope-cohesion 1e4 \
    --slope-friction-angle 30 --slope-cap-pressure -1
expect_error 2 "--boulder-hardening -1" --boulder-material von_mises --boulder-yield 1e8 --boulder-hardening -1
# the 3D model takes a rigid boulder and a layer (test_fem3d_layer); a layer thinner than its contact element is refused
expect_error 1 "layer_thickness = 0.001 m is thinner than the element" --layer-thickness 0.001 --slope-angle 30
"$bin" impact --boulder-material rigid --slope-angle 30 --friction 0.5 --refinement 2 >/dev/null 2>&1 ||
    fail "3D refused a rigid boulder"
"$bin" impact --help | grep -q -- '--slope-cap-pressure PA' || fail "help lacks --slope-cap-pressure"
# a layer: its inputs named, FE only
expect_error 2 "--layer-thickness -1" --layer-thickness -1
expect_error 2 "layer_yield = 0" --layer-thickness 0.1 --layer-material von_mises
expect_error 2 "--layer-E -5" --layer-thickness 0.1 --layer-E -5
expect_error 2 "--layer-material 'sand'" --layer-material sand
expect_error 1 "has no layer" --solver hunter --layer-thickness 0.1
expect_error 1 "the hertz solver is elastic" --solver hertz --slope-material von_mises --slope-yield 1e8
# large deformation: the value named; the 3D model takes it too (a short run)
expect_error 2 "large_deformation 'maybe'" --large-deformation maybe
"$bin" impact --help | grep -q -- '--large-deformation K' || fail "help lacks --large-deformation"
# ale: off | on (auto meant off and is gone); the internal numerics are no options
expect_error 2 "--ale 'auto': ale 'auto' is unknown (accepted: off | on)" --ale auto
expect_error 2 "unknown option '--sphere-contact-3d'" --sphere-contact-3d on
expect_error 2 "unknown option '--surface-mass-3d'" --surface-mass-3d on
"$bin" impact --solver fem --large-deformation on --slope-angle 30 --friction 0.5 --refinement 2 --domain-factor 3 \
    --threads 1 --end-time 2e-4 >/dev/null 2>&1 || fail "3D refused --large-deformation on"
# the simulated time [s]: named with its value and unit; in the help
expect_error 2 "end_time = -1" --end-time -1
expect_error 2 "--end-time 'soon'" --end-time soon
"$bin" impact --help | grep -q -- '--end-time S' || fail "help lacks --end-time"
# a rigid boulder: Hertz with E* = E_s / (1 - nu_s^2) (F = 1.18873e8 N at 10 m/s)
out=$("$bin" impact --solver hertz --boulder-material rigid --json) || fail "rigid hertz exit"
echo "$out" | grep -q '"contact_force_max": 11887' || fail "rigid boulder Hertz force: $out"

# --- FE on the coarsest mesh, when the solver is built ---
out=$("$bin" impact --solver fem --refinement 2 --boundary absorbing --json 2>/dev/null)
status=$?
if [ $status -eq 0 ]; then
    if command -v python3 >/dev/null; then
        python3 - "$out" <<'PY' || fail "fem JSON: $out"
import json, sys
o = json.loads(sys.argv[1])
assert abs(o["contact_force_max"] / 9.0089e7 - 1) < 0.1, o
assert 0.95 < o["R_n"] < 1.0 and o["nodes"] > 0 and o["steps"] > 0, o
assert abs(o["energy_error"]) < 1e-2, o
assert o["plastic_work"] == 0 and o["equivalent_plastic_strain_max"] == 0, o
PY
        out=$("$bin" impact --refinement 2 --slope-material von_mises --slope-yield 2e8 --json 2>/dev/null) \
            || fail "plastic fem exit"
        python3 - "$out" <<'PY' || fail "plastic fem JSON: $out"
import json, sys
o = json.loads(sys.argv[1])
# J2 slope, Y = 200 MPa, 10 m/s: Thornton (p_y = 1.55 Y) 0.30 < R_n < Johnson 0.55 (plasticity_refs.md 1.5)
assert 0.3 < o["R_n"] < 0.6 and 0.3 < o["plastic_work"] < 0.9, o
assert 0 < o["indentation_depth"] < o["penetration_max"] and o["equivalent_plastic_strain_max"] > 0, o
assert abs(o["energy_error"]) < 5e-3, o
PY
    fi
    # the default uses all cores: the same numbers as one thread (all but the wall time), for the
    # axisymmetric and the 3D model
    for args in "--refinement 2 --boundary absorbing" "--refinement 2 --slope-angle 45 --friction 0.6"; do
        # shellcheck disable=SC2086
        a=$("$bin" impact --solver fem $args --json | sed 's/, "wall_seconds".*//')
        # shellcheck disable=SC2086
        b=$("$bin" impact --solver fem $args --threads 1 --json | sed 's/, "wall_seconds".*//')
        [ -n "$a" ] && [ "$a" = "$b" ] || fail "fem $args: default threads differ from 1 thread: $a / $b"
    done
else
    err=$("$bin" impact --solver fem --refinement 2 2>&1 >/dev/null)
    case "$err" in *"not built"*) echo "cli_impact: FE solver not built, FE check skipped" ;;
        *) fail "fem run exited $status: $err" ;; esac
fi

# --- --vtk DIR: a missing DIR (and its parents) is created, for both geometries; a DIR that
# cannot be created is named, with a non-zero exit ---
if [ "$status" -eq 0 ]; then # the FE solver is built
    tmp=$(mktemp -d)
    for args in "" "--slope-angle 45"; do
        # shellcheck disable=SC2086
        "$bin" impact --solver fem --refinement 2 --end-time 5e-4 $args --vtk "$tmp/new/vtk" --json >/dev/null \
            || fail "--vtk into a missing directory ($args): exit $?"
        [ -s "$tmp/new/vtk/fem.pvd" ] && [ -s "$tmp/new/vtk/fem_0000.vtu" ] \
            || fail "--vtk ($args): no fem.pvd / fem_0000.vtu in the created directory"
        rm -rf "$tmp/new"
    done
    : >"$tmp/file"
    msg=$("$bin" impact --solver fem --refinement 2 --end-time 5e-4 --vtk "$tmp/file/vtk" 2>&1 >/dev/null) \
        && fail "--vtk under a regular file: exit 0"
    case "$msg" in *"--vtk"*"$tmp/file/vtk"*) ;; *) fail "--vtk under a regular file: message '$msg'" ;; esac
    rm -rf "$tmp"
fi

# --- a rough block at normal incidence on a soil (the axisymmetric contact's friction): the JSON
# names friction_work after at_rest, a small positive fraction of KE0; without friction it is absent ---
if [ "$status" -eq 0 ] && command -v python3 >/dev/null; then
    soil="--boulder-material rigid --radius 0.5 --layer-thickness 1 --layer-material drucker_prager
          --layer-density 1900 --layer-E 100e6 --layer-poisson 0.3 --layer-cohesion 10e3 --layer-friction-angle 40
          --layer-cap-pressure 200e3 --layer-cap-hardening 40e6 --refinement 2 --end-time 0.01"
    # shellcheck disable=SC2086
    rough=$("$bin" impact $soil --friction 0.6 --json 2>/dev/null) || fail "rough block: exit $?"
    # shellcheck disable=SC2086
    smooth=$("$bin" impact $soil --json 2>/dev/null) || fail "smooth block: exit $?"
    python3 - "$rough" "$smooth" <<'PY' || fail "friction_work in the JSON: $rough / $smooth"
import json, sys
r, s = json.loads(sys.argv[1]), json.loads(sys.argv[2])
k = list(r)
assert k[k.index("at_rest") + 1] == "friction_work", k
assert 0 < r["friction_work"] < 0.05, r
assert "friction_work" not in s, s
PY
fi

[ "$fails" -eq 0 ] && echo "cli_impact: all checks passed"
exit $((fails > 0))
