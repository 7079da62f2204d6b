"""Batched, block-wise eigen-analysis of a sweep against a per-speed eig loop.

Six-bladed rotor with flap on an x-y hub, 1000 rotor speeds. Both sides start
from the same multiblade matrices; the baseline forms the full 28 x 28 state
matrix at each speed and calls numpy.linalg.eig in a Python loop, groundres
finds the coupling blocks (body + first cyclic lag; first cyclic flap;
collective, differential and second cyclic lag and flap) and solves each block
for all speeds in one batched call. The eigenvalues must agree.

Run: python3 benchmarks/bench_sweep.py
"""

import time

import numpy as np

from groundres import (
    Blade,
    Body,
    Case,
    Rotor,
    Sweep,
    analyze,
    modal,
)
from groundres.system import System


def case():
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
        ("x", "y"),
        mass_x=8026.6,
        mass_y=3283.6,
        stiffness_x=1240481.8,
        stiffness_y=1240481.8,
        damping_x=51078.7,
        damping_y=25539.35,
    )
    return Case(Rotor.uniform(6, blade, flap=True), body, Sweep(1.0, 45.0, 1000), title="bench")


def best_of(fn, repeat=5):
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t)
    return min(times), out


def main():
    c = case()
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
    print(f"6 blades with flap, x-y hub, {len(speeds)} speeds, {n} dofs ({2 * n} states)")
    print(f"coupling blocks (dofs): {[len(b) for b in blocks]}")
    print(f"multiblade matrices, batched:           {t_matrices * 1e3:8.1f} ms")
    print(f"per-speed numpy.linalg.eig loop:        {t_loop * 1e3:8.1f} ms")
    print(f"groundres block-wise batched eig:       {t_fast * 1e3:8.1f} ms")
    print(f"ratio (loop / groundres):               {t_loop / t_fast:8.1f} x   (target >= 5 x)")
    print(f"whole analyze() incl. tracking, labels, ranges, damping search: {t_analyze * 1e3:.0f} ms")


if __name__ == "__main__":
    main()
