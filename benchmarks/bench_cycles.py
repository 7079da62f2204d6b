"""A limit-cycle diagram against the linear analysis of the same case, and a confirming simulation.

Target (issue 26): a limit-cycle diagram over a 100-speed sweep costs at most
5 times the linear sweep of the same case. The diagram is the prediction at
100 speeds over the sweep (``limit_cycles(case, linear=False)``: the scan of
blade lag amplitudes at every speed, each neutral amplitude refined); the
linear sweep is the analysis ``groundres run`` makes of the case (the laws at
small motion), on the same 100 speeds (``analyze(case, speeds=...)``: the
sweep, ranges, margins and the exact minimum lag damping). The bare eigen
sweep of the same speeds is printed for scale. Medians of runs alternating,
in one process, on the shipped cases with nonlinear dampers, and on each with
blade 1's damper failed (the Floquet route, each blade at its own amplitude,
against the linear Floquet analysis).

A confirming simulation of 40 s of the nonlinear equations (started above the
largest stable cycle, below any threshold over it, or at 0.8 times the smallest threshold)
reports its right-hand-side evaluations, method and time.

Run in the default environment: python3 benchmarks/bench_cycles.py [--repeats N]
"""

import argparse
import statistics
import time
import tomllib
from dataclasses import replace

import numpy as np

from groundres import analyze, limit_cycles
from groundres.assess.confirm import stable_start
from groundres.assess.limit_cycles import disturbance
from groundres.methods import choose_method
from groundres.model.casefile import case_text
from groundres.model.schema import load_case, parse_case
from groundres.solve import nonlinear
from groundres.solve.solvers import solver_for

CASES = ["hammond-relief-valve", "hammond-friction-link"]


def cases():
    """(label, case) of every shipped case with nonlinear dampers, and each with blade 1's failed."""
    for name in CASES:
        yield name, load_case(name)
        text, source = case_text(name)
        text += '\n[[rotor.blade]]\nindex = 1\nlag_damper = "failed"\n'
        yield f"{name}, 1 failed", parse_case(tomllib.loads(text), source, text)


def timed(fn) -> float:
    start = time.perf_counter()
    fn()
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    options = parser.parse_args()
    head = f"{'case (100 speeds)':36s} {'sweep [s]':>10s} {'linear [s]':>11s} {'cycles [s]':>11s}"
    print(f"{head} {'ratio':>7s}  (<= 5)")
    for name, case in cases():
        case = replace(case, limit_cycle=replace(case.limit_cycle, points=100))
        speeds = np.linspace(case.sweep.start, case.sweep.stop, 100)
        work = {
            "sweep": lambda c=case, w=speeds: solver_for(c, choose_method(c)).sweep(w),
            "linear": lambda c=case, w=speeds: analyze(c, speeds=w),
            "cycles": lambda c=case: limit_cycles(c, linear=False),
        }
        for fn in work.values():  # (warm: imports, generated functions)
            fn()
        times = {k: [] for k in work}
        for _ in range(options.repeats):
            for k, fn in work.items():
                times[k].append(timed(fn))
        med = {k: statistics.median(v) for k, v in times.items()}
        print(
            f"{name:36s} {med['sweep']:10.4f} {med['linear']:11.3f} {med['cycles']:11.3f} "
            f"{med['cycles'] / med['linear']:7.2f}"
        )
    print("\nconfirming simulations, 40 s of the nonlinear equations")
    for name, case in cases():
        found = limit_cycles(case, linear=False)
        stable = found.largest_stable()
        if stable is not None:
            others = [c for c in found.prediction.at(stable.speed) if c is not stable]
            cycle, factor = stable, round(stable_start(stable, others), 3)
        else:
            cycle, factor = found.smallest_threshold(), 0.8
        start = disturbance(nonlinear.structure(case), cycle, factor)
        begin = time.perf_counter()
        history = nonlinear.integrate(case, cycle.speed, 40.0, start)
        seconds = time.perf_counter() - begin
        late = history.time >= 30.0
        blade = 1 + int(np.argmax([b.amplitude for b in cycle.blades]))
        (w, a), *_ = nonlinear.components(history.time[late], history.lag(blade)[late])
        kind = "stable cycle" if cycle.stable else "threshold"
        print(
            f"{name:36s} {history.method:6s} {history.evaluations:8d} evaluations {seconds:7.2f} s; "
            f"{factor} x the {kind} {np.degrees(cycle.amplitude):.4g} deg -> {np.degrees(a):.4g} deg"
        )


if __name__ == "__main__":
    main()
