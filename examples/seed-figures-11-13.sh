#!/usr/bin/env bash
# Eigenvector analysis as in the seed paper's Figures 11 to 13: phasor diagrams,
# rate phases, whirl and animated mode shapes at one rotor speed below, one
# inside and one above the unstable range of
#   Figure 11: three-bladed soft in-plane rotor, body x and y  (soft-inplane),
#   Figure 12: the same blades with flap, body pitch and roll  (soft-inplane-pitch-roll),
#   Figure 13: four-bladed articulated rotor, anisotropic hub  (hammond-undamped).
# Speeds in rpm (the cases' unit; reference 155 rpm).
# Run from anywhere: bash examples/seed-figures-11-13.sh [OUTPUT_DIR]
set -euo pipefail
out=${1:-groundres-out/seed-figures-11-13}
run() {  # figure case where rpm
    groundres phasors "$2" --speed "$4" --out "$out/figure-$1/$3"
}
run 11 soft-inplane below 155
run 11 soft-inplane inside 232.5
run 11 soft-inplane above 325.5
run 12 soft-inplane-pitch-roll below 139.5
run 12 soft-inplane-pitch-roll inside 248
run 12 soft-inplane-pitch-roll above 372
run 13 hammond-undamped below 93
run 13 hammond-undamped inside 248
run 13 hammond-undamped above 356.5
echo "Wrote $out"
