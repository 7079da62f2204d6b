"""`groundres run` of the Hammond (1974) one-damper-inoperative case, whole process,
against the lean per-speed loop.

groundres: ``groundres run CASE --out DIR`` as a separate process (start-up,
imports, the analysis with its range search and exact minimum lag damping,
writing summary.json, modes.csv, modes.nc and the Coleman diagram), with the
sweep's points set to 40 and to 400. The compiled kernel is ready (one run
before the timing fills numba's cache, as any run after a machine's first does).

Baseline, the lean loop (``bench_floquet.baseline_monodromy``): for each speed,
``scipy.integrate.solve_ivp`` (DOP853, rtol 1e-10) of the transition matrix
over one revolution, then ``numpy.linalg.eigvals``: the bare sweep, nothing
else. Timed on ``--loop-speeds`` speeds spread over the sweep, scaled to 400.

Figures (issue 10):
- marginal cost per speed, (run(400) - run(40)) / 360, against the loop's
  cost per speed: target >= 50x;
- the whole run of 400 speeds against the loop's 400 speeds: target >= 5x.

Run in the default environment: python3 benchmarks/bench_run.py [--loop-speeds N] [--repeat N]
"""

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
import tomllib
from importlib import resources
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from bench_floquet import baseline_monodromy  # noqa: E402
from groundres import load_case  # noqa: E402
from groundres.model.system import System  # noqa: E402

CASE = "hammond-1974-one-damper"


def case_file(folder, points):
    text = (resources.files("groundres") / "cases" / f"{CASE}.toml").read_text()
    assert tomllib.loads(text)["sweep"]["points"] == 400
    path = os.path.join(folder, f"{CASE}-{points}.toml")
    with open(path, "w") as f:
        f.write(text.replace("points = 400", f"points = {points}"))
    return path


def timed_run(path, out, repeat):
    times = []
    for _ in range(repeat):
        shutil.rmtree(out, ignore_errors=True)
        t = time.perf_counter()
        command = [sys.executable, "-m", "groundres.cli", "run", path, "--out", out]
        subprocess.run(command, check=True, capture_output=True)
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--loop-speeds", type=int, default=20, help="speeds the lean loop is timed on")
    parser.add_argument("--repeat", type=int, default=5, help="runs of each (the median is kept)")
    args = parser.parse_args()
    work = tempfile.mkdtemp(prefix="groundres-bench-")
    try:
        few, many = case_file(work, 40), case_file(work, 400)
        out = os.path.join(work, "out")
        timed_run(few, out, 1)  # (fills the compiled kernel's cache if this machine has none yet)
        t_few = timed_run(few, out, args.repeat)
        t_many = timed_run(many, out, args.repeat)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    case = load_case(CASE)
    system = System(case.rotor, case.body)
    speeds = case.sweep.speeds
    pick = speeds[np.unique(np.linspace(0, len(speeds) - 1, args.loop_speeds).round().astype(int))]
    t = time.perf_counter()
    for w in pick:
        np.linalg.eigvals(baseline_monodromy(system, w))
    per_speed = (time.perf_counter() - t) / len(pick)
    loop = per_speed * len(speeds)
    marginal = (t_many - t_few) / (len(speeds) - 40)
    print(f"{CASE}: {2 * system.size} states, Floquet, 40 and {len(speeds)} speeds")
    print(f"groundres run, 40 speeds (whole process):   {t_few:7.2f} s")
    print(f"groundres run, 400 speeds (whole process):  {t_many:7.2f} s")
    print(f"lean loop, 400 speeds (bare sweep):         {loop:7.2f} s  ({per_speed * 1e3:.1f} ms a speed)")
    print(
        f"marginal cost a speed: groundres {marginal * 1e3:.2f} ms, loop {per_speed * 1e3:.1f} ms: "
        f"{per_speed / marginal:6.1f} x  (target >= 50 x)"
    )
    print(f"whole run of 400 speeds against the loop's:  {loop / t_many:6.1f} x  (target >= 5 x)")


if __name__ == "__main__":
    main()
