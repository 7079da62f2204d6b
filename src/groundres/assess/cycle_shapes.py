"""A limit cycle's motion: each blade's lag in the rotating frame, and the hub's.

A root of the equivalent linear system moves the nonrotating coordinates
(body, multiblade) at its frequency w plus multiples of Omega: a time-invariant
(multiblade) root at w alone, a periodic (Floquet) one at w + o Omega for its
harmonics o. Blade k's lag is then zeta_k(t) = sum_j B_kj(Omega t) q_j(t), B the
multiblade basis, whose own frequencies in the rotating frame are w + m Omega.
:func:`blade_spectra` samples that periodic product over one revolution and
takes its Fourier series, so the same code serves both routes and any rotor,
identical blades or not. Its largest component sets the amplitude and
frequency the blade's law is evaluated at; the second largest over it says how
good the single-harmonic approximation is; the peak (half peak-to-peak) is
bounded by the sum of all components, which is what is reported.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..model import mbc

#: Second component over the first beyond which the single-harmonic approximation is poor.
POOR = 0.2
#: Cycles beyond this blade amplitude leave the small-angle structure [rad].
LARGE = math.radians(10.0)
#: The hub's second frequency is reported where its component holds this share of the first.
HUB_SECOND = 0.2


@dataclass(frozen=True)
class BladeCycle:
    """One blade's lag on a limit cycle (SI, angles in rad): its largest component in the
    rotating frame (``amplitude`` at ``frequency``), the sum of all (``peak``), the second
    largest over the largest, and the equivalent linear damper its law is taken as (None for
    a blade without a law: a failed damper)."""

    amplitude: float
    peak: float
    frequency: float
    second_component: float
    damping: float | None = None
    stiffness: float | None = None


@dataclass
class Cycle:
    """One limit cycle at one rotor speed; SI units, angles in rad.

    ``amplitude``, ``peak``, ``frequency`` and ``second_component`` are those of the blade
    that moves most; ``blades`` has every blade's (:class:`BladeCycle`), and
    ``equivalent_damping`` and ``equivalent_stiffness`` are the equivalent damper of the
    most-moving blade with a law.
    """

    speed: float
    amplitude: float
    stable: bool
    frequency: float
    #: The frequency of the hub's largest component [rad/s] (the body coordinates': what the
    #: fuselage feels; :attr:`nonrotating_second` the next).
    nonrotating_frequency: float
    peak: float
    hub: dict
    second_component: float
    equivalent_damping: float
    equivalent_stiffness: float
    blades: tuple = ()
    #: The frequency of the hub's second component [rad/s] where it holds :data:`HUB_SECOND` of the
    #: first (a two-bladed or dissimilar rotor shakes the hub at more than one frequency, such as
    #: Omega - w and Omega + w), else None.
    nonrotating_second: float | None = None
    #: The motion at t = 0 (blade 1 at azimuth 0) in blade coordinates, displacements then
    #: rates [m, rad; m/s, rad/s], complex: the cycle is Re(start ...) continued in time.
    start: np.ndarray = field(default=None, repr=False)

    @property
    def poor(self) -> bool:
        """Whether the single-harmonic approximation is poor for a law here (:data:`POOR`): the
        second component of a blade with a law."""
        seen = [b.second_component for b in self.blades if b.damping is not None]
        return max(seen, default=self.second_component) > POOR

    @property
    def large(self) -> bool:
        """Whether the cycle is beyond the small angles the structure assumes (:data:`LARGE`)."""
        return self.peak > LARGE

    @property
    def dissimilar(self) -> bool:
        """Whether the blades' amplitudes differ (a failed or different damper)."""
        amplitudes = [b.amplitude for b in self.blades]
        return bool(amplitudes) and max(amplitudes) - min(amplitudes) > 1e-6 * max(amplitudes)


