"""The compiled transition kernel against the NumPy reference, its embedded error
control against finer grids (tests/test_floquet.py checks the multipliers
against a tight SciPy integration), the node matrices
by the Schur complement against a dense solve, and the lag damping set per
speed against a system rebuilt with it."""

import os
from dataclasses import replace
from importlib import resources

import numpy as np
import pytest

from groundres import load_case
from groundres.model.system import System
from groundres.solve.floquet import coefficients, compiled, exponents, transition

SHIPPED = sorted(
    p.name[:-5] for p in (resources.files("groundres") / "cases").iterdir() if p.name.endswith(".toml")
)


def shipped_system(name):
    case = load_case(name)
    return System(case.rotor, case.body), case.sweep.speeds


def relative(a, b):
    """Largest entry difference relative to max(1, |b|), per matrix."""
    return np.abs(a - b).max((-1, -2)) / np.maximum(1.0, np.abs(b).max((-1, -2)))


@pytest.mark.parametrize("name", SHIPPED)
def test_compiled_and_numpy_kernels_agree_on_every_shipped_case(name):
    """Same grid, same method: the two paths differ by round-off only. 1e-12 is
    about 50 eps per entry after some hundred steps of a 12-stage method. Speeds
    where 48 steps do not resolve the fastest motion (more than 2 rad of it a
    step: a slow rotor under stiff gear legs) are left out: there the explicit
    method amplifies round-off by orders of magnitude, in both paths."""
    system, speeds = shipped_system(name)
    angle = exponents.symmetry(system).angle
    moving = speeds[speeds > 0]
    # (in air each speed on the equations frozen at its own trim, as the analysis does: two
    # speeds, each with its own node grids, check the same kernel as the vacuum's five)
    count = 2 if system.rotor.aero else 5
    moving = moving[np.unique(np.linspace(0, len(moving) - 1, 4 * count).astype(int))]
    moving = moving[transition.rates_per_radian(system, moving) * angle / 48 <= 2.0]
    assert len(moving), "no speed the fixed grid resolves"
    w = moving[np.linspace(0, len(moving) - 1, count).astype(int)]
    batches = (
        [(system.frozen(x), w[i : i + 1]) for i, x in enumerate(w)] if system.rotor.aero else [(system, w)]
    )
    for held, at in batches:
        for steps, parts in ((48, 1), (96, 4)):
            fast = transition.transition(held, at, angle, steps, parts, compiled=True)
            slow = transition.transition(held, at, angle, steps, parts, compiled=False)
            assert relative(fast, slow).max() < 1e-12


@pytest.mark.parametrize("name", ["hammond-1974-one-damper", "two-bladed", "soft-inplane-pitch-roll"])
def test_embedded_estimate_keeps_the_transition_matrix_within_the_tolerance(name):
    """The step count the embedded estimate settles on gives the transition
    matrix to TOLERANCE: checked against the same method on four times the steps."""
    system, speeds = shipped_system(name)
    angle = exponents.symmetry(system).angle
    w = speeds[speeds > 0][np.linspace(0, (speeds > 0).sum() - 1, 7).astype(int)]
    phi, steps = transition.integrate(system, w, angle, compiled=True)
    for count in np.unique(steps):
        sel = steps == count
        fine = transition.ordered_product(
            transition.transition(system, w[sel], angle, int(4 * count), compiled=True)
        )
        assert relative(phi[sel], fine).max() < transition.TOLERANCE


@pytest.mark.parametrize("name", ["soft-inplane-pitch-roll", "hammond-1974-one-damper"])
def test_node_matrices_by_the_schur_complement_equal_a_dense_solve(name):
    system, _ = shipped_system(name)
    psi = np.linspace(0, 2 * np.pi, 37)
    fit = coefficients._Harmonics(system)
    assert fit.schur
    fast = fit.solve(psi)
    fit.schur = False
    dense = fit.solve(psi)
    assert np.abs(fast - dense).max() < 1e-12 * np.abs(dense).max()


def test_lag_damping_per_speed_equals_a_system_rebuilt_with_it():
    """The equations are affine in the lag damping: one split system with the
    damping as a per-speed coefficient gives the transition matrices of systems
    rebuilt with each damping (one failed damper stays failed)."""
    system, speeds = shipped_system("hammond-1974-one-damper")
    split = system.lag_damping_split()
    angle = 2 * np.pi
    w = np.array([12.0, 20.0, 30.0])
    c = np.array([0.0, 2500.0, 40000.0])
    both = transition.transition(split, w, angle, 64)[0]
    each = transition.transition(split, w, angle, 64, damping=c, compiled=True)[0]
    for i in range(3):
        rebuilt = transition.transition(
            system.with_lag_damping(c[i]), w[i : i + 1], angle, 64, compiled=False
        )[0]
        assert relative(each[i : i + 1], rebuilt).max() < 1e-12
    assert relative(both[:1], each[:1]).max() < 1e-12  # (c = 0: the split system itself)
    assert system.with_lag_damping(c[1]).rotor.blades[0].lag_damping == 0.0  # (blade 1 failed)
    sym = exponents.symmetry(system)  # (the full period: c = 0 alone would repeat every quarter turn)
    ours = exponents.solve(split, w, harmonics=0, damping=c, sym=sym)
    for i in range(3):
        alone = exponents.solve(system.with_lag_damping(c[i]), w[i : i + 1], harmonics=0, sym=sym)
        np.testing.assert_allclose(
            np.sort_complex(ours.multiplier[i]), np.sort_complex(alone.multiplier[0]), atol=1e-9
        )


