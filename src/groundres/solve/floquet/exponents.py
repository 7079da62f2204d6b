"""Periodic systems: Floquet exponents and the harmonics of periodic eigenvectors.

The transition matrix over one period (or the shorter period of a symmetry)
comes from :mod:`groundres.solve.floquet.transition`. Its eigenvalues are the multipliers
rho; the exponents lambda = ln(rho)/T are unique up to multiples of the
period's frequency. The periodic part p(t) = x(t) exp(-lambda t) of each
Floquet solution is sampled over one revolution and written as harmonics in
multiblade coordinates: the motion at Im(lambda) + m Omega seen from
nonrotating axes (Peters, Lieb and Ahaus 2011, "Interpretation of Floquet
eigenvalues and eigenvectors for periodic systems", JAHS 56, 032001), from
which :mod:`groundres.modes.identify` names the root and gives its frequency.

Symmetry (:mod:`groundres.solve.floquet.symmetry`): where advancing the azimuth by
Delta = 2 pi j / N hands each blade's role to blade k + j, only Delta is
integrated; the exponents come from R = G^-1 Phi(Delta) and are unique up to
multiples of (N/j) Omega.

Low rotor speeds. The period grows as 1/Omega, so a well damped mode decays
over it by many decades and the eigenvalues of the product Phi(Delta) lose
the small multipliers to round-off. Where the multipliers of a speed span
more than exp(LIFT_SPREAD) (as seen, or as the frozen system's real parts
foretell: the multipliers themselves cannot show a spread beyond
round-off), the period is cut into K parts and the multipliers come from
the lifted matrix (:mod:`groundres.solve.floquet.lifting`): over one part no mode grows
or decays by more than exp(LIFT_STEP). The samples over a revolution are as many as the
fastest motion needs (twice its frequency over Omega plus the harmonics
kept), so the harmonics do not alias at low speed. At Omega = 0 the
equations have constant coefficients (the rotor stands still, blade 1 at
azimuth 0) and are solved as they are.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...errors import SpeedRangeError
from ...model.system import System
from ..modal import displacements, kept_states, state_matrix
from .air import in_air
from .coefficients import frozen_rates, halves, per_speed, rates_per_radian
from .lifting import lifted_eig
from .symmetry import Symmetry, symmetry
from .tableau import DOP8
from .transition import STEP_SCALE, TOLERANCE, divisor_at_least, integrate, transition
from .vectorised import ordered_product

#: Harmonics returned on each side of a root's dominant one.
HARMONICS = 10
#: Transition tolerance of a scan (:func:`solve` with ``bounds``): one that only
#: looks for where the largest real part peaks, or may be positive, and decides
#: nothing itself (every verdict and every value reported is evaluated again at
#: :data:`TOLERANCE`). Most speeds then take the fewest steps the integration
#: allows, about a third of the steps at TOLERANCE; on the shipped and benchmark
#: cases the largest real part moved by less than 1e-9 1/s.
SCAN_TOLERANCE = 1e-7
#: ln of the multiplier spread beyond which the lifted problem is solved.
LIFT_SPREAD = 16.0
#: ln of the spread allowed over one part of the lifted problem.
LIFT_STEP = 14.0
#: Largest lifted matrix solved [rows].
LIFT_SIZE = 3000


@dataclass
class FloquetSolution:
    """Floquet analysis of a sweep.

    Attributes
    ----------
    exponent : complex ndarray (n_s, 2n)
        Floquet exponents [1/s]. With harmonics: the representative whose
        frequency is that of the root's harmonic of largest kinetic-weighted
        share (the centre of ``harmonics``); without: principal values
        (Im in (-Omega_F/2, Omega_F/2], Omega_F = (N / j) Omega).
    multiplier : complex ndarray (n_s, 2n)
        Eigenvalues of R = G^-1 Phi(Delta) (the multipliers of the reduced period).
    vector : complex ndarray (n_s, 2n, 2n)
        Eigenvectors of R (columns), in y = [q; dq/dpsi].
    harmonics : complex ndarray (n_s, n, 2 H + 1, 2n) or None
        Amplitude of each nonrotating coordinate (body, multiblade) of the
        periodic eigenvector at frequency Im(exponent) + orders Omega.
    orders : int ndarray (2 H + 1,)
    symmetry : Symmetry
    steps : int ndarray (n_s,)
    speeds : ndarray (n_s,)
    lifted : bool ndarray (n_s,)
        Speeds solved through the lifted problem.
    key : complex ndarray (n_s, 2n)
        The multipliers with their moduli compressed (no underflow), for
        telling conjugate pairs: conjugate exponents (modulo the period's
        frequency) have conjugate keys.
    real_lower, real_upper : ndarray (n_s, 2n) or None
        (with ``bounds``) Bounds of each exponent's real part [1/s] given the
        integration's error: ``ln(|rho| -+ kappa ||dPhi||) / T``, with kappa the
        multiplier's condition number and ``||dPhi|| <= 2n e max(1, |Phi|)`` from
        the error estimate e of an entry (first order in dPhi; the estimate
        itself overstates the error, 7 to 5000 times on the embedded
        estimate's calibration cases); -inf and +inf for a lifted speed.

    At Omega = 0 the exponents are the roots of the system at rest, the
    vectors its eigenvectors in [q; dq/dt] and the multipliers exp(lambda T)
    over the reduced period T of the lowest speed that turns (so that branches
    continue into the sweep).
    """

    exponent: np.ndarray
    multiplier: np.ndarray
    vector: np.ndarray
    harmonics: np.ndarray | None
    orders: np.ndarray
    symmetry: Symmetry
    steps: np.ndarray
    speeds: np.ndarray
    lifted: np.ndarray
    key: np.ndarray
    real_lower: np.ndarray | None = None
    real_upper: np.ndarray | None = None


def _pairing_key(lam, dt):
    """exp(lambda dt) with the decay compressed so that it cannot underflow."""
    decay = lam.real * dt[:, None]
    squeeze = np.minimum(1.0, 600.0 / np.maximum(np.abs(decay).max(-1, keepdims=True), 1e-300))
    return np.exp(decay * squeeze + 1j * lam.imag * dt[:, None])


def _group(parts, k):
    """Products over k equal groups of consecutive parts: (k, ...)."""
    per = parts.shape[0] // k
    return ordered_product(np.swapaxes(parts.reshape((k, per) + parts.shape[1:]), 0, 1))


def _full_vectors(parts, starts, z, keep):
    """Periodic eigenvectors at the starts of K parts with the positions of the integrals put
    back, (K, ..., m, mr), from those of the kept states (K, ..., mr, mr)
    (:func:`groundres.solve.modal.kept_states`).

    parts : (K, ..., m, m) transition matrices over the parts (the last one's with the
    symmetry map applied); z : (..., mr) the lifted eigenvalues (K = 1: the multipliers).
    An integral's position moves by its rate and nothing moves by it: over part k it
    gains b_k = parts[k][integral, kept] starts[k], so that z x_(k+1) = x_k + b_k;
    periodic, x_0 = sum_k z^k b_k / (z^K - 1) (zero where z^K = 1: a root at zero).
    """
    k_parts, m = parts.shape[0], parts.shape[-1]
    out = np.zeros(parts.shape[:-1] + starts.shape[-1:], complex)
    out[..., keep, :] = starts
    drop = np.setdiff1d(np.arange(m), keep)
    if not len(drop):
        return out
    gain = parts[..., drop[:, None], keep] @ starts  # (K, ..., k, mr)
    z = z[..., None, :]
    powers = z[None] ** np.arange(k_parts).reshape((-1,) + (1,) * z.ndim)
    denominator = z**k_parts - 1.0
    usable = np.abs(denominator) > 1e-14
    x = np.where(usable, (powers * gain).sum(0) / np.where(usable, denominator, 1.0), 0.0)
    for k in range(k_parts):
        out[k][..., drop, :] = x
        x = (x + gain[k]) / z
    return out


def _periodic_samples(parts, starts, exponent, dt):
    """The periodic part at every part's start, from its values at group starts.

    parts : (B, k, m, m); starts : (K, k, m, m) at the starts of K equal groups
    of parts; exponent : (k, m); dt : (k,) duration of one part [s].
    Returns (B, k, m, m).
    """
    n_parts, n_groups = parts.shape[0], starts.shape[0]
    per = n_parts // n_groups
    decay = np.exp(-exponent * dt[:, None])[:, None, :]  # one part's exp(-lambda dt)
    out = np.empty(parts.shape[:-1] + starts.shape[-1:], complex)
    for gi in range(n_groups):
        y = starts[gi]
        for b in range(gi * per, (gi + 1) * per):
            out[b] = y
            y = (parts[b] @ y) * decay
    return out


def _sampled_displacements(upto, vectors, exponent, dt, n):
    """Displacement rows of the periodic part at every part's start, from the transition
    matrices up to each part's end (one batched product).

    upto : (B, k, m, m) Phi from 0 to the end of each part; vectors : (k, m, r);
    exponent : (k, r); dt : (k,) duration of one part [s]. Returns (B, k, n, r):
    Phi(psi_b)[:n] v exp(-lambda b dt), Phi(psi_0) = I.
    """
    out = np.empty(upto.shape[:2] + (n, vectors.shape[-1]), complex)
    out[0] = vectors[:, :n]
    if len(upto) > 1:  # (per speed, all samples' rows at once; real and imaginary parts apart)
        b, k, m = len(upto) - 1, upto.shape[1], upto.shape[-1]
        rows = np.swapaxes(upto[:-1, :, :n, :], 0, 1).reshape(k, b * n, m)
        for part, values in ((out.real, vectors.real), (out.imag, vectors.imag)):
            part[1:] = np.swapaxes((rows @ values).reshape(k, b, n, -1), 0, 1)
    steps = np.arange(len(upto))[:, None, None]
    out *= np.exp(-exponent[None] * (steps * dt[None, :, None]))[:, :, None, :]
    return out


def _harmonics(system, sym, samples, weights, exponent, speeds, h):
    """Window of harmonics around each root's dominant one.

    samples : (B, k, n, 2n) displacements of the periodic part over the reduced period;
    weights : (k, n) kinetic weights of the multiblade coordinates.
    Returns (exponent shifted to the dominant harmonic (k, 2n), harmonics (k, n, 2h+1, 2n)).
    """
    n = system.size
    step = np.argmax(sym.g, axis=1)  # (g is a permutation: g @ q = q[step])
    parts, order = [], np.arange(n)
    for _ in range(system.n_blades // sym.shift):
        parts.append(samples[..., order, :])
        order = order[step]
    full = np.concatenate(parts, axis=0)  # (K, k, n, 2n) over one revolution
    k_full = len(full)
    coeff = system.multiblade_spectrum(full)  # order o at index o mod K
    energy = np.einsum("okne,kn->oke", np.abs(coeff) ** 2, weights)
    centre = np.argmax(energy, axis=0)  # (k, 2n)
    signed = np.where(centre > k_full // 2, centre - k_full, centre)
    index = (centre[None] + np.arange(-h, h + 1)[:, None, None]) % k_full  # (2h+1, k, 2n)
    window = np.take_along_axis(coeff, index[:, :, None, :], axis=0)  # (2h+1, k, n, 2n)
    return exponent + 1j * signed * speeds[:, None], np.moveaxis(window, 0, 2)


def solve(
    system: System,
    speeds,
    harmonics: int = HARMONICS,
    tolerance=TOLERANCE,
    scale=STEP_SCALE,
    tableau=DOP8,
    lift: bool = True,
    progress=None,
    damping=None,
    sym: Symmetry | None = None,
    compiled: bool | None = None,
    bounds: bool = False,
) -> FloquetSolution:
    """Floquet exponents, multipliers and (if ``harmonics`` > 0) periodic eigenvectors.

    Parameters
    ----------
    system : System
    speeds : ndarray (n_s,)
        Rotor speeds [rad/s], >= 0.
    harmonics : int
        H: harmonics -H..H around each root's dominant one are returned; 0 for
        exponents only.
    tolerance, scale, tableau
        Accuracy of the transition matrices (:func:`groundres.solve.floquet.transition.integrate`).
    lift : bool
        Solve the lifted problem where the multipliers span many decades. Without
        it the largest real parts are still exact, and so (with ``harmonics``) are
        the periodic eigenvectors of those roots, since the largest multipliers of
        a product are resolved whatever the smallest do; but the real parts and
        eigenvectors of roots damped many e-folds more than the largest are not.
    progress : callable, optional
        ``progress(done, total)`` in speeds, called as batches of speeds are done.
    damping : float or ndarray (n_s,) or (n_s, d), optional
        Damping along the system's d damping directions at each speed [in the
        system's units] (:func:`groundres.solve.floquet.coefficients.per_speed`); ``system`` is then
        a split one (:meth:`groundres.model.system.System.split_damping`): one set
        of node matrices serves every damping.
    sym : Symmetry, optional
        The symmetry to use (that of the system with its dampers, where
        ``system`` is a split one, whose blades may look more alike).
    compiled : bool or None
        The compiled kernel, NumPy, or the kernel where it is ready
        (:func:`groundres.solve.floquet.transition.use_kernel`).
    bounds : bool
        Also bound each exponent's real part from the integration's error
        (:attr:`FloquetSolution.real_upper`, ``real_lower``), for a scan at a loose
        ``tolerance`` (:data:`SCAN_TOLERANCE`).
    """
    speeds = np.asarray(speeds, dtype=float)
    if system.rotor.aero is not None and system._frozen is None:
        return in_air(
            solve,
            system,
            speeds,
            damping=damping,
            progress=progress,
            harmonics=harmonics,
            tolerance=tolerance,
            scale=scale,
            tableau=tableau,
            lift=lift,
            sym=sym,
            compiled=compiled,
            bounds=bounds,
        )
    sym = symmetry(system) if sym is None else sym
    damping = per_speed(damping, len(speeds))
    n = system.size
    m = 2 * n
    integrals = system.integrals
    keep = kept_states(n, integrals)
    mr = len(keep)  # (the roots: the integrals' positions are no state, :func:`_full_vectors`)
    n_s = len(speeds)
    g = np.kron(np.eye(2), sym.g)
    g_kept = g[keep[:, None], keep]
    exponent = np.zeros((n_s, mr), complex)
    multiplier = np.zeros((n_s, mr), complex)
    key = np.zeros((n_s, mr), complex)
    vector = np.zeros((n_s, m, mr), complex)
    out_h = np.zeros((n_s, n, 2 * harmonics + 1, mr), complex) if harmonics else None
    steps = np.zeros(n_s, int)
    lifted = np.zeros(n_s, bool)
    lower, upper = (np.zeros((n_s, mr)), np.zeros((n_s, mr))) if bounds else (None, None)
    weights = system.kinetic_weights(speeds) if harmonics else None
    moving = np.flatnonzero(speeds > 0)
    still = np.flatnonzero(speeds <= 0)
    if len(still):
        # the rotor at rest: constant coefficients; multipliers over the lowest
        # moving speed's period, so that branches continue into the sweep
        period = sym.angle / speeds[moving].min() if len(moving) else 1.0
        mass, damp, stiff = system.matrices(speeds[still], 0.0)
        if damping is not None:
            sides = np.array(halves(5 + damping.shape[1], system.direction_halves)[5:], bool)
            directions = system.damping_directions
            damp = damp + np.einsum("sd,dij->sij", damping[still][:, sides], directions[sides])
            stiff = stiff + np.einsum("sd,dij->sij", damping[still][:, ~sides], directions[~sides])
        lam, x = np.linalg.eig(state_matrix(mass, damp, stiff, integrals))
        x = np.concatenate([displacements(x, lam, n, integrals), x[:, mr - n :]], axis=1)
        exponent[still], vector[still], multiplier[still] = lam, x, np.exp(lam * period)
        if bounds:
            lower[still] = upper[still] = lam.real
        key[still] = _pairing_key(lam, np.full(len(still), period))
        if harmonics:
            q = system.to_multiblade(x[None, :, :n, :], np.zeros(1))[0]
            out_h[still, :, harmonics, :] = q
    rate, low, high = np.zeros(n_s), np.zeros(n_s), np.zeros(n_s)
    if len(moving):
        c_moving = None if damping is None else damping[moving]
        if lift or harmonics:
            rate[moving], low[moving], high[moving] = frozen_rates(system, speeds[moving], damping=c_moving)
        else:  # (the real parts' spread only decides lifting: the rates set the first step counts)
            rate[moving] = rates_per_radian(system, speeds[moving], damping=c_moving)
    n_sym = system.n_blades // sym.shift

    def samples(r):
        """Samples of the reduced period the harmonics need (fastest motion r [1/rad])."""
        full = 2 * (np.ceil(r) + harmonics) + 2  # over a revolution
        return np.maximum(-(-full // n_sym), 4).astype(int)

    def blocks_for(count, sel):
        if not harmonics:
            return 1
        return divisor_at_least(count, int(samples(rate[moving[sel]].max())))

    finished = speeds <= 0

    def accept(sel, phi, parts, count, error):
        idx = moving[sel]
        w = speeds[idx]
        dt = sym.angle / w
        rho, vec = np.linalg.eig(g_kept.T @ phi[:, keep[:, None], keep])
        rho, vec = rho.astype(complex), vec.astype(complex)
        if bounds:
            lower[idx], upper[idx] = _real_bounds(rho, vec, phi[:, keep[:, None], keep], error, dt)
        vec = _full_vectors((g.T @ phi)[None], vec[None], rho, keep)[0]
        size = np.log(np.maximum(np.abs(rho), 1e-300))
        lam = size / dt[:, None] + 1j * np.angle(rho) / dt[:, None]
        # decades spanned over the period: seen in the multipliers (which round-off
        # caps) or expected from the frozen system, with a margin
        spread = np.maximum(size.max(-1) - size.min(-1), 1.25 * (high[idx] - low[idx]) * dt + 2.0)
        need = np.flatnonzero(spread > LIFT_SPREAD) if lift else np.array([], int)
        samples = None
        if harmonics:  # (speeds that need the lifted problem are redone below)
            samples = _sampled_displacements(parts, vec, lam, dt / len(parts), n)
        for j in need:
            k_parts = int(np.ceil(spread[j] / LIFT_STEP)) + 1
            while True:
                k_parts = divisor_at_least(count, k_parts)
                if 2 * k_parts * m > LIFT_SIZE or k_parts >= count:
                    raise SpeedRangeError(
                        float(w[j]), f"sees its roots decay over about {spread[j]:.0f} e-folds in one period"
                    )
                n_parts = math.lcm(len(parts), k_parts) if harmonics else k_parts
                c_j = None if damping is None else damping[idx[j] : idx[j] + 1]
                fine = transition(system, w[j : j + 1], sym.angle, count, n_parts, tableau, c_j, compiled)[
                    :, 0
                ]
                groups = _group(fine, k_parts)
                z, at = lifted_eig(groups[:, keep[:, None], keep], g_kept)
                at = _full_vectors(groups, at, z, keep)
                if np.ptp(np.log(np.abs(z))) <= LIFT_STEP:
                    break
                k_parts = 2 * k_parts
            lam[j] = k_parts * np.log(z) / dt[j]  # (not from z^K, which may underflow)
            rho[j], vec[j] = z**k_parts, at[0]
            lifted[idx[j]] = True
            if bounds:
                lower[idx[j]], upper[idx[j]] = -np.inf, np.inf
            if harmonics:
                one = _periodic_samples(fine[:, None], at[:, None], lam[j][None], dt[j : j + 1] / n_parts)
                samples[:, j] = one[:: n_parts // len(parts), 0, :n]  # the batch's sample count
        multiplier[idx], vector[idx], steps[idx] = rho, vec, count
        key[idx] = _pairing_key(lam, dt)
        if harmonics:
            exponent[idx], out_h[idx] = _harmonics(system, sym, samples, weights[idx], lam, w, harmonics)
        else:
            exponent[idx] = lam
        if progress is not None:
            finished[idx] = True  # (a speed may be accepted again with more steps)
            progress(int(finished.sum()), n_s)

    if len(moving):
        w = speeds[moving]
        least = samples(rate[moving]) if harmonics else None
        integrate(
            system,
            w,
            sym.angle,
            tolerance,
            scale,
            tableau,
            blocks_for,
            accept,
            rate[moving],
            least,
            None if damping is None else damping[moving],
            compiled,
            cumulative=bool(harmonics),
        )
    orders = np.arange(-harmonics, harmonics + 1)
    return FloquetSolution(
        exponent, multiplier, vector, out_h, orders, sym, steps, speeds, lifted, key, lower, upper
    )


def _real_bounds(rho, vec, phi, error, dt):
    """Lower and upper bounds of the exponents' real parts [1/s] given the transition matrices' error.

    rho, vec : (k, m), (k, m, m) multipliers and eigenvectors; phi : (k, m, m);
    error : (k,) estimated error of an entry relative to max(1, |phi|); dt (k,).
    A multiplier moves by at most kappa ||dPhi||_2 to first order (kappa =
    |w| |v| / |w^H v|, the left eigenvectors the rows of vec^-1), and
    ||dPhi||_2 <= m max |dPhi_ij|. A defective set of eigenvectors has no
    bounds (-inf, +inf).
    """
    m = phi.shape[-1]
    size = m * error * np.maximum(1.0, np.abs(phi).max((-1, -2)))
    try:
        left = np.linalg.inv(vec)
    except np.linalg.LinAlgError:  # (rare: the speeds one at a time, a singular one unbounded)
        left = np.full_like(vec, np.inf)
        for i in range(len(vec)):
            try:
                left[i] = np.linalg.inv(vec[i])
            except np.linalg.LinAlgError:
                pass
    kappa = np.linalg.norm(vec, axis=-2) * np.linalg.norm(left, axis=-1)
    move = kappa * size[:, None]
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        upper = np.log(np.abs(rho) + move) / dt[:, None]
        lower = np.log(np.maximum(np.abs(rho) - move, 0.0)) / dt[:, None]
    lower[~np.isfinite(move)] = -np.inf
    return np.where(np.isnan(lower), -np.inf, lower), np.where(np.isnan(upper), np.inf, upper)


def monodromy(
    system: System, speeds, tolerance=TOLERANCE, scale=STEP_SCALE, tableau=DOP8, compiled=None
) -> np.ndarray:
    """Full-revolution transition matrix of x = [q; dq/dt], shape (n_s, 2n, 2n).

    Built from the reduced period with the symmetry when there is one;
    ``compiled`` as in :func:`groundres.solve.floquet.transition.integrate`.
    """
    speeds = np.asarray(speeds, dtype=float)
    sym = symmetry(system)
    phi, _ = integrate(system, speeds, sym.angle, tolerance, scale, tableau, compiled=compiled)
    g = np.kron(np.eye(2), sym.g)
    full = np.linalg.matrix_power(g.T @ phi, system.n_blades // sym.shift)
    n = system.size
    # y = [q; dq/dpsi] -> x = [q; dq/dt] = D y with D = diag(1, Omega)
    d = np.concatenate([np.ones((len(speeds), n)), np.repeat(speeds[:, None], n, 1)], 1)
    return d[:, :, None] * full / d[:, None, :]