def blade_spectra(system, harmonics, orders, frequency, speeds):
    """Every blade's lag components in the rotating frame (module docstring).

    Parameters
    ----------
    system : System
    harmonics : complex ndarray (m, n, H)
        Amplitudes of the nonrotating coordinates (:meth:`System.multiblade_coordinates`) at
        the frequencies ``frequency`` + ``orders`` Omega.
    orders : int ndarray (H,)
    frequency : ndarray (m,)
        The roots' frequency w [rad/s] (the imaginary part of the root).
    speeds : ndarray (m,)

    Returns
    -------
    amplitude, at, second, peak : ndarray (m, N)
        Each blade's largest component and its frequency [rad/s, >= 0], the second largest
        over the largest, and the sum of all.
    """
    n_b = system.n_blades
    lag = [i for i, c in enumerate(system.multiblade_coordinates()) if c.kind == "lag"]
    count = 2 * (int(np.abs(orders).max()) + n_b) + 2  # (samples: every order the product holds)
    psi = 2 * np.pi * np.arange(count) / count
    basis = mbc.multiblade_basis(n_b, psi)[0]  # (K, N blades, N multiblade)
    turns = np.exp(1j * np.outer(psi, orders))  # (K, H)
    periodic = np.einsum("kbj,mjh,kh->mbk", basis, harmonics[:, lag, :], turns)
    spectrum = np.abs(np.fft.fft(periodic, axis=-1)) / count  # (m, N, K): order at index mod K
    signed = np.where(np.arange(count) > count // 2, np.arange(count) - count, np.arange(count))
    top = np.argmax(spectrum, axis=-1)
    ordered = np.sort(spectrum, axis=-1)
    amplitude, second = ordered[..., -1], ordered[..., -2]
    at = np.abs(np.asarray(frequency)[:, None] + signed[top] * np.asarray(speeds)[:, None])
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(amplitude > 0, second / amplitude, 0.0)
    return amplitude, at, ratio, spectrum.sum(-1)


def hub_frequencies(system, harmonics, orders, frequency: float, speed: float) -> tuple:
    """The frequencies [rad/s, >= 0] of the hub's largest component and of its second (None
    where that holds less than :data:`HUB_SECOND` of the first): ``harmonics`` (n, H) at
    ``frequency`` + ``orders`` Omega, each order's size the hub centre's largest in-plane
    displacement [m] (:meth:`groundres.model.body.Body.hub_in_plane`; where the hub does not move
    in its plane, the largest body coordinate's; the root's own frequency where the body does not
    move)."""
    body = [i for i, c in enumerate(system.multiblade_coordinates()) if c.kind == "body"]
    size = np.zeros(len(orders))
    if body:
        size = np.abs(system.body.hub_in_plane() @ harmonics[body]).max(axis=0)
        if not size.max() > 0:  # (a body that only heaves, or turns about the hub)
            size = np.abs(harmonics[body]).max(axis=0)
    if not size.max() > 0:
        return abs(frequency), None
    first, second = np.argsort(size)[::-1][:2] if len(size) > 1 else (int(np.argmax(size)), None)
    at = np.abs(frequency + np.asarray(orders) * speed)
    if second is None or size[second] < HUB_SECOND * size[first]:
        return float(at[first]), None
    return float(at[first]), float(at[second])


def hub_amplitudes(system, harmonics) -> dict:
    """The body coordinates' largest components in ``harmonics`` (n, H): name -> m or rad."""
    coords = system.multiblade_coordinates()
    return {c.name: float(np.abs(harmonics[i]).max()) for i, c in enumerate(coords) if c.kind == "body"}


def make_cycle(
    system, speed, amplitude, stable, root, spectra, harmonics, start, laws, damping, stiffness, orders=(0,)
):
    """The cycle of one neutral root scaled to ``amplitude`` of its most-moving blade.

    ``spectra``: one point's rows of :func:`blade_spectra` (each (N,)) for the root as found;
    ``harmonics`` (n, H) at the root's frequency + ``orders`` Omega and ``start`` (2n, blade
    coordinates, rates per second) its motion as found; ``laws``: per blade, whether it has a
    law; ``damping``, ``stiffness``: each blade's equivalent damper (N,).
    """
    unit, at, second, peak = spectra
    top = int(np.argmax(unit))
    scale = amplitude / unit[top]
    blades = tuple(
        BladeCycle(
            amplitude=float(unit[k] * scale),
            peak=float(peak[k] * scale),
            frequency=float(at[k]),
            second_component=float(second[k]),
            damping=float(damping[k]) if laws[k] else None,
            stiffness=float(stiffness[k]) if laws[k] else None,
        )
        for k in range(len(unit))
    )
    working = [k for k in range(len(unit)) if laws[k]]
    lead = max(working, key=lambda k: unit[k])
    hub_first, hub_second = hub_frequencies(system, harmonics, orders, root.imag, speed)
    return Cycle(
        speed=float(speed),
        amplitude=float(amplitude),
        stable=bool(stable),
        frequency=float(at[top]),
        nonrotating_frequency=hub_first,
        peak=float(peak[top] * scale),
        hub=hub_amplitudes(system, harmonics * scale),
        second_component=float(second[top]),
        equivalent_damping=float(damping[lead]),
        equivalent_stiffness=float(stiffness[lead]),
        blades=blades,
        start=np.asarray(start) * scale,
        nonrotating_second=hub_second,
    )
