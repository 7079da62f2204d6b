"""Periodic systems: monodromy matrix, Floquet exponents, periodic eigenvectors.

The blade-coordinate equations M(psi) q'' + C(psi) q' + K(psi) q = 0 are
integrated in the azimuth psi = Omega t. With q' = dq/dpsi they read

    q'' = (F_a(psi) + F_b(psi) / Omega + F_c(psi) / Omega^2) [q; q'],

because the mass matrix does not depend on Omega, damping is C0 + Omega C1 and
stiffness K0 + Omega K1 + Omega^2 K2 (dampers and springs; Coriolis;
centrifugal). The three F matrices are evaluated exactly from the derived
harmonics at the nodes of a fixed azimuth grid, once for all speeds, so that a
step for every speed of a sweep costs a few batched matrix products.

The integrator is the eighth-order Runge-Kutta method of Dormand and Prince
(the twelve stages of DOP853) on a fixed grid, chosen on evidence: for
multipliers to 1e-10 it needs three to five times fewer stage evaluations
than a sixth-order method (Butcher 1964, kept as BUTCHER6 for comparison). The
equations are linear, so every step's propagator is formed independently, for
all steps and speeds of a batch at once, and multiplied together by pairwise
reduction. The step count is chosen per speed: a first guess from the fastest
rate of the system per radian, then a Richardson estimate against a coarser
grid, and more steps where it is not met (:func:`_integrate`). Speeds with the
same step count are integrated together. ``benchmarks/bench_floquet.py``
compares it with SciPy's adaptive DOP853.

Symmetry (fast Floquet theory, Peters 1995, "Fast Floquet theory and trim for
multi-bladed rotorcraft", JAHS 39(4)): if advancing the azimuth by
Delta = 2 pi j / N maps the equations onto themselves with blade k + j taking
the place of blade k, then Phi(T) = (G^-1 Phi(Delta))^(N/j) with G that
permutation. Only Delta is integrated; the exponents come from
R = G^-1 Phi(Delta) and are unique up to multiples of (N/j) Omega.
"""

from __future__ import annotations

import math
import os
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from fractions import Fraction as _F

import numpy as np

from . import _dop853
from .system import System

# Butcher (1964) sixth-order, seven-stage explicit Runge-Kutta method.
_C = [0, _F(1, 3), _F(2, 3), _F(1, 3), _F(1, 2), _F(1, 2), 1]
_A = [
    [],
    [_F(1, 3)],
    [0, _F(2, 3)],
    [_F(1, 12), _F(1, 3), _F(-1, 12)],
    [_F(-1, 16), _F(9, 8), _F(-3, 16), _F(-3, 8)],
    [0, _F(9, 8), _F(-3, 8), _F(-3, 4), _F(1, 2)],
    [_F(9, 44), _F(-9, 11), _F(63, 44), _F(18, 11), 0, _F(-16, 11)],
]
_B = [_F(11, 120), 0, _F(27, 40), _F(27, 40), _F(-4, 15), _F(-4, 15), _F(11, 120)]


@dataclass(frozen=True)
class Tableau:
    """An explicit Runge-Kutta method: nodes c, matrix a (lower triangular), weights b."""

    c: np.ndarray
    a: np.ndarray
    b: np.ndarray
    order: int

    @classmethod
    def from_lists(cls, c, a, b, order):
        s = len(c)
        mat = np.zeros((s, s))
        for i, row in enumerate(a):
            mat[i, : len(row)] = [float(v) for v in row]
        return cls(np.array([float(v) for v in c]), mat, np.array([float(v) for v in b]), order)


BUTCHER6 = Tableau.from_lists(_C, _A, _B, 6)
#: Dormand-Prince eighth-order method (DOP853's twelve stages) on a fixed grid:
#: for multipliers to 1e-10 it needs three to five times fewer stage
#: evaluations than BUTCHER6 on the shipped cases (benchmarks/bench_floquet.py).
DOP8 = Tableau.from_lists(_dop853.C, _dop853.A, _dop853.B, 8)
#: First guess of step * (fastest rate per radian + HARMONIC_RATE).
STEP_SCALE = 1.0
#: Rate [1/rad] added for the azimuth variation of the coefficients themselves.
HARMONIC_RATE = 2.0
#: Accuracy asked of the transition matrix (entries, relative to max(1, |Phi|)).
TOLERANCE = 5e-11


