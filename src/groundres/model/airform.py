"""The time-invariant forms of a rotor in air, as sums over monomials of the trim state.

In vacuum the multiblade and rotating-axes forms are quadratic in the rotor
speed, so three speeds give them everywhere. In air the trim changes with the
speed, but every blade array is still ``sum_k m_k(state) X_k``: monomials of
the trim state (speed, inflow ratio, each blade's coning and trim lag, their
cosines and sines) times fixed arrays (:func:`groundres.symbolic.codegen.air_values`),
and the dynamic inflow's own terms are a constant and ``abs(lambda) Omega``
times fixed arrays. The transforms are linear in the blade arrays and add
their own Omega and Omega^2, so each form is exactly

    F(Omega) = F_0(Omega) + sum_s v_s(Omega) (A_s + Omega B_s + Omega^2 C_s),

F_0 the body's and the damper rods' part, v_s the value of source s (a
monomial of one blade's trim state) at the speed. :class:`AirForm` finds
A_s, B_s and C_s once per band of speeds (the transform of every source that
touches the system's coordinates at the speeds 0 and +-b, b a power of
:data:`BAND`, so that the round-off of B and C, that of F at b, stays within
BAND^2 of F's own at any speed of the band) and evaluates F at any speeds as
one matrix product after the trims: a scan's or search's new speed costs its
trim and a product, not the assembly of the blades' matrices.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..symbolic.codegen import air_monomials
from . import inflow as inflow_module
from . import trim as trim_module

#: Sources transformed at once while the form is built (bounds the memory).
CHUNK = 256
#: Ratio of one band of speeds to the next (module docstring).
BAND = 16.0


class Source(NamedTuple):
    """Fixed arrays of a rotor in air weighed by monomials of the trim state (:func:`sources`)."""

    #: The blade (None: every blade alike; then the first blade's trim gives the values).
    blade: int | None
    #: The generated function whose monomials weigh ``arrays``, or "own-mass" and
    #: "own-damping" for the dynamic inflow's own terms (a 1/N share on every blade).
    kind: str
    #: (K, 3, 5, nl, nl): mass, damping, stiffness harmonics on the system's coordinates.
    arrays: np.ndarray
    #: Which of the kind's monomials they are, (K,).
    which: np.ndarray
    #: The flat entries of a (3, 5, nl, nl) array that any of them touches, (E,).
    entries: np.ndarray
    #: ``arrays`` on those entries only, (K, E) (a few per cent of the whole are not zero).
    compact: np.ndarray


class AirForm:
    """A time-invariant form of a system in air (module docstring).

    Parameters
    ----------
    system : System
        A rotor in air (not frozen at one trim).
    transform : callable
        ``transform(speeds, harmonics) -> (3, n_s, n, n)``: the form of the system whose
        blade harmonic arrays are ``harmonics`` (n_s, N, 3, 5, nl, nl) at ``speeds``
        (:meth:`groundres.model.system.System.multiblade` or ``rotating_axes``).
    """

    def __init__(self, system, transform):
        self.system, self.transform = system, transform
        self.sources = system.air_sources  # [Source]
        self.bands = {}

    def _band(self, band: float):
        """(A, B, C) of every source and of F_0 at ``band`` [rad/s], (3, 1 + S, 3 n^2)."""
        if band not in self.bands:
            system = self.system
            n_b, shape = system.n_blades, self.sources[0].arrays.shape[1:]
            rows = [(None, np.zeros(shape))] + [
                (source.blade, array) for source in self.sources for array in source.arrays
            ]
            parts = []
            for start in range(0, len(rows), CHUNK):
                chunk = rows[start : start + CHUNK]
                harmonics = np.zeros((len(chunk), n_b) + shape)
                for i, (blade, array) in enumerate(chunk):
                    harmonics[i, slice(None) if blade is None else blade] = array
                at = [
                    self.transform(np.full(len(chunk), w), harmonics).reshape(3, len(chunk), -1)
                    for w in (0.0, band, -band)
                ]
                parts.append(np.stack(at, 1))  # (3 groups, 3 speeds, rows, n^2)
            f = np.concatenate(parts, axis=2)
            f[:, :, 1:] -= f[:, :, :1]  # (each source without the body's part)
            a = f[:, 0]
            b = (f[:, 1] - f[:, 2]) / (2 * band)
            c = (f[:, 1] + f[:, 2] - 2 * a) / (2 * band**2)
            self.bands[band] = np.stack([a, b, c]).transpose(0, 2, 1, 3).reshape(3, len(rows), -1)
        return self.bands[band]

    def values(self, speeds) -> np.ndarray:
        """v_s at ``speeds`` (n_s, 1 + S): one for F_0, then every source's value."""
        return np.concatenate([np.ones((len(speeds), 1)), source_values(self.system, speeds)], axis=1)

    def __call__(self, speeds):
        """Mass, damping and stiffness of the form at ``speeds`` [rad/s], (3, n_s, n, n)."""
        speeds = np.asarray(speeds, dtype=float).reshape(-1)
        n = self.system.size
        out = np.empty((3, len(speeds), n * n))
        values = self.values(speeds)
        with np.errstate(divide="ignore"):  # (at rest only A counts: any band)
            band = np.where(
                speeds > 0, BAND ** np.ceil(np.log(np.maximum(speeds, 1e-300)) / np.log(BAND)), 1.0
            )
        band = np.where(band > 0, band, 1.0)
        for b in np.unique(band):
            sel = band == b
            w = speeds[sel][:, None]
            v = values[sel]
            a, b_, c = self._band(float(b))
            found = v @ a + (w * v) @ b_ + (w * w * v) @ c  # (n_sel, 3 n^2)
            out[:, sel] = found.reshape(-1, 3, n * n).transpose(1, 0, 2)
        return out.reshape(3, len(speeds), n, n)


