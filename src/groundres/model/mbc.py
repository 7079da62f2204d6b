"""Coordinate transforms that remove the periodic coefficients.

Multiblade (Coleman) coordinates for any number of blades N:

    q_k = q_0 + sum_{n=1}^{(N-1)//2} (q_nc cos n psi_k + q_ns sin n psi_k) + q_d (-1)^(k-1)

(``q_d`` only for even N), with blade k at psi_k = Omega t + 2 pi (k-1)/N.
Body coordinates in rotating axes turn with the rotor:

    x = x_r cos(Omega t) - y_r sin(Omega t),  y = x_r sin(Omega t) + y_r cos(Omega t),

and likewise (pitch, roll) -> (pitch_r, roll_r).

For a system ``M q'' + C q' + K q = 0`` and ``q = T(t) p`` the transformed
equations premultiplied by T' are

    T'M T p'' + T'(2 M T' + C T) p' + T'(M T'' + C T' + K T) p = 0,

which is what :func:`transform_equations` returns. Premultiplying by T' (rather
than by the inverse of T) keeps the mass matrix symmetric; multiblade rows are
then N/2 (cyclic) or N (collective, differential) times the averaged equations.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Coordinate:
    """One generalised coordinate of a (transformed) system.

    Attributes
    ----------
    kind : str
        "body", "lag", "flap" or "inflow" (a state of dynamic inflow: its rate is the inflow
        velocity, its displacement the air that velocity carries down).
    name : str
        Body: "x", "y", "pitch", "roll". Blade, multiblade: "0", "1c", "1s", ...,
        "d"; blade, individual: "1", "2", ... (blade index).
    harmonic : int
        Multiblade harmonic n (0 for collective, N/2 for differential); 0 for body
        and individual blade coordinates.
    frame : str
        "nonrotating" or "rotating": the axes in which the coordinate is measured.
    """

    kind: str
    name: str
    harmonic: int = 0
    frame: str = "nonrotating"

    @property
    def unit(self) -> str:
        """Unit of the coordinate's displacement (:func:`unit_of`)."""
        return unit_of(self.kind, self.name)

    @property
    def short(self) -> str:
        """Name of a blade coordinate in a time history and its initial values: ``x``, ``lag1``,
        ``inflow_uniform``."""
        return self.symbol if self.kind in ("body", "inflow") else f"{self.kind}{self.name}"

    @property
    def symbol(self) -> str:
        """Short name for tables and equations, e.g. ``lag_1c`` or ``x_r``."""
        if self.kind == "body":
            return self.name + ("_r" if self.frame == "rotating" else "")
        return f"{self.kind}_{self.name}"


def unit_of(kind: str, name: str) -> str:
    """Unit of a coordinate's displacement: "m" for body translations (in either frame: ``x`` or
    ``x_r``) and the inflow states (the air their rates, the inflow velocities, carry down),
    "rad" for angles."""
    if kind == "inflow":
        return "m"
    return "m" if kind == "body" and name.removesuffix("_r") in ("x", "y", "z") else "rad"


def multiblade_names(n_blades: int) -> list[tuple[str, int]]:
    """Names and harmonics of the N multiblade coordinates, in transform order."""
    names = [("0", 0)]
    for n in range(1, (n_blades - 1) // 2 + 1):
        names += [(f"{n}c", n), (f"{n}s", n)]
    if n_blades % 2 == 0:
        names.append(("d", n_blades // 2))
    return names


def blade_azimuths(n_blades: int, phase=0.0) -> np.ndarray:
    """Azimuths psi_k = phase + 2 pi (k-1)/N; shape ``phase.shape + (N,)``."""
    phase = np.asarray(phase, dtype=float)
    return phase[..., None] + 2.0 * np.pi * np.arange(n_blades) / n_blades


def multiblade_basis(n_blades: int, phase=0.0):
    """Blade-to-multiblade matrix and its first two azimuth derivatives.

    Parameters
    ----------
    n_blades : int
        N >= 2.
    phase : float or array
        Azimuth of blade 1 [rad], e.g. Omega t.

    Returns
    -------
    basis, d_basis, d2_basis : ndarray, shape ``phase.shape + (N, N)``
        ``basis[..., k, j]`` is multiblade function j at blade k; the
        derivatives are with respect to azimuth (multiply by Omega, Omega^2 for
        time derivatives).
    """
    psi = blade_azimuths(n_blades, phase)
    out = np.zeros((3,) + psi.shape + (n_blades,))
    for j, (name, n) in enumerate(multiblade_names(n_blades)):
        if name == "0":
            out[0, ..., j] = 1.0
        elif name == "d":
            out[0, ..., j] = (-1.0) ** np.arange(n_blades)
        elif name.endswith("c"):
            out[0, ..., j] = np.cos(n * psi)
            out[1, ..., j] = -n * np.sin(n * psi)
            out[2, ..., j] = -(n**2) * np.cos(n * psi)
        else:
            out[0, ..., j] = np.sin(n * psi)
            out[1, ..., j] = n * np.cos(n * psi)
            out[2, ..., j] = -(n**2) * np.sin(n * psi)
    return out[0], out[1], out[2]


def rotation_basis(phase=0.0):
    """2 x 2 rotation by ``phase`` and its azimuth derivatives (rotating axes)."""
    c, s = np.cos(phase), np.sin(phase)
    rot = np.stack([np.stack([c, -s], -1), np.stack([s, c], -1)], -2)
    d_rot = np.stack([np.stack([-s, -c], -1), np.stack([c, -s], -1)], -2)
    return rot, d_rot, -rot


def transform_equations(mass, damping, stiffness, t, t_dot, t_ddot):
    """Equations in new coordinates p, for q = T p (stacked over leading axes).

    Parameters
    ----------
    mass, damping, stiffness : ndarray (..., n, n)
        Matrices of the original equations at the instant considered.
    t, t_dot, t_ddot : ndarray (..., n, m)
        T and its first and second time derivatives at that instant.

    Returns
    -------
    tuple of ndarray (..., m, m)
        Mass, damping and stiffness of T' M T p'' + ... (see module docstring).
    """
    tt = np.swapaxes(t, -1, -2)
    new_mass = tt @ mass @ t
    new_damping = tt @ (2.0 * mass @ t_dot + damping @ t)
    new_stiffness = tt @ (mass @ t_ddot + damping @ t_dot + stiffness @ t)
    return new_mass, new_damping, new_stiffness
