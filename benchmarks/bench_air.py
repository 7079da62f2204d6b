"""A sweep in air against the same sweep in vacuum: what the air costs.

Target (issue 25): an air sweep costs at most 1.5 times the same sweep in
vacuum (trim included). The sweep is the case's: its grid of speeds, each
speed's time-invariant form (in air: the hover trim and the strip-theory loads
about it, from nothing: a fresh solver, no trim or form kept), the roots and
eigenvectors of every coupling block, and the tracking along branches. The
same case without its ``[aero]`` table (``Case.in_vacuum``) is the baseline:
the same rotor, body, grid and method. Medians of runs alternating vacuum and
air, in one process.

With dynamic inflow the sweep carries three more states (14 instead of 12 in
the body-coupled block of the model rotor): its eigenproblems alone cost
(14/12)^3 = 1.6 times the vacuum's. Those cases are shown for what they cost,
against the same target.

For context, not the target:

* a new speed asked alone (a scan's or search's; in air its trim, the form from
  the monomials of the trim state, and the roots);
* the whole analysis (``analyze``: sweep, ranges, margins, the exact minimum
  lag damping), which does different work in air: the air couples collective
  flap and lag (LAPACK blocks where the vacuum has closed-form roots), and the
  ranges, margins and damping search take the steps their roots ask for;
* a Floquet analysis in air (a failed damper), each speed frozen at its own trim.

Run in the default environment: python3 benchmarks/bench_air.py [--repeats N]
"""

import argparse
import statistics
import time
import tomllib

import numpy as np

from groundres import analyze
from groundres.methods import choose_method
from groundres.model.casefile import case_text
from groundres.model.schema import load_case, parse_case
from groundres.solve.solvers import solver_for

UNIFORM = ["model-rotor-hover-9deg", "model-rotor-hover-9deg-pitch-lag", "helicopter-hover"]
DYNAMIC = ["model-rotor-hover-9deg-inflow", "model-rotor-hover-0deg-inflow"]


def failed(name: str, points: int):
    """A shipped case in air with blade 1's lag damper failed (Floquet), on ``points`` speeds."""
    text, source = case_text(name)
    failure = "\n[[rotor.blade]]\nindex = 1\nlag_damping = 0.0\n"
    text = text.replace("points = 400", f"points = {points}") + failure
    return parse_case(tomllib.loads(text), source, text)


def paired(work, case, repeats: int) -> tuple[float, float]:
    """Median seconds of ``work(case)`` in vacuum and in air, runs alternating (after one
    warm run of each: imports, generated functions); a ``work`` that returns seconds is timed
    by itself."""
    vacuum, air = case.in_vacuum(), case
    work(vacuum), work(air)
    times = {"vacuum": [], "air": []}
    for _ in range(repeats):
        for name, c in (("vacuum", vacuum), ("air", air)):
            start = time.perf_counter()
            own = work(c)
            times[name].append(own if isinstance(own, float) else time.perf_counter() - start)
    return statistics.median(times["vacuum"]), statistics.median(times["air"])


def sweep(case) -> None:
    """The case's sweep from nothing: a fresh solver (no trim or form kept), the form at every
    speed of the grid, roots, eigenvectors and tracking."""
    solver_for(case, choose_method(case)).sweep(case.sweep.speeds)


def new_speeds(case, count: int = 200) -> float:
    """Seconds per new speed asked alone after the sweep (largest real parts)."""
    solver = solver_for(case, choose_method(case))
    speeds = case.sweep.speeds
    solver.sweep(speeds)
    news = np.linspace(speeds[0], speeds[-1], count) * (1 + 1e-4)
    start = time.perf_counter()
    for w in news:
        solver.real_parts(np.array([w]))
    return (time.perf_counter() - start) / count


def row(label: str, vacuum: float, air: float, scale: float = 1.0) -> None:
    print(f"{label:52s} {vacuum * scale:9.3f} {air * scale:9.3f} {air / vacuum:7.2f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5, help="runs of each whole analysis")
    parser.add_argument("--floquet-points", type=int, default=60)
    options = parser.parse_args()
    sweeps = 8 * options.repeats  # (a sweep takes milliseconds: more runs, a steadier median)
    print(f"{'the sweep, trim included [ms]':52s} {'vacuum':>9s} {'air':>9s} {'ratio':>7s}  (target <= 1.5)")
    for name in UNIFORM + DYNAMIC:
        label = name + ("  (dynamic inflow)" if name in DYNAMIC else "")
        row(label, *paired(sweep, load_case(name), sweeps), 1e3)
    print(f"\n{'for context':52s} {'vacuum':>9s} {'air':>9s} {'ratio':>7s}")
    for name in UNIFORM + DYNAMIC:
        row(f"{name}, a new speed [ms]", *paired(new_speeds, load_case(name), options.repeats), 1e3)
    for name in UNIFORM:
        row(f"{name}, whole analysis [s]", *paired(analyze, load_case(name), options.repeats))
    case = failed("model-rotor-hover-9deg", options.floquet_points)
    label = f"blade 1 failed, Floquet, {options.floquet_points} speeds [s]"
    row(label, *paired(analyze, case, max(1, options.repeats // 2)))


if __name__ == "__main__":
    main()
