"""The azimuth-domain coefficient matrices at any azimuth (node matrices) and on fixed grids.

The blade-coordinate equations M(psi) q'' + C(psi) q' + K(psi) q = 0, in the
azimuth psi = Omega t, read q'' = (F_a + F_b / Omega + F_c / Omega^2) [q; q']
with ' = d/dpsi, because the mass matrix does not depend on Omega, damping is
C0 + Omega C1 and stiffness K0 + Omega K1 + Omega^2 K2:

    F_a = -M^-1 [K2, C1],   F_b = -M^-1 [K1, C0],   F_c = -M^-1 [K0, 0],

and, for dampings c_j set per speed along the system's damping directions
(C0 + sum_j c_j D_j: a lag damping on the working dampers, or the damping
keys a design study varies), F_j = -M^-1 [0, D_j] with coefficient c_j / Omega;
a stiffness direction (K0 + sum_j k_j S_j: the equivalent spring of a damper
law, :attr:`groundres.model.system.System.direction_halves`) is F_j = -M^-1 [S_j, 0]
with coefficient k_j / Omega^2.

Every coefficient is a trigonometric polynomial of degree two in the azimuth,
so the matrices are fitted exactly from five azimuths (at three speeds, which
separate the powers of Omega). The blades' own block of the mass matrix
(lag and flap of each blade, which meet only through the body) does not
depend on the azimuth: M^-1 is applied through the Schur complement on the
body's few coordinates, so a node costs a few products with the
(precomputed) blade block's inverse applied to the harmonics instead of a
dense solve. Where the blade block does vary (no such model today), the
dense solve is used.

The roots of the equations held at a few azimuths (:func:`frozen_roots`)
bound those of the periodic system roughly: they set step counts and tell
where the lifted Floquet problem is needed.
"""

from __future__ import annotations

import threading

import numpy as np

from ...model.system import System
from ..parallel import CORES, map_threads

#: Largest node grid kept on a system [values]; finer grids are evaluated in pieces.
GRID_CACHE_SIZE = 4_000_000
#: Held while a system's grid cache is read or changed (threads of one batch share it).
_CACHE_LOCK = threading.Lock()


def _harmonic_basis(psi, degree: int = 2):
    """(1, cos psi, sin psi, ..., cos d psi, sin d psi) along a new last axis."""
    terms = [np.ones_like(psi)]
    for d in range(1, degree + 1):
        terms += [np.cos(d * psi), np.sin(d * psi)]
    return np.stack(terms, -1)


