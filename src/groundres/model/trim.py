"""The hover trim of a rotor in air, at every speed of a sweep at once.

At each rotor speed the body is at rest, every blade holds still in the hub's
axes at its coning and trim lag angles, and the inflow is uniform, from
momentum theory (a rotor without flap has its flap hinge held at zero coning):
the rotor's thrust T = rho pi R^2 (Omega R)^2 C_T with
C_T = 2 lambda abs(lambda) (lambda the inflow ratio, positive down through the
disk). The unknowns (each blade's coning and trim lag, and lambda) solve the
blades' flap and lag equations and the momentum balance together, by
Newton's method batched over the speeds, with the derivatives derived with
the loads (:mod:`groundres.symbolic.aero`). Nothing divides by lambda, so a
rotor at zero thrust (lambda = 0) trims like any other.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, fields, replace

import numpy as np

from ..errors import ModelRangeError
from ..symbolic.codegen import BLADE_ARGUMENTS, SPAN_ARGUMENTS, air_coefficients, air_values
from .speedtable import SpeedTable

#: Most Newton steps; the trim converges in a handful (quadratically).
MAX_STEPS = 60
#: A step below this [rad, -] (relative to 1 + the largest unknown) is the last: Newton's
#: method converges quadratically, so the step after it would be of its square (1e-16, round-off),
#: and the loads at the trim are those of the last evaluation moved by the step along their
#: derivatives (to its square, too).
LAST_STEP = 1e-8
#: Speeds trimmed first, from zero, where many are asked with no guess: the rest start from them.
COARSE = 24
#: Largest Newton step in an angle [rad] and in lambda: keeps the first steps sane.
MAX_STEP = 0.2


@dataclass(frozen=True)
class Trim:
    """A rotor's hover trim over a sweep (SI).

    Attributes
    ----------
    rotor_speed : ndarray (n_s,)
        [rad/s].
    inflow_ratio : ndarray (n_s,)
        lambda = v / (Omega R) [-], positive down through the disk.
    coning, trim_lag : ndarray (n_s, N)
        Each blade's flap and lag angle at the trim [rad] (lag against the rotation).
    thrust, torque : ndarray (n_s,)
        The rotor's thrust along the shaft [N] and the torque it asks of the shaft [N m].
    thrust_coefficient : ndarray (n_s,)
        C_T = T / (rho pi R^2 (Omega R)^2) = 2 lambda abs(lambda) [-].
    solidity : float
        sigma = N c / (pi R) [-].
    """

    rotor_speed: np.ndarray
    inflow_ratio: np.ndarray
    coning: np.ndarray
    trim_lag: np.ndarray
    thrust: np.ndarray
    torque: np.ndarray
    thrust_coefficient: np.ndarray
    solidity: float

    @property
    def loading(self) -> np.ndarray:
        """Blade loading C_T / sigma [-]."""
        return self.thrust_coefficient / self.solidity

    def take(self, rows) -> Trim:
        """The trims of some speeds (``rows``: indices into this sweep)."""
        return Trim(*(getattr(self, f)[rows] for f in _PER_SPEED), self.solidity)

    def at(self, speeds) -> Trim:
        """The first speed's trim held at every one of ``speeds`` (its thrust and torque too)."""
        held = self.take(np.zeros(np.size(speeds), int))
        return replace(held, rotor_speed=np.asarray(speeds, dtype=float).reshape(-1))


#: The fields of a Trim that run over the speeds.
_PER_SPEED = ("rotor_speed", "inflow_ratio", "coning", "trim_lag", "thrust", "torque", "thrust_coefficient")


class TrimTable:
    """The trims a system has found, speed by speed, to answer later speeds from
    (:class:`groundres.model.speedtable.SpeedTable`): each speed is trimmed once, and a new
    one starts Newton's method from the trims found nearest it, which it then needs few
    steps to polish."""

    def __init__(self, rotor, body, unit_kg: float):
        solidity = rotor.aero.solidity(rotor.n_blades)

        def found(speeds, table):
            guess = None if table.speeds is None else Trim(*table.values, solidity)
            trim = solve_trim(rotor, body, speeds, unit_kg, guess=guess)
            return (getattr(trim, f) for f in _PER_SPEED)

        self.table, self.solidity = SpeedTable(found), solidity

    def __call__(self, speeds) -> Trim:
        return Trim(*self.table(speeds), self.solidity)


def aero_arguments(aero) -> dict:
    """The aerodynamic arguments of the generated functions (radians, the case's mass unit): every
    number of the Aero."""
    return {f.name: getattr(aero, f.name) for f in fields(aero) if f.name not in ("inflow", "lock_given")}


