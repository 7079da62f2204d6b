#!/usr/bin/env bash
# Eigenvector analysis as in the seed paper's Figures 11 to 13: phasor diagrams,
# rate phases and whirl of the regressive lag mode at one rotor speed below,
# one inside and one above the unstable range of
#   Figure 11: three-bladed soft in-plane rotor, body x and y  (soft-inplane),
#   Figure 12: the same blades with flap, body pitch and roll  (soft-inplane-pitch-roll),
#   Figure 13: four-bladed articulated rotor, anisotropic hub  (hammond-undamped).
# Speeds in rpm (the cases' unit; reference 155 rpm).
# Run from anywhere: bash examples/seed-figures-11-13.sh [OUTPUT_DIR [PHASORS_OPTION ...]]
# (about 25 s on 2 cores). Options given after the folder go to every
# `groundres phasors` in place of the default --mode "regressive lag" --no-gif:
# --gif draws the least stable, regressive lag and body modes with animated
# shapes (mode_<mode>.gif), about two minutes in all.
set -euo pipefail
out=${1:-groundres-out/examples/seed-figures-11-13}
options=("${@:2}")
if [ ${#options[@]} -eq 0 ]; then options=(--mode "regressive lag" --no-gif); fi
run() {  # figure case where rpm
    groundres phasors "$2" --speed "$4" "${options[@]}" --out "$out/figure-$1/$3"
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