class _Harmonics:
    """The harmonics of M and of the right-hand sides [K2, C1, K1, C0, K0, D_1, ...] of one system."""

    def __init__(self, system: System):
        theta = 2 * np.pi * np.arange(5) / 5
        probe = np.array([0.0, 1.0, 2.0])
        m, c, k = system.matrices(probe, theta[:, None])  # (5 azimuths, 3 speeds, n, n)
        c0, c1 = c[:, 0], c[:, 1] - c[:, 0]
        k0 = k[:, 0]
        k2 = (k[:, 2] - 2 * k[:, 1] + k0) / 2
        k1 = k[:, 1] - k0 - k2
        blocks = [k2, c1, k1, c0, k0]
        for direction in system.damping_directions:
            blocks.append(np.broadcast_to(direction, k0.shape))
        fit = np.linalg.inv(_harmonic_basis(theta))
        self.n = n = m.shape[-1]
        self.mass = np.einsum("hj,jab->hab", fit, m[:, 0])  # (5, n, n)
        self.right = np.einsum("hj,jab->hab", fit, np.concatenate(blocks, -1))  # (5, n, W)
        nb = self.nb = system.n_body
        blade = self.mass[:, nb:, nb:]
        scale = np.abs(blade[0]).max() if n > nb else 0.0
        self.schur = n > nb and bool(np.abs(blade[1:]).max() <= 1e-13 * scale)
        if self.schur:
            # G = Mll^-1 R_l and H = Mll^-1 M_lb (degree 2), and the Schur complement's
            # S = M_bb - M_bl H and right-hand side E = R_b - M_bl G (degree 4, fitted at nine azimuths)
            inv = np.linalg.inv(blade[0])
            self.g = np.einsum("ab,hbw->haw", inv, self.right[:, nb:])
            self.h = np.einsum("ab,hbw->haw", inv, self.mass[:, nb:, :nb])
            theta9 = 2 * np.pi * np.arange(9) / 9
            at9 = _harmonic_basis(theta9)
            mbl = np.einsum("th,hab->tab", at9, self.mass[:, :nb, nb:])
            s9 = np.einsum("th,hab->tab", at9, self.mass[:, :nb, :nb]) - mbl @ np.einsum(
                "th,hab->tab", at9, self.h
            )
            e9 = np.einsum("th,hab->tab", at9, self.right[:, :nb]) - mbl @ np.einsum(
                "th,hab->tab", at9, self.g
            )
            fit9 = np.linalg.inv(_harmonic_basis(theta9, 4))
            self.s = np.einsum("ht,tab->hab", fit9, s9)
            self.e = np.einsum("ht,tab->hab", fit9, e9)

    def solve(self, psi, sign: float = 1.0) -> np.ndarray:
        """``sign`` M(psi)^-1 [K2, C1, K1, C0, K0, D_1, ...](psi): (..., n, W)."""
        psi = np.asarray(psi, dtype=float)
        basis = _harmonic_basis(psi).reshape(-1, 5)

        def at(coeff, b=basis, scale=1.0):  # a trigonometric polynomial at every azimuth: one product
            return (b @ (scale * coeff.reshape(len(coeff), -1))).reshape(psi.shape + coeff.shape[1:])

        if not self.schur:
            return np.linalg.solve(at(self.mass), at(self.right, scale=sign))
        nb = self.nb
        if nb == 0:
            return at(self.g, scale=sign)
        basis4 = _harmonic_basis(psi, 4).reshape(-1, 9)
        # (S is the body's small, well-conditioned mass matrix with the blades' share:
        # its inverse applied is several times faster than a batched solve with W columns)
        xb = np.linalg.inv(at(self.s, basis4)) @ at(self.e, basis4, sign)  # (..., nb, W)
        out = np.empty(psi.shape + (self.n, self.g.shape[-1]))
        out[..., :nb, :] = xb
        out[..., nb:, :] = at(self.g, scale=sign)  # G - H xb
        out[..., nb:, :] -= at(self.h) @ xb
        return out


def _harmonics(system: System) -> _Harmonics:
    """The system's harmonics, fitted once and kept on it (in air: on a system frozen at one
    speed's trim, whose matrices are polynomials in the speed)."""
    if system.rotor.aero is not None and system._frozen is None:
        raise ValueError("node matrices of a rotor in air need a system frozen at one speed's trim")
    fit = system.grid_cache.get("node_harmonics")
    if fit is None:
        fit = system.grid_cache["node_harmonics"] = _Harmonics(system)
    return fit


#: Which half of [q; q'] the first five blocks of :func:`node_blocks` multiply
#: (0: q, 1: q'); the directions after them multiply their own half (q' for damping).
HALVES = (0, 1, 0, 1, 0)


def halves(blocks: int, tail=()) -> tuple:
    """The half of [q; q'] each of ``blocks`` blocks multiplies: :data:`HALVES`, then the
    directions' ``tail`` (:attr:`groundres.model.system.System.direction_halves`: 1 a
    damping direction, 0 a stiffness one), then q'."""
    fixed = HALVES[:blocks]
    rest = blocks - len(fixed)
    tail = tuple(tail)[:rest]
    return fixed + tail + (1,) * (rest - len(tail))


