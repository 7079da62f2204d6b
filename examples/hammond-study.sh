#!/usr/bin/env bash
# A design study of the Hammond (1974) rotor on its hub: lag damping x hub
# damping in x, with every lag damper working and with each one out of action
# in turn, on a local Dask cluster (one worker per core). Then the stability
# boundary along the lag damping by root finding, for the same hub dampings.
# The design point (4067.5 N m s/rad, 51078.7 N s/m) is stable with all
# dampers and unstable with any one failed.
# Run from anywhere: bash examples/hammond-study.sh [OUTPUT_DIR [coarse|fine]]
# coarse (the default) maps 9 x 4 points, about 20 s on 2 cores; fine maps
# 17 x 10, about a minute and a half. An interrupted run resumes where it stopped.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
out=${1:-groundres-out/examples/hammond-study}
case ${2:-coarse} in
    coarse) grid=(--vary rotor.lag_damping=1000:9000:9 --vary body.damping_x=10000:100000:4) ;;
    fine) grid=(--vary rotor.lag_damping=1000:9000:17 --vary body.damping_x=10000:100000:10) ;;
    *) echo "grid '$2': use coarse or fine" >&2; exit 2 ;;
esac
groundres study "$here/hammond-study.toml" "${grid[@]}" --failures single --out "$out/map"
groundres study "$here/hammond-study.toml" "${grid[@]}" --failures single \
    --boundary rotor.lag_damping --out "$out/boundary"
echo "Wrote $out"
