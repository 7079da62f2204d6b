"""`analyze` end to end on Floquet cases of growing size, against a lean per-speed loop.

The cases of issue 10's table: the Hammond (1974) rotor with one lag damper
inoperative, 3 or 8 blades on an x-y hub (10 and 20 states), and with flap on
a body that also pitches and rolls (3, 4 and 8 blades: 20, 24 and 40 states).
Each is swept over 100 speeds from 30 to 400 rpm.

groundres: ``analyze(case)``, everything a run computes (sweep, tracking,
identification, ranges on the internal grid, the exact minimum lag damping).

Baseline, the lean loop: for each speed, ``scipy.integrate.solve_ivp``
(DOP853, rtol 1e-10) of the transition matrix over one revolution with the
harmonic matrices formed once per speed (``bench_floquet.baseline_monodromy``),
then ``numpy.linalg.eigvals`` of it. Timed on a few speeds spread over the
sweep and scaled to the sweep's count. It gives the multipliers only: no
tracking, no names, no ranges, no damping search.

Targets (issue 10): >= 20x at 10-20 states, >= 10x at 24-40 states.
Run in the default environment: python3 benchmarks/bench_analyze.py [--loop-speeds N]
"""

import argparse
import sys
import time
import tomllib
from importlib import resources
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from bench_floquet import baseline_monodromy  # noqa: E402
from groundres import analyze  # noqa: E402
from groundres.model.schema import parse_case  # noqa: E402
from groundres.model.system import System  # noqa: E402
from groundres.solve.floquet import compiled  # noqa: E402

#: Pitch and roll of the body about a pivot 1.6 m below the hub (a helicopter of
#: the Hammond rotor's size: about 10 times soft-inplane-pitch-roll's body).
PITCH_ROLL = dict(
    inertia_pitch=25000.0,
    inertia_roll=8000.0,
    stiffness_pitch=3.8e6,
    stiffness_roll=1.0e6,
    damping_pitch=2.0e5,
    damping_roll=1.0e5,
    hub_height=1.6,
)
#: (blades, flap and pitch-roll) of the table's cases.
CASES = [(3, False), (8, False), (3, True), (4, True), (8, True)]


def case(blades: int, full: bool, points: int):
    text = (resources.files("groundres") / "cases" / "hammond-1974-one-damper.toml").read_text()
    data = tomllib.loads(text)
    data["rotor"]["blades"] = blades
    data["sweep"]["points"] = points
    data["sweep"]["method"] = "floquet"
    if full:
        data["rotor"] |= {"flap": True, "flap_stiffness": 0.0, "flap_damping": 0.0}
        data["body"]["dofs"] = ["x", "y", "pitch", "roll"]
        data["body"] |= PITCH_ROLL
    return parse_case(data)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=100)
    parser.add_argument("--loop-speeds", type=int, default=8, help="speeds the lean loop is timed on")
    args = parser.parse_args()
    compiled.kernel(wait=True)  # (compiled now if this machine has not yet: not timed)
    print(f"{'case':34s} {'states':>6s} {'analyze [s]':>12s} {'loop [s]':>10s} {'speed-up':>9s} target")
    for blades, full in CASES:
        c = case(blades, full, args.points)
        system = System(c.rotor, c.body)
        analyze(case(blades, full, 4))  # (warm: generated code imported, grids made)
        t = time.perf_counter()
        analyze(c)
        ours = time.perf_counter() - t
        speeds = c.sweep.speeds[np.linspace(0, len(c.sweep.speeds) - 1, args.loop_speeds).astype(int)]
        t = time.perf_counter()
        for w in speeds:
            np.linalg.eigvals(baseline_monodromy(system, w))
        loop = (time.perf_counter() - t) * len(c.sweep.speeds) / len(speeds)
        states = 2 * system.size
        target = 20 if states <= 20 else 10
        name = f"{blades} blades, {'flap, x-y-pitch-roll' if full else 'hub x-y'}"
        row = f"{name:34s} {states:6d} {ours:12.2f} {loop:10.1f} {loop / ours:8.1f}x  >= {target}x"
        print(row, flush=True)


if __name__ == "__main__":
    main()