@dataclass(frozen=True)
class Symmetry:
    """Azimuth shift that maps the system onto itself.

    Attributes
    ----------
    shift : int
        Blades j moved by the map (N for no symmetry: the full period).
    angle : float
        Azimuth interval Delta = 2 pi j / N [rad].
    g : ndarray (n, n)
        Permutation of coordinates with X(psi + Delta) = g X(psi) g' for the
        mass, damping and stiffness matrices X.
    """

    shift: int
    angle: float
    g: np.ndarray


def symmetry(system: System) -> Symmetry:
    """The shortest azimuth shift under which the blade-coordinate equations repeat.

    In blade coordinates (body axes nonrotating) every coefficient is a sum over
    blades of functions of each blade's own azimuth, so advancing the azimuth by
    2 pi j / N only hands each blade's role to blade k + j: the equations repeat
    when the blades do (blade k like blade k + j), whatever the body.
    """
    rotor = system.rotor
    n = rotor.n_blades
    for j in range(1, n + 1):
        if n % j == 0 and all(rotor.blades[k] == rotor.blades[(k + j) % n] for k in range(n)):
            return Symmetry(j, 2 * math.pi * j / n, _coordinate_map(system, j))
    raise AssertionError("the full period is always a symmetry")


def _coordinate_map(system: System, shift: int) -> np.ndarray:
    """g with X(psi + Delta) = g X(psi) g' (blade k + j takes blade k's place)."""
    size, n_body, n = system.size, system.n_body, system.n_blades
    g = np.zeros((size, size))
    g[:n_body, :n_body] = np.eye(n_body)
    for kind in range(len(system.blade_kinds)):
        base = n_body + kind * n
        for k in range(n):
            g[base + k, base + (k + shift) % n] = 1.0
    return g


def node_matrices(system: System, psi) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """F_a, F_b, F_c at azimuths ``psi`` (any shape), each (..., n, 2n).

    q'' = (F_a + F_b / Omega + F_c / Omega^2) [q; q'] with ' = d/dpsi.
    """
    psi = np.asarray(psi, dtype=float)
    probe = np.array([0.0, 1.0, 2.0])
    m, c, k = system.matrices(probe, psi[..., None])  # (..., 3 speeds, n, n)
    mass = m[..., 0, :, :]
    c0, c1 = c[..., 0, :, :], c[..., 1, :, :] - c[..., 0, :, :]
    k0 = k[..., 0, :, :]
    k2 = (k[..., 2, :, :] - 2 * k[..., 1, :, :] + k0) / 2
    k1 = k[..., 1, :, :] - k0 - k2
    zero = np.zeros_like(k0)
    rhs = np.concatenate([k2, c1, k1, c0, k0, zero], -1)  # (..., n, 6n)
    sol = -np.linalg.solve(mass, rhs)
    n2 = 2 * mass.shape[-1]
    return sol[..., :n2], sol[..., n2 : 2 * n2], sol[..., 2 * n2 :]


def rates_per_radian(system: System, speeds, probes=2) -> np.ndarray:
    """Fastest rate of the azimuth-domain system [1/rad] at each speed (from a few azimuths)."""
    speeds = np.asarray(speeds, dtype=float)
    psi = np.linspace(0, 2 * np.pi, probes, endpoint=False)
    fa, fb, fc = node_matrices(system, psi)
    inv = 1.0 / speeds
    f = fa[:, None] + fb[:, None] * inv[:, None, None] + fc[:, None] * (inv**2)[:, None, None]
    n = f.shape[-2]
    a = np.zeros(f.shape[:-2] + (2 * n, 2 * n))
    a[..., :n, n:] = np.eye(n)
    a[..., n:, :] = f
    return np.abs(np.linalg.eigvals(a)).max(-1).max(0)