def source_values(system, speeds) -> np.ndarray:
    """The value of every source of ``system`` (:func:`sources`) at ``speeds``, (n_s, S): the
    monomials of each blade's trim state, or the inflow's own 1 and ``abs(lambda) Omega``."""
    trim = system.trim(speeds)
    columns = []
    for source in system.air_sources:
        k = 0 if source.blade is None else source.blade
        if source.kind == "own-mass":
            columns.append(np.ones((len(speeds), 1)))
        elif source.kind == "own-damping":
            columns.append((np.abs(trim.inflow_ratio) * speeds)[:, None])
        else:
            state = (speeds, trim.inflow_ratio, trim.coning[:, k], trim.trim_lag[:, k])
            columns.append(air_monomials(source.kind, *state)[:, source.which])
    return np.concatenate(columns, axis=1)


def blade_arrays(system, speeds) -> np.ndarray:
    """Every blade's harmonic arrays in air at ``speeds``, (n_s, N, 3, 5, nl, nl)
    (:meth:`groundres.model.system.System.blade_harmonics`): the sources weighed by their
    values, one product per blade (one for all where the blades are alike)."""
    speeds = np.asarray(speeds, dtype=float).reshape(-1)
    found = system.air_sources
    values = source_values(system, speeds)
    shape = found[0].arrays.shape[1:]
    owners = sorted({-1 if source.blade is None else source.blade for source in found})
    total = {b: np.zeros((len(speeds), int(np.prod(shape)))) for b in owners}
    col = 0
    for source in found:  # (onto the entries the source touches: a few per cent of the arrays)
        count = len(source.arrays)
        total[-1 if source.blade is None else source.blade][:, source.entries] += (
            values[:, col : col + count] @ source.compact
        )
        col += count
    common = total.pop(-1, None)
    if not total:  # (every blade alike)
        one = common.reshape((len(speeds),) + shape)
        return np.broadcast_to(one[:, None], (len(speeds), system.n_blades) + shape)
    own = np.stack([total[k] for k in range(system.n_blades)], axis=1)
    if common is not None:  # (the inflow's own terms, on every blade)
        own += common[:, None]
    return own.reshape((len(speeds), system.n_blades) + shape)


def sources(system) -> list[Source]:
    """The blades' arrays in air as sources (:class:`Source`): each blade's (one for all where
    they are alike) weighed by the monomials of its trim state, and the dynamic inflow's own."""
    rotor, body = system.rotor, system.body
    aero = rotor.aero
    out = []

    def add(blade, kind, arrays):  # (the monomials that touch the system's coordinates only)
        flat = arrays.reshape(len(arrays), -1)
        touch = np.flatnonzero(np.abs(flat).max(-1) > 0)
        entries = np.flatnonzero((flat[touch] != 0).any(0))
        out.append(Source(blade, kind, arrays[touch], touch, entries, flat[touch][:, entries]))

    index = np.array(system.local_indices)

    def local(arrays):
        """Every monomial's arrays (K, 3, 5, m, m) on the system's coordinates (those past m,
        the inflow states on arrays without them, are zero)."""
        inside = np.flatnonzero(index < arrays.shape[-1])
        out = np.zeros(arrays.shape[:3] + (len(index), len(index)))
        taken = arrays.take(index[inside], axis=3).take(index[inside], axis=4)
        out[:, :, :, inside[:, None], inside] = taken
        return out

    n_inflow = len(system.inflow_states)
    alike = rotor.blades_alike and system.trims_alike  # (each blade at its own trim otherwise)
    blades = [None] if alike else list(range(system.n_blades))
    hub = trim_module.hub_of(body)
    for k in blades:
        blade = rotor.blades[0 if k is None else k]
        arrays = trim_module.coefficients("blade_in_air", blade, hub, aero)
        if n_inflow:
            coupling = trim_module.coefficients("inflow_in_air", blade, hub, aero)
            add(k, "inflow_in_air", local(np.concatenate([np.zeros_like(coupling[:, :1]), coupling], 1)))
        add(k, "blade_in_air", local(arrays))
    if n_inflow:
        mass, damping = local(inflow_module.own_arrays(aero, system.n_blades))
        add(None, "own-mass", mass[None])
        add(None, "own-damping", damping[None])
    return out
