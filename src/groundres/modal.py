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
* :func:`modes` labels branches physically from their eigenvector content and
  gathers each conjugate pair into one mode.
"""

from __future__ import annotations

import os
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import numpy as np
from scipy.optimize import linear_sum_assignment
from scipy.sparse.csgraph import connected_components

from .mbc import Coordinate

_PAIRS = {("x", "y"): "whirl", ("pitch", "roll"): "tilt"}


def state_matrix(mass, damping, stiffness):
    """First-order form x' = A x with x = [q, q'], stacked over leading axes."""
    n = mass.shape[-1]
    rhs = np.linalg.solve(mass, np.concatenate([stiffness, damping], axis=-1))
    a = np.zeros(mass.shape[:-2] + (2 * n, 2 * n))
    a[..., :n, n:] = np.eye(n)
    a[..., n:, :] = -rhs
    return a


def _normalised(mass, damping, stiffness):
    """Matrices scaled so that entries of every row/column are comparable."""
    d = np.sqrt(np.abs(np.diagonal(mass, axis1=-2, axis2=-1)))
    scale = d[..., :, None] * d[..., None, :]
    w = np.sqrt(np.maximum(np.abs(np.diagonal(stiffness, axis1=-2, axis2=-1)) / d**2, 0).max(-1))
    w = np.maximum(w, 1e-300)[..., None, None]
    return np.abs(mass) / scale + np.abs(damping) / (scale * w) + np.abs(stiffness) / (scale * w**2)


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


_POOL = None


def _batched(fn, a):
    """Apply a batched LAPACK call over the leading axis, split across cores.

    NumPy's linear algebra releases the GIL, so threads share a large batch.
    """
    global _POOL
    cores = min(os.cpu_count() or 1, 4)
    if a.ndim < 3 or a.shape[0] < 256 or cores < 2:
        return fn(a)
    if _POOL is None:
        _POOL = ThreadPoolExecutor(cores)
    parts = list(_POOL.map(fn, np.array_split(a, cores)))
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


def block_eig(m, c, k, vectors=True):
    """Eigenvalues (and displacement eigenvectors) of one block at every speed.

    One coordinate: the roots of m s^2 + c s + k. Two coordinates forming a
    whirl-symmetric pair (every pure-blade cyclic pair of identical blades):
    with u = q_c + i q_s the pair is one complex equation, solved in closed
    form; its roots are the forward (eigenvector [1, -i]) and the conjugate
    equation's the backward whirls ([1, i]). Anything else: batched LAPACK.

    Returns eigenvalues (..., 2n) and, if asked, vectors (..., n, 2n).
    """
    n = m.shape[-1]
    if n == 1:
        s1, s2 = _quadratic_roots(m[..., 0, 0] + 0j, c[..., 0, 0] + 0j, k[..., 0, 0] + 0j)
        w = np.stack([s1, s2], -1)
        return (w, np.ones(w.shape[:-1] + (1, 2), complex)) if vectors else w
    if n == 2 and _whirl_symmetric(m, c, k):
        coeff = [x[..., 0, 0] - 1j * x[..., 0, 1] for x in (m, c, k)]
        s1, s2 = _quadratic_roots(*coeff)
        w = np.stack([s1, s2, s1.conj(), s2.conj()], -1)
        if not vectors:
            return w
        v = np.array([[1, 1, 1, 1], [-1j, -1j, 1j, 1j]]) / np.sqrt(2)
        return w, np.broadcast_to(v, w.shape[:-1] + (2, 4)).copy()
    a = state_matrix(m, c, k)
    if not vectors:
        return _batched(np.linalg.eigvals, a)
    w, v = _batched(np.linalg.eig, a)
    q = v[..., :n, :]
    return w, q / np.linalg.norm(q, axis=-2, keepdims=True)


def block_eigenvalues(mass, damping, stiffness, blocks):
    """All eigenvalues, block by block (no vectors), shape (..., 2n)."""
    out = [
        block_eig(*(x[..., b[:, None], b] for x in (mass, damping, stiffness)), vectors=False) for b in blocks
    ]
    return np.concatenate(out, axis=-1)


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
    """

    eigenvalue: np.ndarray
    vector: np.ndarray
    block: np.ndarray
    blocks: list
    harmonics: np.ndarray | None = None
    orders: np.ndarray | None = None


def solve(mass, damping, stiffness, blocks) -> Eigensolution:
    """Eigen-solution of M q'' + C q' + K q = 0 at every speed, block by block."""
    n_s, n = mass.shape[0], mass.shape[-1]
    values = np.zeros((n_s, 2 * n), complex)
    vectors = np.zeros((n_s, n, 2 * n), complex)
    block_of = np.zeros(2 * n, int)
    col = 0
    for i, b in enumerate(blocks):
        sub = [x[:, b[:, None], b] for x in (mass, damping, stiffness)]
        w, q = block_eig(*sub)
        m = 2 * len(b)
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