def node_blocks(system: System, psi, directions: int = 0) -> np.ndarray:
    """-M^-1 [K2, C1, K1, C0, K0, D_1 .. D_d] at azimuths ``psi`` (any shape): (..., n, (5 + d) n).

    The node matrices in compact form: F = sum_b coef_b X_b placed on the
    half :func:`halves` [b] of [q; q'] (:func:`node_coefficients`); the first
    ``directions`` damping directions D_j of the system
    (:attr:`groundres.model.system.System.damping_directions`) are included.
    """
    x = _harmonics(system).solve(psi, sign=-1.0)
    return x[..., : (5 + directions) * system.size]


def expand(blocks: np.ndarray, coef: np.ndarray, tail=()) -> np.ndarray:
    """F = sum_b coef_b X_b on its half (:func:`halves` with the directions' ``tail``):
    blocks (..., n, B n), coef (n_s, B) -> (n_s, ..., n, 2n)."""
    n = blocks.shape[-2]
    out = np.zeros(coef.shape[:1] + blocks.shape[:-1] + (2 * n,))
    shape = (len(coef),) + (1,) * blocks.ndim
    for b, half in enumerate(halves(coef.shape[1], tail)):
        out[..., half * n : (half + 1) * n] += coef[:, b].reshape(shape) * blocks[..., b * n : (b + 1) * n]
    return out


def node_matrices(system: System, psi) -> tuple[np.ndarray, ...]:
    """F_a, F_b, F_c at azimuths ``psi`` (any shape), each (..., n, 2n).

    q'' = (F_a + F_b / Omega + F_c / Omega^2) [q; q'] with ' = d/dpsi.
    """
    return tuple(expand(node_blocks(system, psi), np.repeat(np.eye(3), 2, axis=1)[:, :5]))


def grid_values(n: int, steps: int, stages: int, directions: int = 0) -> int:
    """Values of a grid of node blocks (:func:`grid_nodes`) for ``n`` coordinates."""
    return steps * stages * n * n * (5 + directions)