def grid_matrices(system: System, angle: float, steps: int, tableau=DOP8):
    """F_a, F_b, F_c at the stage nodes of a fixed grid: each (steps, stages, n, 2n).

    Kept on the system (a few grids) so that repeated analyses reuse them.
    """
    key = (angle, int(steps), id(tableau))
    if key not in system.grid_cache:
        if len(system.grid_cache) > 16:
            system.grid_cache.clear()
        h = angle / steps
        system.grid_cache[key] = node_matrices(system, (np.arange(steps)[:, None] + tableau.c[None, :]) * h)
    return system.grid_cache[key]


_POOL = None
_CORES = min(os.cpu_count() or 1, 4)


def _map(fn, items):
    """Map over items in threads (NumPy's matrix products release the GIL)."""
    global _POOL
    items = list(items)
    if len(items) < 2 or _CORES < 2:
        return map(fn, items)
    if _POOL is None:
        _POOL = ThreadPoolExecutor(_CORES)
    return _POOL.map(fn, items)


def _ordered_product(p):
    """P[-1] @ ... @ P[1] @ P[0] over the first axis, by pairwise reduction."""
    while p.shape[0] > 1:
        if p.shape[0] % 2:
            tail = p[-1:]
            p = np.concatenate([p[1:-1:2] @ p[0:-1:2], tail])
        else:
            p = p[1::2] @ p[0::2]
    return p[0]


def _step_propagators(fa, fb, fc, inv, h, tableau):
    """One-step propagators of the Runge-Kutta method for every step and speed.

    The equation is linear, so each step's propagator P = I + h sum b_i K_i
    (stages started from the identity) is independent of the others and all
    are formed at once: arrays (steps, n_s, 2n, 2n). With y = [q; v] and
    v' = F y, a stage is K_i = [V_i; F_i Y_i]; only the lower halves
    L_i = F_i Y_i are stored, because the upper halves follow from them:
    Y_i = [I_q + h c_i I_v + h^2 sum (A^2)_il L_l ; I_v + h sum a_il L_l].
    """
    steps, stages, n, n2 = fa.shape
    n_s = len(inv)
    coef = np.stack([np.ones_like(inv), inv, inv**2])  # (3, n_s)
    # F at every node and speed with one matrix product, laid out (stages, steps, n_s, n, 2n)
    nodes = np.stack([fa, fb, fc], 2).reshape(steps, stages, 3, n * n2)
    f = np.einsum("tspm,pk->stkm", nodes, coef, optimize=True).reshape(stages, steps, n_s, n, n2)
    a, b, c = tableau.a, tableau.b, tableau.c
    a2 = a @ a
    eye_q, eye_v = np.eye(n2)[:n], np.eye(n2)[n:]
    low = np.empty((stages, steps, n_s, n, n2))
    y = np.empty((steps, n_s, n2, n2))
    for i in range(stages):
        if i == 0:
            low[0] = f[0]  # Y_1 = I
            continue
        weights = np.stack([h * h * a2[i, :i], h * a[i, :i]])
        both = np.tensordot(weights, low[:i], axes=(1, 0))  # (2, steps, n_s, n, 2n)
        y[..., :n, :] = both[0] + (eye_q + h * c[i] * eye_v)
        y[..., n:, :] = both[1] + eye_v
        np.matmul(f[i], y, out=low[i])
    weights = np.stack([h * h * (b @ a), h * b])
    both = np.tensordot(weights, low, axes=(1, 0))
    out = np.empty((steps, n_s, n2, n2))
    out[..., :n, :] = both[0] + (eye_q + h * b.sum() * eye_v)
    out[..., n:, :] = both[1] + eye_v
    return out


