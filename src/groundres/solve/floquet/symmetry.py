"""The rotor's cyclic symmetry: the shortest azimuth shift under which the equations repeat.

Fast Floquet theory (Peters 1995, "Fast Floquet theory and trim for
multi-bladed rotorcraft", JAHS 39(4)): if advancing the azimuth by
Delta = 2 pi j / N maps the equations onto themselves with blade k + j taking
the place of blade k, then the transition matrix over a revolution is
(G^-1 Phi(Delta))^(N/j) with G that permutation of coordinates, and only
Delta needs integrating (:mod:`groundres.solve.floquet.exponents`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...model.system import System


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
    blades of functions of each blade's own azimuth (and damper rods constant in
    the blades' coordinates), so advancing the azimuth by 2 pi j / N only hands
    each blade's role to blade k + j: the equations repeat when the blades and
    their rods do (:meth:`groundres.model.params.Rotor.repeats`), whatever the body.
    """
    rotor = system.rotor
    n = rotor.n_blades
    for j in range(1, n + 1):
        if n % j == 0 and rotor.repeats(j):
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
