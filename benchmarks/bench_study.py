"""A design-study map on a local Dask cluster of 1 and 2 workers, against `groundres run` in a loop.

The map (issue 11): the Hammond (1974) one-damper-inoperative case (Floquet,
100 speeds each), lag damping x hub damping in x, SIZE x SIZE points
(40 x 40 by default). groundres: ``groundres.study`` on a local cluster of 1
and of 2 worker processes (cluster start-up included), in grid points per
second. Baseline: ``groundres run`` of the case with the point's values
written into its file, one process per point, as a script would loop; timed
on a few points and scaled to the map.

Targets (issue 11): the whole map in under 60 s on 2 cores; 1 -> 2 workers
at least 1.7x.

Run in the default environment: python3 benchmarks/bench_study.py [--size N] [--baseline-points N]
"""

import argparse
import subprocess
import sys
import tempfile
import time
import tomllib
from pathlib import Path

import numpy as np

from groundres import load_case, parse_case
from groundres.solve.floquet import compiled
from groundres.studies import run
from groundres.studies.study import study


def the_case():
    text = load_case("hammond-1974-one-damper").text.replace("points = 400", "points = 100")
    assert "points = 100" in text
    return parse_case(tomllib.loads(text), "hammond-1974-one-damper", text), text


def vary(size):
    return {"rotor.lag_damping": f"2000:12000:{size}", "body.damping_x": f"20000:100000:{size}"}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=40)
    parser.add_argument("--baseline-points", type=int, default=4)
    args = parser.parse_args()
    compiled.kernel(wait=True)  # (compiled now if this machine has not yet: not timed)
    case, text = the_case()
    points = args.size**2
    print(
        f"map: {args.size} x {args.size} = {points} points, Hammond one damper inoperative, 100 speeds each"
    )
    rates = {}
    for workers in (1, 2):
        t = time.perf_counter()
        client = run.local_client(workers)
        try:
            ds = study(case, vary(args.size), client=client)
        finally:
            cluster = client.cluster
            client.close()
            cluster.close()
        seconds = time.perf_counter() - t
        rates[workers] = points / seconds
        failed = int((ds.error.values != "").sum())
        print(
            f"{workers} worker(s): {seconds:7.1f} s, {rates[workers]:6.2f} points/s ({failed} failed points)"
        )
    lags = np.linspace(2000, 12000, args.size)[:: max(1, args.size // args.baseline_points)][
        : args.baseline_points
    ]
    t = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        for i, lag in enumerate(lags):
            path = Path(tmp) / f"case{i}.toml"
            path.write_text(text.replace("lag_damping = 4067.5", f"lag_damping = {float(lag)!r}", 1))
            out = Path(tmp) / f"out{i}"
            subprocess.run(
                [sys.executable, "-m", "groundres.cli", "run", str(path), "--out", str(out)],
                check=True,
                capture_output=True,
            )
    per_run = (time.perf_counter() - t) / len(lags)
    print(f"groundres run loop: {per_run:.2f} s a point -> {per_run * points:.0f} s for the map (estimated)")
    print(
        f"2 workers: the map in {points / rates[2]:.1f} s (target < 60 s); "
        f"1 -> 2 workers {rates[2] / rates[1]:.2f}x (target >= 1.7x); "
        f"against the run loop {per_run * rates[2]:.0f}x"
    )


if __name__ == "__main__":
    main()