def test_per_blade_damping_and_stiffness_directions_equal_a_rebuilt_system():
    """A nonlinear damper's equivalent system sets each blade's damping and spring per point:
    the split system with one damping and one stiffness direction per blade gives the
    transition matrices (compiled and NumPy) and the roots at rest of systems rebuilt with
    those values."""
    system, _ = shipped_system("hammond-1974")
    rotor = system.rotor
    n = rotor.n_blades

    def rebuilt(c, k):
        blades = tuple(
            replace(b, lag_damping=float(c[j]), lag_stiffness=b.lag_stiffness + float(k[j]))
            for j, b in enumerate(rotor.blades)
        )
        return System(replace(rotor, blades=blades), system.body)

    zero = rebuilt([0.0] * n, [0.0] * n)
    unit = np.eye(n)
    split = zero.split_damping(
        [rebuilt(unit[j], [0.0] * n) for j in range(n)], [rebuilt([0.0] * n, unit[j]) for j in range(n)]
    )
    assert split.direction_halves == (1,) * n + (0,) * n
    w = np.array([0.0, 12.0, 30.0])
    values = np.array([[0.0, 1500.0, 4067.5, 9000.0], [3000.0, 0.0, 200.0, 4067.5], [10.0, 20.0, 0.0, 5.0]])
    springs = np.array([[0.0, 2e4, 5e5, 1e3], [1e5, 0.0, 0.0, 3e4], [7e4, 7e4, 0.0, 1e6]])
    both = np.concatenate([values, springs], axis=1)
    moving = slice(1, 3)
    for kernel in (True, False):
        each = transition.transition(split, w[moving], 2 * np.pi, 64, damping=both[moving], compiled=kernel)[
            0
        ]
        for i, row in zip(range(1, 3), range(2)):
            alone = rebuilt(values[i], springs[i])
            rebuilt_phi = transition.transition(alone, w[i : i + 1], 2 * np.pi, 64, compiled=False)[0]
            assert relative(each[row : row + 1], rebuilt_phi).max() < 1e-12
    sym = exponents.symmetry(rebuilt(np.arange(n), [0.0] * n))  # (the full period)
    ours = exponents.solve(split, w, harmonics=0, damping=both, sym=sym)
    for i in range(3):
        alone = exponents.solve(rebuilt(values[i], springs[i]), w[i : i + 1], harmonics=0, sym=sym)
        scale = np.abs(alone.exponent[0]).max()
        np.testing.assert_allclose(
            np.sort_complex(ours.exponent[i]), np.sort_complex(alone.exponent[0]), atol=1e-9 * scale
        )


def test_compiled_code_is_cached_only_where_no_one_else_can_write(tmp_path, monkeypatch):
    """numba's cache holds machine code: it is used only in folders that this
    user owns and no one else may write, under a root that no other account
    may write (its group only where that group is the user's own)."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    os.chmod(tmp_path, 0o755)
    mask = os.umask(0o002)  # (a usual umask for accounts with their own group)
    try:
        assert compiled.cache_folder() == str(tmp_path / "groundres" / "numba")
    finally:
        os.umask(mask)
    for folder in (tmp_path / "groundres", tmp_path / "groundres" / "numba"):
        assert (os.stat(folder).st_mode & 0o777) == 0o700
    os.chmod(tmp_path / "groundres", 0o770)
    assert compiled.cache_folder() is None
    os.chmod(tmp_path / "groundres", 0o700)
    os.chmod(tmp_path, 0o757)
    assert compiled.cache_folder() is None
    os.chmod(tmp_path, 0o775)
    own_group = os.stat(tmp_path).st_gid == os.getgid()
    assert (compiled.cache_folder() is not None) == own_group
    monkeypatch.setenv("XDG_CACHE_HOME", "relative/path")
    assert compiled.cache_folder() is None


def test_the_first_use_compiles_in_the_background_and_numpy_serves_meanwhile(tmp_path, monkeypatch):
    """A machine without the compiled kernel: the first use starts the compiler in a
    background process and gets None (NumPy integrates); once that process has
    filled the cache, the kernel is ready and gives the NumPy path's matrices."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    for name in ("_KERNEL", "_STARTED", "_BACKGROUND"):
        monkeypatch.setattr(compiled, name, None if name != "_STARTED" else False)
    assert compiled.kernel() is None
    assert not transition.use_kernel(transition.DOP8)
    assert compiled._BACKGROUND.wait(timeout=300) == 0
    assert compiled.kernel() is not None and transition.use_kernel(transition.DOP8)
    system, speeds = shipped_system("two-bladed")
    w = speeds[[10, 200]]
    fast = transition.transition(system, w, np.pi, 40)
    slow = transition.transition(system, w, np.pi, 40, compiled=False)
    assert relative(fast, slow).max() < 1e-12