@functools.lru_cache(maxsize=64)
def coefficients(name: str, blade, hub: tuple, aero) -> np.ndarray:
    """The coefficients (K, ...) of ``name`` ("blade_in_air" or "trim_in_air") for one blade on
    a hub at ``hub`` = (hub_height, hub_x, hub_y) [m] in ``aero`` (kept: a sweep, its scans
    and searches evaluate the same blade at thousands of speeds, each a product with these)."""
    fixed = {k: getattr(blade, k) for k in BLADE_ARGUMENTS if hasattr(blade, k)}
    fixed.update(dict(zip(("hub_height", "hub_x", "hub_y"), hub)))
    return air_coefficients(name, **fixed, **aero_arguments(aero), **moments(blade, aero))


def hub_of(body) -> tuple:
    """(hub_height, hub_x, hub_y) [m] of a body."""
    return (body.hub_height, body.hub_x, body.hub_y)


def moments(blade, aero) -> dict:
    """The span's moments int rho^k d rho about a blade's hinge (rho from root_cutout - e to
    tip_radius - e) [m^(k+1)], by their argument names (SPAN_ARGUMENTS)."""
    low, high = aero.root_cutout - blade.hinge_offset, aero.tip_radius - blade.hinge_offset
    return {name: (high ** (k + 1) - low ** (k + 1)) / (k + 1) for k, name in enumerate(SPAN_ARGUMENTS)}


def solve_trim(rotor, body, speeds, unit_kg: float = 1.0, guess: Trim | None = None) -> Trim:
    """The hover trim of ``rotor`` (on ``body``, which stays at rest) at ``speeds`` [rad/s].

    ``rotor`` and ``body`` are in a mass unit of ``unit_kg`` kg
    (:class:`groundres.model.units.MassUnit`); the thrust and torque returned are SI.
    Newton's method starts from zero, or from ``guess`` (trims found at other speeds, sorted)
    interpolated to each speed (:func:`_interpolated`: a new speed among many found takes a
    single evaluation of the loads).

    Raises
    ------
    ModelRangeError
        Where no trim is found (naming the speed): a blade with nothing to hold
        its drag (no hinge offset, no lag spring), or loads beyond the model.
    """
    aero = rotor.aero
    speeds = np.asarray(speeds, dtype=float)
    n_s, n = speeds.size, rotor.n_blades
    if guess is None and n_s > 2 * COARSE:  # (a few from zero, the rest from them: fewer steps)
        first = np.unique(np.quantile(speeds, np.linspace(0, 1, COARSE)))
        guess = solve_trim(rotor, body, first, unit_kg)
    # Distinct blades trim on their own; alike ones share one trim.
    kinds = list(dict.fromkeys(rotor.blades))
    which = [kinds.index(b) for b in rotor.blades]
    count = np.bincount(which, minlength=len(kinds)).astype(float)
    per_kind = [coefficients("trim_in_air", b, hub_of(body), aero) for b in kinds]

    def trim_loads(w, j, lam_j, beta_j, zeta_j):  # (4, 4, m)
        return air_values("trim_in_air", per_kind[j], w, lam_j, beta_j, zeta_j)

    k = len(kinds)
    beta, zeta, lam = np.zeros((n_s, k)), np.zeros((n_s, k)), np.zeros(n_s)
    if guess is not None and len(guess.rotor_speed):
        first = [which.index(j) for j in range(k)]  # (a blade of each kind)
        known = np.column_stack([guess.inflow_ratio, guess.coning[:, first], guess.trim_lag[:, first]])
        found = _interpolated(speeds, guess.rotor_speed, known)
        lam, beta, zeta = found[:, 0].copy(), found[:, 1 : 1 + k].copy(), found[:, 1 + k :].copy()
    spinning = speeds > 0
    area = math.pi * aero.tip_radius**2
    momentum = aero.air_density * area * (speeds * aero.tip_radius) ** 2  # T = momentum * C_T
    live = spinning & (aero.air_density > 0)
    beta[~live], zeta[~live], lam[~live] = 0.0, 0.0, 0.0  # (no load: the blades at rest, no inflow)
    active = np.flatnonzero(live)
    thrust_at, torque_at = np.zeros(n_s), np.zeros(n_s)
    for _ in range(MAX_STEPS):
        if active.size == 0:
            break
        w = speeds[active]
        loads = [trim_loads(w, j, lam[active], beta[active, j], zeta[active, j]) for j in range(k)]
        m = active.size
        size = 2 * k + 1
        residual = np.zeros((m, size))
        jacobian = np.zeros((m, size, size))
        # the rotor's thrust and torque, and their derivatives in the unknowns
        rotor_loads = np.zeros((2, m, size + 1))
        for j, value in enumerate(loads):
            for row in range(2):
                residual[:, 2 * j + row] = value[row, 0]
                jacobian[:, 2 * j + row, 2 * j] = value[row, 1]
                jacobian[:, 2 * j + row, 2 * j + 1] = value[row, 2]
                jacobian[:, 2 * j + row, -1] = value[row, 3]
            if not rotor.flap:  # the flap hinge held at zero: no coning
                residual[:, 2 * j] = beta[active, j]
                jacobian[:, 2 * j, :] = 0.0
                jacobian[:, 2 * j, 2 * j] = 1.0
            for r, row in enumerate((2, 3)):
                rotor_loads[r, :, 0] += count[j] * value[row, 0]
                rotor_loads[r, :, 1 + 2 * j] += count[j] * value[row, 1]
                rotor_loads[r, :, 2 + 2 * j] += count[j] * value[row, 2]
                rotor_loads[r, :, -1] += count[j] * value[row, 3]
        # momentum theory: the thrust is momentum * 2 lambda abs(lambda)
        l_now = lam[active]
        residual[:, -1] = rotor_loads[0, :, 0] - momentum[active] * 2 * l_now * np.abs(l_now)
        jacobian[:, -1] = rotor_loads[0, :, 1:]
        jacobian[:, -1, -1] -= momentum[active] * 4 * np.abs(l_now)
        with np.errstate(all="ignore"):
            try:
                step = np.linalg.solve(jacobian, -residual[..., None])[..., 0]
            except np.linalg.LinAlgError:
                step = np.full_like(residual, np.nan)
        bad = ~np.isfinite(step).all(-1)
        if bad.any():
            _no_trim(speeds[active[bad][0]], rotor)
        biggest = np.abs(step).max(-1)
        step *= np.minimum(1.0, MAX_STEP / np.maximum(biggest, 1e-300))[:, None]
        beta[active] += step[:, 0:-1:2]
        zeta[active] += step[:, 1:-1:2]
        lam[active] += step[:, -1]
        # (the loads at the trim: the last evaluation's moved along the step, to its square)
        thrust_at[active], torque_at[active] = rotor_loads[:, :, 0] + np.einsum(
            "rmi,mi->rm", rotor_loads[:, :, 1:], step
        )
        scale = 1 + np.abs(np.concatenate([beta[active], zeta[active], lam[active, None]], axis=1)).max(-1)
        active = active[biggest > LAST_STEP * scale]
    else:
        _no_trim(speeds[active[0]], rotor)
    beyond = np.flatnonzero(((np.abs(beta) > math.pi / 2) | (np.abs(zeta) > math.pi / 2)).any(1))
    if len(beyond):
        _no_trim(speeds[beyond[0]], rotor)
    return Trim(  # (thrust and torque zero where the rotor stands still or has no air)
        rotor_speed=speeds,
        inflow_ratio=lam,
        coning=beta[:, which],
        trim_lag=zeta[:, which],
        thrust=thrust_at * unit_kg,
        torque=torque_at * unit_kg,
        thrust_coefficient=2 * lam * np.abs(lam),
        solidity=aero.solidity(n),
    )


