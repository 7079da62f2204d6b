#!/usr/bin/env bash
# A design study of the Hammond (1974) rotor on its hub: lag damping x hub
# damping in x, with every lag damper working and with each one out of action
# in turn, on a local Dask cluster (one worker per core). Then the stability
# boundary along the lag damping by root finding, for the same hub dampings.
# The design point (4067.5 N m s/rad, 51078.7 N s/m) is stable with all
# dampers and unstable with any one failed.
# Run from anywhere: bash examples/hammond-study.sh [OUTPUT_DIR]
# (about a minute and a half on 2 cores; an interrupted run resumes where it stopped)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
out=${1:-groundres-out/hammond-study}
groundres study "$here/hammond-study.toml" \
    --vary rotor.lag_damping=1000:9000:17 --vary body.damping_x=10000:100000:10 \
    --failures single --out "$out/map"
groundres study "$here/hammond-study.toml" \
    --vary rotor.lag_damping=1000:9000:17 --vary body.damping_x=10000:100000:10 \
    --failures single --boundary rotor.lag_damping --out "$out/boundary"
echo "Wrote $out"
