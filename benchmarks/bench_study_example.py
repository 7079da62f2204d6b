"""The README's design study from the command line: cold, with fewer speeds, and called again.

The study (issue 23): ``groundres study hammond-1974 --vary
rotor.lag_damping=1000:9000:17 --vary body.damping_x=10000:100000:10
--failures single`` (170 grid points x 5 failure states, of which the four
single failures of alike blades are computed once: 340 sweeps), on a local
cluster of one worker per core, cluster start-up included. Timed as a user
runs it, a whole command each:

- baseline: at the case's own 400 speeds a sweep;
- ``--points 100``: the same study at 100 speeds (its measures are refined
  between speeds; docs/studies.md says how little they move);
- the ``--points 100`` command again into the same folder: the store is
  whole, so it should compute nothing and start no cluster.

Targets (issue 23): the example in about a minute on 2 cores; the second call
in a few seconds. ``--grid coarse`` runs the 9 x 4 grid instead.

Run in the default environment: python3 benchmarks/bench_study_example.py [--grid fine|coarse]
"""

import argparse
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from groundres.solve.floquet import compiled

GRIDS = {
    "fine": ["--vary", "rotor.lag_damping=1000:9000:17", "--vary", "body.damping_x=10000:100000:10"],
    "coarse": ["--vary", "rotor.lag_damping=1000:9000:9", "--vary", "body.damping_x=10000:100000:4"],
}


def timed(args: list[str]) -> float:
    t = time.perf_counter()
    subprocess.run([sys.executable, "-m", "groundres.cli", *args], check=True, stdout=subprocess.DEVNULL)
    return time.perf_counter() - t


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grid", choices=sorted(GRIDS), default="fine")
    args = parser.parse_args()
    compiled.kernel(wait=True)  # (compiled now if this machine has not yet: not timed)
    study = ["study", "hammond-1974", *GRIDS[args.grid], "--failures", "single"]
    with tempfile.TemporaryDirectory() as tmp:
        base = timed([*study, "--out", str(Path(tmp) / "base")])
        fewer = timed([*study, "--points", "100", "--out", str(Path(tmp) / "fewer")])
        again = timed([*study, "--points", "100", "--out", str(Path(tmp) / "fewer")])
    print(f"grid {args.grid}: the study as written (400 speeds)  {base:7.1f} s")
    print(f"            --points 100                       {fewer:7.1f} s  ({base / fewer:.2f}x faster)")
    print(f"            the same command again             {again:7.1f} s  ({fewer / again:.0f}x faster)")


if __name__ == "__main__":
    main()
