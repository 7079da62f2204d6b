"""Eigen-analysis of time-invariant systems over a speed sweep: solve, track, label.

* :func:`coupling_blocks` splits the coordinates into groups that do not couple
  (e.g. collective and differential lag never couple with hub motion), so that
  each small block is solved on its own: LAPACK cost grows with the cube of the
  size, and only the body-coupled block is large.
* :func:`solve` computes eigenvalues and eigenvectors of every block, batched
  over all speeds (one LAPACK call per block, no Python loop per speed).
* :func:`track` orders each speed's eigenvalues so that every column is one
  continuous branch (eigenvector similarity and predicted eigenvalue, optimal
  assignment).

Labels and frequencies of the roots come from :mod:`groundres.modes.identify`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import linear_sum_assignment
from scipy.sparse.csgraph import connected_components

from .parallel import CORES, map_threads


def kept_states(n: int, integrals=()) -> np.ndarray:
    """Which entries of x = [q, q'] are states: all but the positions of ``integrals``.

    An integral is a coordinate that enters the equations only through its rate
    (its stiffness column is zero: the inflow states of dynamic inflow, which are
    velocities): its position is no state, and dropping it removes exactly one
    root at zero that is no motion of the system.
    """
    return np.setdiff1d(np.arange(2 * n), np.asarray(integrals, int))


def first_order(accelerations, integrals=()):
    """x' = A x with x = [q, q'] from the accelerations' rows q'' = F x, ``accelerations``
    (..., n, 2n); without the positions of ``integrals`` (:func:`kept_states`)."""
    n = accelerations.shape[-2]
    a = np.zeros(accelerations.shape[:-2] + (2 * n, 2 * n))
    a[..., :n, n:] = np.eye(n)
    a[..., n:, :] = accelerations
    if len(integrals):
        keep = kept_states(n, integrals)
        a = a[..., keep[:, None], keep]
    return a


def state_matrix(mass, damping, stiffness, integrals=()):
    """First-order form x' = A x with x = [q, q'] (without the positions of ``integrals``,
    :func:`kept_states`), stacked over leading axes."""
    if len(integrals) and np.asarray(stiffness)[..., np.asarray(integrals, int)].any():
        raise ValueError("an integral coordinate has stiffness: its position is a state")
    rhs = np.linalg.solve(mass, np.concatenate([stiffness, damping], axis=-1))
    return first_order(-rhs, integrals)


def displacements(vectors, values, n: int, integrals=()):
    """The displacement part (..., n, m) of eigenvectors of :func:`state_matrix` (..., 2n - k, m)
    with eigenvalues ``values`` (..., m): an integral's displacement is its rate over the
    eigenvalue (at a root at zero, a constant rate: its rate itself, for its shape)."""
    if not len(integrals):
        return vectors[..., :n, :]
    integrals = np.asarray(integrals, int)
    k = len(integrals)
    out = np.empty(vectors.shape[:-2] + (n, vectors.shape[-1]), complex)
    out[..., np.setdiff1d(np.arange(n), integrals), :] = vectors[..., : n - k, :]
    out[..., integrals, :] = integrated(vectors[..., n - k + integrals, :], np.asarray(values)[..., None, :])
    return out


def integrated(rates, values):
    """Displacements whose rates are ``rates`` in motion growing as exp(``values`` t) (the two
    broadcast): rates over values; where a value is zero (a constant rate), the rates
    themselves, for their shape."""
    return np.where(values == 0, rates, rates / np.where(values == 0, 1.0, values))


def unit_mass_state_matrix(mass, damping, stiffness, integrals=()):
    """:func:`state_matrix` in coordinates scaled so that the mass matrix has a
    unit diagonal, and the scales d (the state is balanced whatever the units
    and sizes of body and blades; a similarity: the roots are the same, a
    displacement eigenvector is ``d[..., :, None] * displacements(v, w, n)``)."""
    d = 1.0 / np.sqrt(np.abs(np.diagonal(mass, axis1=-2, axis2=-1)))
    scale = d[..., :, None] * d[..., None, :]
    return state_matrix(mass * scale, damping * scale, stiffness * scale, integrals), d


def _normalised(mass, damping, stiffness):
    """Matrices scaled so that entries of every row/column are comparable."""
    d = np.sqrt(np.abs(np.diagonal(mass, axis1=-2, axis2=-1)))
    scale = d[..., :, None] * d[..., None, :]
    w = np.sqrt(np.maximum(np.abs(np.diagonal(stiffness, axis1=-2, axis2=-1)) / d**2, 0).max(-1))
    w = np.maximum(w, 1e-300)[..., None, None]
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        out = np.abs(mass) / scale + np.abs(damping) / (scale * w) + np.abs(stiffness) / (scale * w**2)
    # (0 / 0 where a zero entry meets an underflowed scale: that entry couples nothing)
    return np.nan_to_num(out, nan=0.0)


def coupling_blocks(mass, damping, stiffness, tol=1e-9) -> list[np.ndarray]:
    """Groups of coordinates that are coupled at some speed; sorted, largest first.

    The pattern is read at up to 16 speeds spread over the sweep: couplings are
    structural (they vanish only at isolated speeds such as Omega = 0).
    """
    n_s = mass.shape[0] if mass.ndim == 3 else 1
    pick = np.unique(np.linspace(0, n_s - 1, min(n_s, 16)).round().astype(int))
    mass, damping, stiffness = (x.reshape((-1,) + x.shape[-2:])[pick] for x in (mass, damping, stiffness))
    pattern = (_normalised(mass, damping, stiffness) > tol).any(0)
    count, label = connected_components(pattern, directed=False)
    blocks = [np.flatnonzero(label == i) for i in range(count)]
    return sorted(blocks, key=lambda b: (-len(b), b[0]))


def batched(fn, a):
    """Apply a batched LAPACK call over the leading axis, split across cores
    (:func:`groundres.solve.parallel.map_threads`)."""
    if a.ndim < 3 or a.shape[0] < 256 or CORES < 2:
        return fn(a)
    parts = map_threads(fn, np.array_split(a, CORES))
    if isinstance(parts[0], tuple):
        return tuple(np.concatenate(p) for p in zip(*parts))
    return np.concatenate(parts)


def _whirl_symmetric(m, c, k):
    """True when a 2-dof block has the form a I + b J (J = [[0, 1], [-1, 0]]) for M, C, K."""
    for x in (m, c, k):
        scale = np.abs(x).max() + 1e-300
        if np.abs(x[..., 0, 0] - x[..., 1, 1]).max() > 1e-12 * scale:
            return False
        if np.abs(x[..., 0, 1] + x[..., 1, 0]).max() > 1e-12 * scale:
            return False
    return True


def _quadratic_roots(a, b, c):
    """Both roots of a s^2 + b s + c = 0 (complex arrays)."""
    root = np.sqrt(b * b - 4 * a * c + 0j)
    return (-b + root) / (2 * a), (-b - root) / (2 * a)


def block_eig(m, c, k, vectors=True, integrals=()):
    """Eigenvalues (and displacement eigenvectors) of one block at every speed.

    One coordinate: the roots of m s^2 + c s + k. Two coordinates forming a
    whirl-symmetric pair (every pure-blade cyclic pair of identical blades):
    with u = q_c + i q_s the pair is one complex equation, solved in closed
    form; its roots are the forward (eigenvector [1, -i]) and the conjugate
    equation's the backward whirls ([1, i]). Anything else: batched LAPACK.

    ``integrals`` (indices in the block, :func:`kept_states`) are solved by
    LAPACK without their positions: 2n - k roots.

    Returns eigenvalues (..., 2n - k) and, if asked, vectors (..., n, 2n - k).
    """
    n = m.shape[-1]
    if n == 1 and not len(integrals):
        s1, s2 = _quadratic_roots(m[..., 0, 0] + 0j, c[..., 0, 0] + 0j, k[..., 0, 0] + 0j)
        w = np.stack([s1, s2], -1)
        return (w, np.ones(w.shape[:-1] + (1, 2), complex)) if vectors else w
    if n == 2 and not len(integrals) and _whirl_symmetric(m, c, k):
        coeff = [x[..., 0, 0] - 1j * x[..., 0, 1] for x in (m, c, k)]
        s1, s2 = _quadratic_roots(*coeff)
        w = np.stack([s1, s2, s1.conj(), s2.conj()], -1)
        if not vectors:
            return w
        v = np.array([[1, 1, 1, 1], [-1j, -1j, 1j, 1j]]) / np.sqrt(2)
        return w, np.broadcast_to(v, w.shape[:-1] + (2, 4)).copy()
    a, d = unit_mass_state_matrix(m, c, k, integrals)
    if not vectors:
        return batched(np.linalg.eigvals, a)
    w, v = batched(np.linalg.eig, a)
    q = displacements(v, w, n, integrals) * d[..., :, None]
    return w, q / np.linalg.norm(q, axis=-2, keepdims=True)


def within(block, integrals) -> np.ndarray:
    """The positions in ``block`` (coordinate indices) of the ``integrals`` it holds."""
    return np.flatnonzero(np.isin(block, integrals))


def block_eigenvalues(mass, damping, stiffness, blocks, split=False, integrals=()):
    """All eigenvalues, block by block (no vectors), shape (..., 2n - k); a list per block with
    ``split``."""
    out = [
        block_eig(
            *(x[..., b[:, None], b] for x in (mass, damping, stiffness)),
            vectors=False,
            integrals=within(b, integrals),
        )
        for b in blocks
    ]
    return out if split else np.concatenate(out, axis=-1)


def closest_pair(roots, floor) -> np.ndarray:
    """Smallest distance between two roots of one block in the upper half plane, relative (..., ).

    ``roots`` (..., m) of one coupling block; the distance of two roots is
    taken relative to the larger of their sizes and ``floor`` (..., ) [1/s].
    Two roots coalesce (distance 0) at the ends of every coalescence
    instability, so its local minima over speed point at ranges too narrow
    for a grid to catch.
    """
    lam = np.where(roots.imag >= 0, roots, np.nan)
    a, b = lam[..., :, None], lam[..., None, :]
    size = np.maximum(np.maximum(np.abs(a), np.abs(b)), np.asarray(floor)[..., None, None])
    d = np.abs(a - b) / size
    m = roots.shape[-1]
    d = np.where(np.eye(m, dtype=bool), np.inf, d)
    return np.nan_to_num(np.nanmin(d.reshape(d.shape[:-2] + (-1,)), axis=-1), nan=np.inf)


@dataclass
class Eigensolution:
    """Eigenvalues and eigenvectors of a sweep, one column per branch.

    Attributes
    ----------
    eigenvalue : complex ndarray (n_s, 2n)
    vector : complex ndarray (n_s, n, 2n)
        Displacement part of each eigenvector, unit 2-norm.
    block : int ndarray (2n,)
        Index of the coupling block each column belongs to.
    blocks : list of int ndarray
        Coordinate indices of each coupling block.
    harmonics : complex ndarray (n_s, n, M, 2n), optional
        For periodic motion (Floquet; rotating axes seen from nonrotating ones):
        amplitude of each nonrotating coordinate at frequency
        Im(eigenvalue) + orders[m] Omega. None: ``vector`` at order 0 only.
    orders : int ndarray (M,), optional
    key : complex ndarray (n_s, 2n), optional
        What pairs conjugate roots (Floquet: the multipliers); None: the eigenvalues.
    """

    eigenvalue: np.ndarray
    vector: np.ndarray
    block: np.ndarray
    blocks: list
    harmonics: np.ndarray | None = None
    orders: np.ndarray | None = None
    key: np.ndarray | None = None


def solve(mass, damping, stiffness, blocks, integrals=()) -> Eigensolution:
    """Eigen-solution of M q'' + C q' + K q = 0 at every speed, block by block.

    A long sweep is split into as many parts as there are cores, each solved
    whole (state matrices, LAPACK, vectors) in the pool's threads.
    """
    n_s = mass.shape[0]
    if n_s < 256 or CORES < 2:
        return _solve(mass, damping, stiffness, blocks, integrals)
    parts = map_threads(
        lambda idx: _solve(mass[idx], damping[idx], stiffness[idx], blocks, integrals),
        np.array_split(np.arange(n_s), CORES),
    )
    first = parts[0]
    return Eigensolution(
        np.concatenate([p.eigenvalue for p in parts]),
        np.concatenate([p.vector for p in parts]),
        first.block,
        first.blocks,
    )


def _solve(mass, damping, stiffness, blocks, integrals=()) -> Eigensolution:
    """:func:`solve` in the calling thread."""
    n_s, n = mass.shape[0], mass.shape[-1]
    count = 2 * n - len(integrals)
    values = np.zeros((n_s, count), complex)
    vectors = np.zeros((n_s, n, count), complex)
    block_of = np.zeros(count, int)
    col = 0
    for i, b in enumerate(blocks):
        sub = [x[:, b[:, None], b] for x in (mass, damping, stiffness)]
        w, q = block_eig(*sub, integrals=within(b, integrals))
        m = w.shape[-1]
        values[:, col : col + m] = w
        vectors[:, b[:, None], np.arange(col, col + m)] = q
        block_of[col : col + m] = i
        col += m
    return Eigensolution(values, vectors, block_of, list(blocks))


def _assign_min(cost):
    """Optimal assignment (rows -> columns) for a batch of square cost matrices.

    Where every row's cheapest column is a different one, that choice is
    optimal and is taken for the whole batch at once; only the remaining
    matrices go to the Hungarian method.
    """
    best = np.argmin(cost, axis=-1)
    m = cost.shape[-1]
    distinct = (np.sort(best, axis=-1) == np.arange(m)).all(-1)
    for i in np.flatnonzero(~distinct):
        best[i] = linear_sum_assignment(cost[i])[1]
    return best


def track_order(eigenvalue, vector, block, speeds, periodic=False) -> np.ndarray:
    """Column order at each speed that makes each column one continuous branch.

    Cost of joining root i at one speed to root j at the next: 1 - MAC of the
    vectors plus twice the eigenvalue change relative to its size, within each
    block. The costs of all speed steps are formed at once and matched by
    :func:`_assign_min`; chaining the matches is the only step per speed.
    With ``periodic`` the roots are Floquet exponents, whose imaginary parts
    count only modulo the next speed's Omega: the change is measured to the
    nearest representative.

    Returns
    -------
    int ndarray (n_s, n_e)
        ``eigenvalue[s, order[s]]`` is tracked.
    """
    lam, vec = eigenvalue, vector
    n_s = lam.shape[0]
    floor = 1e-3 * max(float(np.max(np.abs(lam))), 1e-12)
    order = np.tile(np.arange(lam.shape[1]), (n_s, 1))
    if n_s < 2:
        return order
    for blk in np.unique(block):
        cols = np.flatnonzero(block == blk)
        rows = np.flatnonzero(np.abs(vec[:, :, cols]).sum((0, 2)) > 0)
        v = vec[:, rows[:, None], cols]  # (n_s, r, m)
        mac = np.abs(np.einsum("sri,srj->sij", v[:-1].conj(), v[1:])) ** 2
        lb = lam[:, cols]
        change = lb[:-1, :, None] - lb[1:, None, :]
        if periodic:
            omega = np.maximum(np.asarray(speeds, float)[1:, None, None], 1e-300)
            shift = np.rint(change.imag / omega) * omega
            change = change - 1j * np.where(np.asarray(speeds)[1:, None, None] > 0, shift, 0)
        dist = np.abs(change) / (np.abs(lb[:-1, :, None]) + floor)
        step = _assign_min(1.0 - mac + 2.0 * dist)  # (n_s-1, m): root i at s -> step[s, i] at s+1
        chain = np.empty((n_s, len(cols)), int)
        chain[0] = np.arange(len(cols))
        for k in range(1, n_s):
            chain[k] = step[k - 1][chain[k - 1]]
        order[:, cols] = cols[chain]
    return order


def track(sol: Eigensolution, speeds) -> Eigensolution:
    """The eigen-solution with its columns ordered into continuous branches (:func:`track_order`)."""
    order = track_order(sol.eigenvalue, sol.vector, sol.block, speeds)
    rows = np.arange(order.shape[0])[:, None]
    harmonics = None
    if sol.harmonics is not None:
        harmonics = np.take_along_axis(sol.harmonics, order[:, None, None, :], axis=3)
    return Eigensolution(
        sol.eigenvalue[rows, order],
        np.take_along_axis(sol.vector, order[:, None, :], axis=2),
        sol.block,
        sol.blocks,
        harmonics,
        sol.orders,
        None if sol.key is None else sol.key[rows, order],
    )
