#!/bin/sh
# tools/s4_spread.sh - the spread of R_n over the friction coefficient (issue 9,
# point 4; docs/studies.md S4): nominal granite, r0 = 1 m, 10 m/s vertical onto
# a slope, f = 0, 0.1, ..., 1.0, with the 3D FE model (`rockfuzz impact`).
# For identical elastic bodies the normal and tangential contact problems
# uncouple (Dundurs beta = 0), so R_n should hardly depend on f; max - min of
# R_n over f measures what the mesh and the domain add.
# Domains: "auto" = the default (automatic size, fixed boundary, no reflected
# P wave back into the contact); "fixed10" = --domain-factor 10 --boundary fixed,
# the seed paper's model (the reflection returns before the contact ends).
# Prints one row per run and a spread line per (angle, a/h, domain).
# Usage: tools/s4_spread.sh [rockfuzz-binary]
#   ANGLES="30 45 60" REFS="3" DOMAINS="auto fixed10" FS="0 0.1 ... 1" to narrow.
# One run is ~0.7 s (a/h = 3) / ~2 s (a/h = 4) of CPU on one core.
set -e
src=$(cd "$(dirname "$0")/.." && pwd)
RF=${1:-$src/build/rockfuzz}
ANGLES=${ANGLES:-"30 45 60"}
REFS=${REFS:-"3"}
DOMAINS=${DOMAINS:-"auto fixed10"}
FS=${FS:-"0 0.1 0.2 0.3 0.4 0.5 0.6 0.7 0.8 0.9 1.0"}
printf '%-5s %-4s %-8s %-4s %-9s %-9s %-9s\n' angle a/h domain f R_n R_t R_ke
for ang in $ANGLES; do
    for ref in $REFS; do
        for dom in $DOMAINS; do
            case $dom in
                auto) dopt="" ;;
                fixed10) dopt="--domain-factor 10 --boundary fixed" ;;
                *) echo "unknown domain $dom" >&2; exit 2 ;;
            esac
            rows=""
            for f in $FS; do
                # shellcheck disable=SC2086
                j=$("$RF" impact --velocity 10 --slope-angle "$ang" --friction "$f" \
                        --refinement "$ref" --threads 1 $dopt --json 2>/dev/null)
                r=$(echo "$j" | jq -r '"\(.R_n) \(.R_t) \(.R_ke)"')
                echo "$r" | awk -v a="$ang" -v h="$ref" -v d="$dom" -v f="$f" \
                    '{printf "%-5s %-4s %-8s %-4s %.6f  %.6f  %.6f\n", a, h, d, f, $1, $2, $3}'
                rows="$rows$f $r
"
            done
            printf '%s' "$rows" | awk -v a="$ang" -v h="$ref" -v d="$dom" '
                NF == 4 { if (n == 0 || $2 < lo) { lo = $2; flo = $1 }
                          if (n == 0 || $2 > hi) { hi = $2; fhi = $1 } n++ }
                END { printf "spread %s deg a/h=%s %s: R_n in [%.6f (f=%s), %.6f (f=%s)], max-min = %.2e\n",
                      a, h, d, lo, flo, hi, fhi, hi - lo }'
        done
    done
done
