"""Command-line timings: --help, a cached run of the default case, a first run.

Targets: --help < 0.5 s; cached run with plots < 2 s; first run, derivation
included, < 15 s. Run: python3 benchmarks/bench_cli.py
"""

import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

EXE = [sys.executable, "-m", "groundres.cli"]


def timed(args, env, repeat):
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        subprocess.run(EXE + args, env=env, check=True, capture_output=True)
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def main():
    work = tempfile.mkdtemp(prefix="groundres-bench-")
    env = {**os.environ, "GROUNDRES_CACHE_DIR": os.path.join(work, "cache")}
    out = os.path.join(work, "out")
    try:
        first = timed(["run", "--out", out], env, 1)
        helptime = timed(["--help"], env, 5)
        cached = timed(["run", "--out", out], env, 5)
        fresh = []
        for i in range(2):
            env_i = {**env, "GROUNDRES_CACHE_DIR": os.path.join(work, f"cache{i}")}
            fresh.append(timed(["run", "--out", out], env_i, 1))
        print(f"groundres --help:                 {helptime:6.2f} s  (target < 0.5 s)")
        print(f"cached run of the default case:   {cached:6.2f} s  (target < 2 s, median of 5)")
        print(f"first run, derivation included:   {min(first, *fresh):6.2f} s  (target < 15 s, best of 3)")
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
