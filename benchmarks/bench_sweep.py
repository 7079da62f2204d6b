"""Batched, block-wise eigen-analysis of a sweep against a per-speed eig loop.

Six-bladed rotor with flap on an x-y hub, and eight blades with flap on a body
that also pitches and rolls (issue 10: >= 10x), 1000 rotor speeds. Both sides start
from the same multiblade matrices; the baseline forms the full state
matrix at each speed and calls numpy.linalg.eig in a Python loop, groundres
finds the coupling blocks (body + first cyclic lag; first cyclic flap;
collective, differential and second cyclic lag and flap) and solves each block
for all speeds in one batched call. The eigenvalues must agree.

Run: python3 benchmarks/bench_sweep.py
"""

import sys
import time
from pathlib import Path

import numpy as np

from groundres import (
    Blade,
    Body,
    Case,
    Rotor,
    Sweep,
    analyze,
)
from groundres.model.system import System
from groundres.solve import modal

sys.path.insert(0, str(Path(__file__).parent))


def case(blades=6, full=False):
    """The Hammond (1974) blade with flap; on an x-y hub, or (``full``) a body that pitches and rolls."""
    from bench_analyze import PITCH_ROLL

    blade = Blade(
        94.9,
        289.1,
        1084.7,
        0.3048,
        lag_stiffness=1e5,
        lag_damping=4067.5,
        flap_stiffness=2e5,
        flap_damping=800.0,
    )
    body = Body(
        ("x", "y", "pitch", "roll") if full else ("x", "y"),
        mass_x=8026.6,
        mass_y=3283.6,
        stiffness_x=1240481.8,
        stiffness_y=1240481.8,
        damping_x=51078.7,
        damping_y=25539.35,
        **(PITCH_ROLL if full else {}),
    )
    return Case(Rotor.uniform(blades, blade, flap=True), body, Sweep(1.0, 45.0, 1000), title="bench")


def best_of(fn, repeat=5):
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t)
    return min(times), out


def main():
    for blades, full, target in ((6, False, 5), (8, True, 10)):
        one(case(blades, full), blades, full, target)


def one(c, blades, full, target):
    system = System(c.rotor, c.body)
    speeds = c.sweep.speeds
    system.multiblade(speeds[:2])  # load the generated code once
    t_matrices, mats = best_of(lambda: system.multiblade(speeds))

    def groundres_solve():
        blocks = modal.coupling_blocks(*mats)
        return modal.solve(*mats, blocks)

    def baseline():
        out = []
        for i in range(len(speeds)):
            a = modal.state_matrix(mats[0][i], mats[1][i], mats[2][i])
            out.append(np.linalg.eig(a)[0])
        return np.array(out)

    t_fast, sol = best_of(groundres_solve)
    t_loop, ref = best_of(baseline, repeat=3)
    for i in (0, 500, 999):
        a, b = np.sort_complex(sol.eigenvalue[i]), np.sort_complex(ref[i])
        d = np.abs(a[:, None] - b[None, :]).min(1).max()
        assert d < 1e-8 * np.abs(b).max(), d
    t_analyze, _ = best_of(lambda: analyze(c), repeat=3)
    n = mats.shape[-1]
    blocks = modal.coupling_blocks(*mats)
    where = "x-y-pitch-roll body" if full else "x-y hub"
    print(f"{blades} blades with flap, {where}, {len(speeds)} speeds, {n} dofs ({2 * n} states)")
    print(f"coupling blocks (dofs): {[len(b) for b in blocks]}")
    print(f"multiblade matrices, batched:           {t_matrices * 1e3:8.1f} ms")
    print(f"per-speed numpy.linalg.eig loop:        {t_loop * 1e3:8.1f} ms")
    print(f"groundres block-wise batched eig:       {t_fast * 1e3:8.1f} ms")
    print(f"ratio (loop / groundres):               {t_loop / t_fast:8.1f} x   (target >= {target} x)")
    print(f"whole analyze() incl. tracking, labels, ranges, damping search: {t_analyze * 1e3:.0f} ms")


if __name__ == "__main__":
    main()