def _interpolated(speeds, known, values) -> np.ndarray:
    """``values`` (n_known, c) at ``known`` speeds (sorted) interpolated to ``speeds``, (n_s, c),
    through the three nearest (a parabola: its error, of the third power of their spacing,
    leaves Newton's method one step); linear with two, the one value with one; outside them,
    the nearest value."""

    def linear():
        return np.stack([np.interp(speeds, known, v) for v in values.T], axis=1)

    if len(known) < 3:
        return linear()
    at = np.clip(np.searchsorted(known, speeds) - 1, 0, len(known) - 3)
    x0, x1, x2 = (known[at + i][:, None] for i in range(3))
    y0, y1, y2 = (values[at + i] for i in range(3))
    w = speeds[:, None]
    with np.errstate(divide="ignore", invalid="ignore"):
        d01 = (y1 - y0) / (x1 - x0)
        d12 = (y2 - y1) / (x2 - x1)
        out = y0 + (w - x0) * (d01 + (w - x1) * (d12 - d01) / (x2 - x0))
    inside = np.isfinite(out).all(1) & (speeds >= known[0]) & (speeds <= known[-1])
    return out if inside.all() else np.where(inside[:, None], out, linear())


def _no_trim(speed: float, rotor) -> None:
    nothing_holds = any(b.hinge_offset == 0 and b.lag_stiffness == 0 for b in rotor.blades)
    why = (
        "a blade without hinge offset and lag spring has nothing to hold its drag"
        if nothing_holds
        else "the blades find no equilibrium within +-90 deg of flap and lag"
    )
    raise ModelRangeError(f"[aero]: no hover trim at {speed:.6g} rad/s: {why}")
