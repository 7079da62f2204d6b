"""A sweep in air against the same sweep in vacuum: what the air costs.

The shipped cases in air, each analysed whole (``analyze``: sweep, tracking,
identification, ranges on the internal grid, margins, the exact minimum lag
damping) as it is, and again without its ``[aero]`` table (``Case.in_vacuum``):
the same rotor, body, sweep and method. The air's cost is the hover trim at
every speed the analysis asks for and the longer matrices (the structure about
the trim plus the strip-theory loads), evaluated as a product of per-blade
coefficients with monomials of the trim state.

Target (issue 25): an air sweep costs at most 1.5 times the same sweep in
vacuum (trim included). Medians of paired runs, alternating, in one process.
A Floquet analysis in air (a failed damper) is timed too: each speed on the
equations frozen at its own trim.

The whole analysis does different work in air and in vacuum: the air couples
flap and lag (larger eigenproblems), and the ranges, margins and damping
search take the steps their roots ask for. So the same work is also timed on
its own: the sweep (the form at every speed of the grid, eigenvectors,
tracking; trims and the air's form built from nothing), and single new speeds
as scans and searches ask for them (each a trim, a form and its roots).

Run in the default environment: python3 benchmarks/bench_air.py [--repeats N]
"""

import argparse
import statistics
import time
import tomllib

import numpy as np

from groundres import analyze
from groundres.model.casefile import case_text
from groundres.model.schema import load_case, parse_case

EIGEN = ["model-rotor-hover-9deg", "model-rotor-hover-9deg-pitch-lag", "helicopter-hover"]


def failed(name: str, points: int):
    """A shipped case in air with blade 1's lag damper failed (Floquet), on ``points`` speeds."""
    text, source = case_text(name)
    failure = "\n[[rotor.blade]]\nindex = 1\nlag_damping = 0.0\n"
    text = text.replace("points = 400", f"points = {points}") + failure
    return parse_case(tomllib.loads(text), source, text)


def paired(case, repeats: int) -> tuple[float, float]:
    """Median seconds of ``analyze`` in vacuum and in air, runs alternating."""
    vacuum, air = case.in_vacuum(), case
    analyze(vacuum), analyze(air)  # (warm: imports, compiled kernels)
    times = {"vacuum": [], "air": []}
    for _ in range(repeats):
        for name, c in (("vacuum", vacuum), ("air", air)):
            start = time.perf_counter()
            analyze(c)
            times[name].append(time.perf_counter() - start)
    return statistics.median(times["vacuum"]), statistics.median(times["air"])


def same_work(case, repeats: int) -> dict:
    """Median seconds of the same work in vacuum and in air: the sweep from nothing, and the
    largest real parts at 200 new speeds one at a time (per speed)."""
    from groundres.methods import choose_method
    from groundres.solve.solvers import solver_for

    out = {}
    for name, c in (("vacuum", case.in_vacuum()), ("air", case)):
        speeds = c.sweep.speeds
        sweep, single = [], []
        for _ in range(repeats):
            start = time.perf_counter()
            solver = solver_for(c, choose_method(c))
            solver.sweep(speeds)
            sweep.append(time.perf_counter() - start)
            news = np.linspace(speeds[0], speeds[-1], 200) * (1 + 1e-4)
            start = time.perf_counter()
            for w in news:
                solver.real_parts(np.array([w]))
            single.append((time.perf_counter() - start) / len(news))
        out[name] = (statistics.median(sweep), statistics.median(single))
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--floquet-points", type=int, default=60)
    options = parser.parse_args()
    print(f"{'case':40s} {'vacuum [s]':>11s} {'air [s]':>9s} {'ratio':>7s}  (target <= 1.5)")
    for name in EIGEN:
        vacuum, air = paired(load_case(name), options.repeats)
        print(f"{name:40s} {vacuum:11.3f} {air:9.3f} {air / vacuum:7.2f}")
    print(f"\n{'the same work':40s} {'vacuum':>11s} {'air':>9s} {'ratio':>7s}")
    for name in EIGEN + ["model-rotor-hover-9deg-inflow"]:
        work = same_work(load_case(name), options.repeats)
        for k, what in enumerate(("sweep [s]", "new speed [ms]")):
            v, a = work["vacuum"][k], work["air"][k]
            scale = 1e3 if k else 1.0
            print(f"{name + ', ' + what:40s} {v * scale:11.3f} {a * scale:9.3f} {a / v:7.2f}")
    case = failed("model-rotor-hover-9deg", options.floquet_points)
    vacuum, air = paired(case, max(1, options.repeats // 2))
    label = f"model-rotor-hover-9deg, blade 1 failed ({options.floquet_points} speeds, Floquet)"
    print(f"{label:40s} {vacuum:11.3f} {air:9.3f} {air / vacuum:7.2f}")


if __name__ == "__main__":
    main()