def track_order(eigenvalue, vector, block, speeds) -> np.ndarray:
    """Column order at each speed that makes each column one continuous branch.

    Cost of joining root i at one speed to root j at the next: 1 - MAC of the
    vectors plus twice the eigenvalue change relative to its size, within each
    block. The costs of all speed steps are formed at once and matched by
    :func:`_assign_min`; chaining the matches is the only step per speed.

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
        dist = np.abs(lb[:-1, :, None] - lb[1:, None, :]) / (np.abs(lb[:-1, :, None]) + floor)
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
    )


# -- physical content and labels ------------------------------------------------


def _label_groups(coords: list[Coordinate], isotropic_pairs):
    """Units of content: (label(s), coordinate indices, kind, harmonic)."""
    index = {(c.kind, c.name): i for i, c in enumerate(coords)}
    groups, used = [], set()
    for (a, b), word in _PAIRS.items():
        if ("body", a) in index and ("body", b) in index and (a, b) in isotropic_pairs:
            ia, ib = index[("body", a)], index[("body", b)]
            groups.append(((f"body forward {word}", f"body backward {word}"), (ia, ib), "whirl", 0))
            used |= {ia, ib}
    for i, c in enumerate(coords):
        if i in used:
            continue
        if c.kind == "body":
            groups.append(((f"body {c.name}",), (i,), "single", 0))
        elif c.name == "0":
            groups.append((("collective lag" if c.kind == "lag" else "coning",), (i,), "single", 0))
        elif c.name == "d":
            groups.append(((f"differential {c.kind}",), (i,), "single", c.harmonic))
        elif c.name.endswith("c"):
            j = index[(c.kind, c.name[:-1] + "s")]
            n = c.harmonic
            suffix = "" if n == 1 else f" {n}"
            groups.append(
                ((f"regressive {c.kind}{suffix}", f"progressive {c.kind}{suffix}"), (i, j), "cyclic", n)
            )
    return groups


def content(coords, weights, eigenvalue, vector, speeds, isotropic_pairs=()):
    """Energy of each eigenpair in each physical label, and by rotating-frame shift.

    Parameters
    ----------
    coords : list of Coordinate
        Nonrotating coordinates (body, multiblade).
    weights : ndarray (n_s, n)
        Diagonal of the mass matrix: kinetic weight of each coordinate.
    eigenvalue : ndarray (n_s, 2n); vector : ndarray (n_s, n, 2n)
    speeds : ndarray (n_s,)
    isotropic_pairs : iterable of (str, str)
        Body pairs, ("x", "y") and/or ("pitch", "roll"), that are isotropic and
        so move in whirls rather than along an axis.

    Returns
    -------
    labels : list of str
    label_coords : list of tuple of int
        Coordinates each label is made of.
    energy : ndarray (n_s, 2n, n_labels)
        Weighted squared amplitude of each eigenpair in each label.
    shift_energy : ndarray (n_s, 2n, 2 h + 1)
        Energy by the multiple m of Omega (m = -h..h) that turns the
        nonrotating frequency into the rotating-frame one, |omega + m Omega|.
    """
    groups = _label_groups(coords, isotropic_pairs)
    labels = [name for g in groups for name in g[0]]
    label_coords = [g[1] for g in groups for _ in g[0]]
    n_s, _, n_e = vector.shape
    h = max([g[3] for g in groups] + [1])
    energy = np.zeros((n_s, n_e, len(labels)))
    shift = np.zeros((n_s, n_e, 2 * h + 1))
    omega = eigenvalue.imag
    speed = speeds[:, None]
    col = 0
    for _, idx, kind, n in groups:
        amp = vector[:, idx, :]
        w = weights[:, idx[0]][:, None]
        if kind == "single":
            e = w * np.abs(amp[:, 0]) ** 2
            energy[..., col] += e
            if coords[idx[0]].kind == "body":  # planar: half forward, half backward whirl
                shift[..., h - 1] += e / 2
                shift[..., h + 1] += e / 2
            else:
                shift[..., h] += e
            col += 1
            continue
        fwd = 2 * w * np.abs((amp[:, 0] + 1j * amp[:, 1]) / 2) ** 2  # whirls at +omega
        bwd = 2 * w * np.abs((amp[:, 0] - 1j * amp[:, 1]) / 2) ** 2  # whirls at -omega
        if kind == "whirl":
            energy[..., col] += np.where(omega >= 0, fwd, bwd)
            energy[..., col + 1] += np.where(omega >= 0, bwd, fwd)
            n = 1
        else:
            energy[..., col] += np.where(omega < n * speed, fwd, 0) + np.where(-omega < n * speed, bwd, 0)
            energy[..., col + 1] += np.where(omega >= n * speed, fwd, 0) + np.where(
                -omega >= n * speed, bwd, 0
            )
        # forward part: rotating frequency omega - n Omega; backward: -(omega + n Omega)
        shift[..., h - n] += fwd
        shift[..., h + n] += bwd
        col += 2
    return labels, label_coords, energy, shift


@dataclass
class Modes:
    """Labelled modes over a sweep: one column per mode.

    A mode is a conjugate pair of roots (or two real roots where it is
    overdamped). At each speed every mode takes the label its eigenvector
    content says (optimal assignment, with a preference for the label the same
    branch had at the previous speed so that mixed modes keep their name), so
    labels follow the physics through crossings and veerings.

    Attributes
    ----------
    labels : list of str
    eigenvalue : complex ndarray (n_s, n_m)
        Representative root: the one with Im >= 0 (two real roots: the larger).
    real_part : ndarray (n_s, n_m)
        Largest real part of the mode's two roots [1/s].
    frequency_nonrotating, frequency_rotating : ndarray (n_s, n_m)
        Frequency [rad/s] seen from nonrotating and rotating axes.
    shape : complex ndarray (n_s, n, n_m)
        Mode shape seen from nonrotating axes: amplitude of each nonrotating
        (body, multiblade) coordinate at the mode's identified frequency.
    energy : ndarray (n_s, n_m, n_m)
        Fraction of the mode's weighted squared amplitude in each label.
    branch : int ndarray (n_s, n_m)
        Tracked branch (column of the eigen-solution) of the representative
        root: where it changes, the label moved to another branch (a veering).
    participation : ndarray (n_s, n_m, M)
        Share of each harmonic ``orders`` in the mode's motion seen from
        nonrotating axes (frequency offset orders * Omega); one order (0) for
        time-invariant multiblade analysis.
    orders : int ndarray (M,)
    harmonics : complex ndarray (n_s, n, M', n_m)
        The whole periodic shape: amplitude of each nonrotating coordinate at
        frequency Im(eigenvalue) + (harmonic_orders - identified_order) * Omega.
    harmonic_orders : int ndarray (M',)
    identified_order : int ndarray (n_s, n_m)
        The harmonic the nonrotating frequency was identified from.
    """

    labels: list
    eigenvalue: np.ndarray
    real_part: np.ndarray
    frequency_nonrotating: np.ndarray
    frequency_rotating: np.ndarray
    shape: np.ndarray
    energy: np.ndarray
    branch: np.ndarray
    participation: np.ndarray
    orders: np.ndarray
    harmonics: np.ndarray
    harmonic_orders: np.ndarray
    identified_order: np.ndarray

    @property
    def damping_ratio(self) -> np.ndarray:
        """-Re(lambda)/|lambda| of the least damped root of each mode [-]."""
        lam = self.eigenvalue
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(np.abs(lam) > 0, -lam.real / np.abs(lam), np.nan)


def _pair_roots(lam, frac):
    """Group the roots of one block at one speed into modes (pairs of columns).

    Roots above the real axis pair with the nearest conjugate below it; the
    rest (real roots, and any left unmatched) pair by content. Returns a list
    of (representative column, other column), the representative being the
    root with Im >= 0, or the larger real part.
    """
    scale = max(np.abs(lam).max(), 1e-300)
    upper = np.flatnonzero(lam.imag > 1e-9 * scale)
    lower = np.flatnonzero(lam.imag < -1e-9 * scale)
    rest = list(np.flatnonzero(np.abs(lam.imag) <= 1e-9 * scale))
    pairs = []
    if len(upper) and len(lower):
        cost = np.abs(lam[upper][:, None] - lam[lower][None, :].conj())
        r, c = linear_sum_assignment(cost)
        pairs += [(upper[i], lower[j]) for i, j in zip(r, c)]
        rest += [upper[i] for i in set(range(len(upper))) - set(r)]
        rest += [lower[j] for j in set(range(len(lower))) - set(c)]
    else:
        rest += list(upper) + list(lower)
    order = sorted(rest, key=lambda j: (int(np.argmax(frac[j])), -lam[j].real))
    for i in range(0, len(order) - 1, 2):
        a, b = order[i], order[i + 1]
        key = lambda j: (lam[j].imag >= 0, lam[j].real)  # noqa: E731
        pairs.append((a, b) if key(a) >= key(b) else (b, a))
    return pairs


@dataclass
class Content:
    """Physical content of every root of a sweep.

    Attributes
    ----------
    labels : list of str
    label_coords : list of tuple of int
    fraction : ndarray (n_s, 2n, n_labels)
        Share of each root's weighted squared amplitude in each label.
    eigenvalue : complex ndarray (n_s, 2n)
        Root with its frequency as seen from nonrotating axes: for periodic
        motion, Im(lambda) + m Omega with m the harmonic of largest share
        (Peters, Lieb & Ahaus 2011, "Interpretation of Floquet eigenvalues and
        eigenvectors for periodic systems", JAHS 56, 032001).
    rotating_frequency : ndarray (n_s, 2n)
        Frequency seen from rotating axes [rad/s], chosen the same way.
    participation : ndarray (n_s, 2n, M)
        Share of each harmonic order (``orders``) in the nonrotating frame.
    orders : int ndarray (M,)
    """

    labels: list
    label_coords: list
    fraction: np.ndarray
    eigenvalue: np.ndarray
    rotating_frequency: np.ndarray
    participation: np.ndarray
    orders: np.ndarray


def _sticky_choice(share, tie_break, margin):
    """Index of the largest share at each speed, keeping the previous choice of the
    same column while it is within ``margin`` of the largest.

    share : (n_s, n_e, K); tie_break : (n_s, n_e, K), smaller wins among equal shares.
    """
    top = share.max(-1, keepdims=True)
    near = share >= top - 1e-9 * np.maximum(top, 1e-300)
    best = np.argmin(np.where(near, tie_break, np.inf), axis=-1)  # (n_s, n_e)
    if margin <= 0 or share.shape[0] < 2:
        return best
    choice = best.copy()
    cols = np.arange(share.shape[1])
    for s in range(1, share.shape[0]):
        prev = choice[s - 1]
        keep = share[s, cols, prev] >= share[s, cols, best[s]] - margin
        choice[s] = np.where(keep, prev, best[s])
    return choice


def identify(sol: Eigensolution, coords, weights, speeds, isotropic_pairs=(), margin=0.0) -> Content:
    """Labels, nonrotating and rotating frequencies of every root from its harmonics.

    The frequency seen from a frame is Im(lambda) + m Omega with m the harmonic
    of largest share in that frame. With ``margin`` > 0 (tracked branches of a
    periodic system) a branch keeps its harmonic while it stays within
    ``margin`` of the largest share, so that frequencies stay continuous.
    """
    harmonics = sol.harmonics if sol.harmonics is not None else sol.vector[:, :, None, :]
    orders = sol.orders if sol.orders is not None else np.array([0])
    n_s, _, n_m, n_e = harmonics.shape
    energy = by_order = None
    rotating = {}
    for m, order in enumerate(orders):
        lam_m = sol.eigenvalue + 1j * order * speeds[:, None]
        labels, label_coords, e, sh = content(
            coords, weights, lam_m, harmonics[:, :, m, :], speeds, isotropic_pairs
        )
        if energy is None:
            energy = np.zeros_like(e)
            by_order = np.zeros((n_s, n_e, n_m))
        energy += e
        by_order[..., m] = e.sum(-1)
        h = (sh.shape[-1] - 1) // 2
        for k in range(-h, h + 1):
            rotating[order + k] = rotating.get(order + k, 0) + sh[..., h + k]

    def shares(x):
        total = x.sum(-1, keepdims=True)
        return x / np.where(total > 0, total, 1.0)

    fraction = shares(energy)
    share = shares(by_order)
    omega = sol.eigenvalue.imag[..., None]
    nr_freq = np.abs(omega + orders * speeds[:, None, None])
    best = orders[_sticky_choice(share, nr_freq, margin)]
    eigenvalue = sol.eigenvalue + 1j * best * speeds[:, None]
    shifts = np.array(sorted(rotating))
    rot_share = shares(np.stack([rotating[k] for k in shifts], -1))  # (n_s, n_e, K)
    rot_freq = np.abs(omega + shifts * speeds[:, None, None])
    pick = _sticky_choice(rot_share, rot_freq, margin)
    f_rot = np.take_along_axis(rot_freq, pick[..., None], -1)[..., 0]
    return Content(labels, label_coords, fraction, eigenvalue, f_rot, share, orders)


def modes(sol: Eigensolution, found: Content, speeds, stickiness=0.25) -> Modes:
    """Gather tracked roots into modes and label them by their content.

    Parameters
    ----------
    sol : Eigensolution
        Tracked eigen-solution (see :func:`track`).
    found : Content
        Its content (see :func:`identify`).
    speeds : ndarray (n_s,)
    stickiness : float
        Bonus, in content fraction, for keeping the label a branch had at the
        previous speed; a label moves to another branch only when that branch's
        content in it is larger by more than this.
    """
    labels, label_coords, frac = found.labels, found.label_coords, found.fraction
    roots = found.eigenvalue
    n_s = roots.shape[0]
    n_l = len(labels)
    rep = np.zeros((n_s, n_l), int)
    other = np.zeros((n_s, n_l), int)
    for blk, members in enumerate(sol.blocks):
        cols = np.flatnonzero(sol.block == blk)
        mine = np.array([i for i, lc in enumerate(label_coords) if set(lc) <= set(members.tolist())])
        if 2 * len(mine) != len(cols):
            raise RuntimeError(f"block of {len(members)} coordinates has labels {[labels[i] for i in mine]}")
        lam_b = roots[:, cols]
        frac_b = frac[:, cols][:, :, mine]  # (n_s, 2 nl, nl)
        scale = np.maximum(np.abs(lam_b).max(-1, keepdims=True), 1e-300)
        upper = lam_b.imag > 1e-9 * scale
        plain = upper.sum(-1) == len(mine)  # no real roots at this speed
        # conjugate partner of each root
        partner = np.argmin(np.abs(lam_b[:, :, None] - lam_b[:, None, :].conj()), axis=-1)
        reps = np.zeros((n_s, len(mine)), int)
        others = np.zeros((n_s, len(mine)), int)
        up_idx = np.argsort(~upper, axis=-1, kind="stable")[:, : len(mine)]
        reps[plain] = up_idx[plain]
        others[plain] = np.take_along_axis(partner, up_idx, -1)[plain]
        for k in np.flatnonzero(~plain):
            pairs = _pair_roots(lam_b[k], frac_b[k])
            reps[k], others[k] = zip(*pairs)
        rows_ = np.arange(n_s)[:, None]
        score = (frac_b[rows_, reps] + frac_b[rows_, others]) / 2  # (n_s, modes, labels)
        top2 = np.sort(score, axis=-1)[..., -2:] if len(mine) > 1 else np.concatenate([score, score * 0], -1)
        choice = np.argmax(score, axis=-1)
        clear = (np.sort(choice, -1) == np.arange(len(mine))).all(-1) & (
            (top2[..., -1] - top2[..., 0]).min(-1) > stickiness
        )
        if len(mine) == 1:
            clear[:] = True
        label_of_col = np.full(len(cols), -1)
        for k in range(n_s):
            if not clear[k]:
                sc = score[k].copy()
                for i in range(len(mine)):
                    for col in (reps[k, i], others[k, i]):
                        if label_of_col[col] >= 0:
                            sc[i, label_of_col[col]] += stickiness
                choice[k] = linear_sum_assignment(-sc)[1]
            label_of_col[reps[k]] = choice[k]
            label_of_col[others[k]] = choice[k]
        inverse = np.argsort(choice, axis=-1)  # mode index holding each label
        rep[:, mine] = cols[np.take_along_axis(reps, inverse, -1)]
        other[:, mine] = cols[np.take_along_axis(others, inverse, -1)]
    rows = np.arange(n_s)[:, None]
    lam = roots[rows, rep]
    lam_other = roots[rows, other]
    harm = sol.harmonics if sol.harmonics is not None else sol.vector[:, :, None, :]
    orders = sol.orders if sol.orders is not None else np.array([0])
    harm = np.take_along_axis(harm, rep[:, None, None, :], axis=3)  # (n_s, n, M, n_m)
    # the shape seen from nonrotating axes: the harmonic the frequency was identified from
    order = np.rint((lam.imag - sol.eigenvalue[rows, rep].imag) / np.maximum(speeds[:, None], 1e-300))
    pos = np.clip(np.searchsorted(orders, order.astype(int)), 0, len(orders) - 1)  # (n_s, n_m)
    shape = np.take_along_axis(harm, pos[:, None, None, :], axis=2)[:, :, 0, :]
    return Modes(
        labels=labels,
        eigenvalue=lam,
        real_part=np.maximum(lam.real, lam_other.real),
        frequency_nonrotating=np.abs(lam.imag),
        frequency_rotating=found.rotating_frequency[rows, rep],
        shape=shape,
        energy=(frac[rows, rep] + frac[rows, other]) / 2,
        branch=rep,
        participation=found.participation[rows, rep],
        orders=found.orders,
        harmonics=harm,
        harmonic_orders=orders,
        identified_order=order.astype(int),
    )
