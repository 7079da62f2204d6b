"""Command-line timings: --help, runs of the default case, `groundres equations`.

The equations of motion ship with the package (groundres/symbolic/
generated_*.py), so no run derives anything: the "first run" below is the
first command of a fresh series (cold file caches, bytecode possibly not yet
compiled), not a run that includes the derivation.

Targets: --help < 0.5 s; run with plots < 2 s (first and later alike);
equations < 5 s. Run: python3 benchmarks/bench_cli.py
"""

import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

EXE = [sys.executable, "-m", "groundres.cli"]


def timed(args, repeat):
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        subprocess.run(EXE + args, check=True, capture_output=True)
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def main():
    work = tempfile.mkdtemp(prefix="groundres-bench-")
    out = os.path.join(work, "out")
    try:
        first = timed(["run", "--out", out], 1)
        helptime = timed(["--help"], 5)
        later = timed(["run", "--out", out], 5)
        equations = timed(["equations", "hammond-1974"], 3)
        print(f"groundres --help:                 {helptime:6.2f} s  (target < 0.5 s)")
        print(f"first run of the default case:    {first:6.2f} s  (target < 2 s, no derivation)")
        print(f"later runs of the default case:   {later:6.2f} s  (target < 2 s, median of 5)")
        print(f"groundres equations hammond-1974: {equations:6.2f} s  (target < 5 s, median of 3)")
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