def transition(system: System, speeds, angle: float, steps: int, samples: int = 0, tableau=DOP8, nodes=None):
    """Azimuth-domain transition matrices over [0, angle] for a batch of speeds.

    Parameters
    ----------
    system : System
    speeds : ndarray (n_s,)
        Rotor speeds [rad/s] integrated together.
    angle : float
        Azimuth interval [rad].
    steps : int
        Fixed steps over the interval (a multiple of ``samples``).
    samples : int
        If > 0, also return the transition matrix at this many equally spaced
        azimuths in [0, angle).
    tableau : Tableau
    nodes : tuple of ndarray, optional
        ``grid_matrices(system, angle, steps, tableau)``, if already computed.

    Returns
    -------
    phi : ndarray (n_s, 2n, 2n)
        Transition matrix of y = [q; dq/dpsi] from 0 to ``angle``.
    sampled : ndarray (samples, n_s, 2n, 2n), only if samples > 0
    """
    speeds = np.asarray(speeds, dtype=float)
    h = angle / steps
    fa, fb, fc = nodes if nodes is not None else grid_matrices(system, angle, steps, tableau)
    n2 = fa.shape[-1]
    chunk = max(1, int(3e6 // (steps * len(tableau.c) * n2 * n2)))  # about 25 MB of stages
    chunk = min(chunk, -(-len(speeds) // _CORES))  # at least one batch per core
    parts = [speeds[i : i + chunk] for i in range(0, len(speeds), chunk)]
    props = np.concatenate(
        list(_map(lambda w: _step_propagators(fa, fb, fc, 1.0 / w, h, tableau), parts)), axis=1
    )  # (steps, n_s, 2n, 2n)
    blocks = max(samples, 1)
    per = steps // blocks
    block_props = np.stack([_ordered_product(props[b * per : (b + 1) * per]) for b in range(blocks)])
    y = np.broadcast_to(np.eye(props.shape[-1]), props.shape[1:]).copy()
    sampled = np.empty((samples,) + y.shape) if samples else None
    for b in range(blocks):
        if samples:
            sampled[b] = y
        y = block_props[b] @ y
    return (y, sampled) if samples else y


@dataclass
class FloquetSolution:
    """Floquet analysis of a sweep.

    Attributes
    ----------
    exponent : complex ndarray (n_s, 2n)
        Floquet exponents [1/s], principal values (Im in (-Omega_F/2, Omega_F/2],
        Omega_F = (N / j) Omega).
    multiplier : complex ndarray (n_s, 2n)
        Eigenvalues of R = G^-1 Phi(Delta) (the multipliers of the reduced period).
    vector : complex ndarray (n_s, 2n, 2n)
        Eigenvectors of R (columns), in y = [q; dq/dpsi].
    sampled : ndarray (K, n_s, 2n, 2n)
        Transition matrix at K equally spaced azimuths over [0, Delta).
    symmetry : Symmetry
    steps : int ndarray (n_s,)
    """

    exponent: np.ndarray
    multiplier: np.ndarray
    vector: np.ndarray
    sampled: np.ndarray
    symmetry: Symmetry
    steps: np.ndarray
    speeds: np.ndarray


def _ladder(samples):
    """Allowed step counts: multiples of ``samples`` growing by factors 1.5 and 4/3."""
    out, k = [], 1
    while k * samples <= 1 << 16:
        out.append(k * samples)
        k = 2 if k == 1 else (k * 3 // 2 if k % 2 == 0 else k * 4 // 3)
    return np.array(sorted(set(out)))


def _integrate(system, speeds, angle, samples, tolerance, scale, tableau):
    """Transition over [0, angle], step count adapted per speed.

    Each speed is integrated with S steps and with fewer steps S' on the same
    ladder; the Richardson estimate |Phi_S - Phi_S'| / ((S/S')^p - 1) of the
    error of Phi_S decides. A speed that fails is integrated again with the
    step count the estimate predicts (error ~ S^-p), and its last result
    serves as the next comparison.
    """
    ladder = _ladder(max(samples, 1))
    rate = rates_per_radian(system, speeds)
    guess = angle * (rate + HARMONIC_RATE) / scale
    steps = ladder[np.minimum(np.searchsorted(ladder, guess), len(ladder) - 1)]
    n2 = 2 * system.size
    p = tableau.order
    phi = np.empty((len(speeds), n2, n2))
    sampled = np.empty((samples, len(speeds), n2, n2)) if samples else None
    previous = {}  # speed index -> (steps, phi) of its last rejected run
    pending = np.arange(len(speeds))

    def run(sel, count, with_samples):
        nodes = grid_matrices(system, angle, int(count), tableau)
        return transition(system, speeds[sel], angle, int(count), with_samples, tableau, nodes)

    for _ in range(10):
        if not len(pending):
            break
        retry = []
        for count in np.unique(steps[pending]):
            sel = pending[steps[pending] == count]
            fine = run(sel, count, samples)
            fine_phi = fine[0] if samples else fine
            size = np.maximum(np.abs(fine_phi).max((-1, -2)), 1.0)
            if all(i in previous for i in sel):
                ref_steps = np.array([previous[i][0] for i in sel])
                ref_phi = np.stack([previous[i][1] for i in sel])
                estimate = np.abs(fine_phi - ref_phi).max((-1, -2)) / ((count / ref_steps) ** p - 1) / size
            else:
                pos = np.searchsorted(ladder, count)
                coarse = ladder[pos - 2] if pos >= 2 else count // 2
                # The truncation error varies smoothly with speed: the coarse
                # comparison runs on every fourth speed of the batch (and its
                # ends), each speed taking the larger estimate of its sampled
                # neighbours.
                probe = np.unique(np.r_[np.arange(0, len(sel), 4), len(sel) - 1])
                ref_phi = run(sel[probe], coarse, 0)
                sampled_est = np.abs(fine_phi[probe] - ref_phi).max((-1, -2)) / size[probe]
                sampled_est /= (count / coarse) ** p - 1
                right = np.clip(np.searchsorted(probe, np.arange(len(sel))), 0, len(probe) - 1)
                left = np.clip(right - (probe[right] > np.arange(len(sel))), 0, len(probe) - 1)
                estimate = np.maximum(sampled_est[left], sampled_est[right])
            phi[sel] = fine_phi
            if samples:
                sampled[:, sel] = fine[1]
            for j, i in enumerate(sel):
                if estimate[j] > tolerance:
                    want = count * (estimate[j] / tolerance) ** (1 / p) * 1.1
                    steps[i] = ladder[min(np.searchsorted(ladder, want), len(ladder) - 1)]
                    previous[i] = (count, fine_phi[j])
                    retry.append(i)
        pending = np.array(sorted(retry), int)
    return phi, sampled, steps


def solve(
    system: System, speeds, samples: int = 16, tolerance=TOLERANCE, scale=STEP_SCALE, tableau=DOP8
) -> FloquetSolution:
    """Floquet exponents and periodic eigenvectors at every speed.

    Speeds are grouped by step count; each group is integrated in one batch,
    and a speed whose error estimate is too large is integrated again with
    twice the steps.
    """
    speeds = np.asarray(speeds, dtype=float)
    sym = symmetry(system)
    phi, sampled, steps = _integrate(system, speeds, sym.angle, samples, tolerance, scale, tableau)
    g = np.kron(np.eye(2), sym.g)
    reduced = g.T @ phi  # g is orthogonal
    rho, vec = np.linalg.eig(reduced)
    dt = sym.angle / speeds[:, None]
    exponent = np.log(rho.astype(complex)) / dt
    return FloquetSolution(exponent, rho, vec, sampled, sym, steps, speeds)


def monodromy(system: System, speeds, tolerance=TOLERANCE, scale=STEP_SCALE, tableau=DOP8) -> np.ndarray:
    """Full-revolution transition matrix of x = [q; dq/dt], shape (n_s, 2n, 2n).

    Built from the reduced period with the symmetry when there is one.
    """
    speeds = np.asarray(speeds, dtype=float)
    sym = symmetry(system)
    phi, _, _ = _integrate(system, speeds, sym.angle, 0, tolerance, scale, tableau)
    g = np.kron(np.eye(2), sym.g)
    full = np.linalg.matrix_power(g.T @ phi, system.n_blades // sym.shift)
    n = system.size
    # y = [q; dq/dpsi] -> x = [q; dq/dt] = D y with D = diag(1, Omega)
    d = np.concatenate([np.ones((len(speeds), n)), np.repeat(speeds[:, None], n, 1)], 1)
    return d[:, :, None] * full / d[:, None, :]