def grid_nodes(
    system: System,
    angle: float,
    steps: int,
    tableau,
    first: int = 0,
    last: int | None = None,
    directions: int = 0,
) -> np.ndarray:
    """:func:`node_blocks` at the stage nodes of steps first..last of a fixed grid: (k, stages, n, W).

    Grids up to GRID_CACHE_SIZE values are kept on the system (the most
    recent ones, up to four times that in all) so that repeated analyses
    reuse them; finer ones are evaluated as asked.
    """
    last = steps if last is None else last
    h = angle / steps
    size = grid_values(system.size, steps, len(tableau.c), directions)

    def evaluated(a, b):  # (steps a..b, in parts over the pool's threads: NumPy releases the GIL)
        rows = np.array_split(np.arange(a, b), min(CORES, max(1, (b - a) // 8)))
        parts = map_threads(
            lambda r: node_blocks(system, (r[:, None] + tableau.c[None, :]) * h, directions), rows
        )
        return np.concatenate(parts) if len(parts) > 1 else parts[0]

    if size > GRID_CACHE_SIZE:
        return evaluated(first, last)
    cache = system.grid_cache
    key = (angle, int(steps), id(tableau), directions)
    with _CACHE_LOCK:  # (one thread builds a grid; the others wait for it)
        if key in cache:
            cache[key] = cache.pop(key)  # (the most recently used last)
        else:
            grids = [k for k in cache if isinstance(k, tuple)]
            while grids and sum(cache[k].size for k in grids) + size > 4 * GRID_CACHE_SIZE:
                del cache[grids.pop(0)]
            cache[key] = evaluated(0, steps)
        return cache[key][first:last]


def per_speed(damping, n_s: int):
    """Dampings along the damping directions at each speed, (n_s, d) (None stays None).

    ``damping``: a number or (n_s,) for one direction, or (n_s, d).
    """
    if damping is None:
        return None
    damping = np.asarray(damping, dtype=float)
    if damping.ndim < 2:
        damping = np.broadcast_to(damping, (n_s,))[:, None]
    return np.broadcast_to(damping, (n_s, damping.shape[1]))


def directions_of(damping) -> int:
    """How many damping directions per-speed dampings (:func:`per_speed`) set."""
    return 0 if damping is None else 1 if np.ndim(damping) < 2 else np.shape(damping)[1]


def node_coefficients(speeds, damping=None, tail=()) -> np.ndarray:
    """Per-speed coefficients of the blocks of :func:`node_blocks`: (n_s, 5 + d).

    (1, 1, 1/Omega, 1/Omega, 1/Omega^2) and, with ``damping`` (per speed along
    the system's d directions, :func:`per_speed`, in the system's units), c_j / Omega
    for a damping direction and k_j / Omega^2 for a stiffness one (``tail`` [j] = 0,
    :func:`halves`).
    """
    inv = 1.0 / np.asarray(speeds, dtype=float)
    cols = [np.ones_like(inv), np.ones_like(inv), inv, inv, inv**2]
    if damping is not None:
        values = per_speed(damping, len(inv))
        sides = halves(5 + values.shape[1], tail)[5:]
        cols += [v * (inv if side else inv**2) for v, side in zip(values.T, sides)]
    return np.stack(cols, 1)


def frozen_roots(system: System, speeds, probes=2, damping=None) -> np.ndarray:
    """Roots [1/rad] of the azimuth-domain system held at a few azimuths, (probes, n_s, 2n - k)
    (k: the system's integrals, whose positions are no state).

    With ``damping`` (per speed along the system's damping directions,
    :func:`per_speed`) the system is a split one
    (:meth:`groundres.model.system.System.split_damping`).
    """
    from ..modal import batched, first_order  # (threads for a long batch)

    speeds = np.asarray(speeds, dtype=float)
    damping = per_speed(damping, len(speeds))
    if system.rotor.aero is not None and system._frozen is None:  # (in air: speed by speed)
        parts = [
            frozen_roots(
                system.frozen(w), speeds[i : i + 1], probes, None if damping is None else damping[i : i + 1]
            )
            for i, w in enumerate(speeds)
        ]
        count = 2 * system.size - len(system.integrals)
        return np.concatenate(parts, axis=1) if parts else np.zeros((probes, 0, count))
    directions = directions_of(damping)
    key = f"frozen-{probes}-{directions}"  # (the same few azimuths every time: their blocks are kept)
    with _CACHE_LOCK:
        blocks = system.grid_cache.get(key)
        if blocks is None:
            psi = np.linspace(0, 2 * np.pi, probes, endpoint=False)
            blocks = system.grid_cache[key] = node_blocks(system, psi, directions)
    tail = system.direction_halves
    f = np.swapaxes(expand(blocks, node_coefficients(speeds, damping, tail), tail), 0, 1)
    a = first_order(f, system.integrals)  # (the integrals' positions are no state)
    return batched(np.linalg.eigvals, a.reshape((-1,) + a.shape[-2:])).reshape(a.shape[:-1])


def rates_per_radian(system: System, speeds, probes=2, damping=None) -> np.ndarray:
    """Fastest rate of the azimuth-domain system [1/rad] at each speed (from a few azimuths)."""
    return np.abs(frozen_roots(system, speeds, probes, damping)).max(-1).max(0)


def frozen_rates(system: System, speeds, probes=4, damping=None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Fastest rate per radian and smallest, largest real part [1/s] from one frozen solve.

    (:func:`rates_per_radian` and the real parts at once; azimuths 0, pi/2, pi,
    3 pi/2). The roots of the equations with the azimuth held fixed bound those
    of the periodic system roughly (a blade without damper keeps its neutral
    root, the others their damping), which the lifted Floquet problem needs
    before it has any root.
    """
    speeds = np.asarray(speeds, dtype=float)
    roots = frozen_roots(system, speeds, probes, damping)
    real = roots.real * speeds[:, None]
    return np.abs(roots).max(-1).max(0), real.min(-1).min(0), real.max(-1).max(0)
