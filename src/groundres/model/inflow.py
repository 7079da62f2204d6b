"""Pitt-Peters dynamic inflow in hover: the three inflow states and their own terms.

With ``inflow = "dynamic"`` the air through the disc is the trim's uniform
inflow plus three states, velocities down the shaft [m/s]: ``v_uniform``, and
``v_forward`` and ``v_left``, the values at the tip of parts growing linearly
forward and to the left of the hub (``docs/theory.md``, "Dynamic inflow").
In hover (Pitt and Peters 1981, "Theoretical prediction of dynamic-inflow
derivatives", Vertica 5; Peters 2009, "How dynamic inflow survives in the
competitive world of rotorcraft aerodynamics", JAHS 54), with psi = Omega t,
nu = v / (Omega R) and lambda the trim inflow ratio:

    M0 nu_0' + 4 lambda nu_0 = C_T,   M1 nu_f' + lambda nu_f = C_f,   M1 nu_l' + lambda nu_l = C_l

with the apparent masses M0 = 128 / (75 pi), M1 = 16 / (45 pi), and the
forcing the thrust's and the first moments' (forward, to the left) changes.
Times rho pi R^4 Omega^2 each row is a force [N]:

    rho pi R^3 M0 v_0. + 4 lambda rho pi R^3 Omega v_0 = dT

and likewise for the moments over R. The inflow states are the rates of
coordinates that appear nowhere else (:attr:`groundres.model.system.System.integrals`),
so that the equations keep their second-order form; the blades' share of the
forcing and the loads the inflow puts on them are derived
(:func:`groundres.symbolic.inflow.derive_inflow_coupling`); the own terms above
are given here (:func:`own_arrays`), a 1/N share with each blade, and joined to the blades'
arrays by :mod:`groundres.model.airform`.
"""

from __future__ import annotations

import math

import numpy as np

from ..symbolic.codegen import INFLOW_STATES

#: The inflow states, in order (:data:`groundres.symbolic.codegen.INFLOW_STATES`).
STATES = INFLOW_STATES
#: Apparent masses of the uniform and of the first-harmonic parts (Pitt and Peters 1981).
APPARENT_MASS = (128.0 / (75.0 * math.pi), 16.0 / (45.0 * math.pi), 16.0 / (45.0 * math.pi))
#: The inflow gains in hover over the trim inflow ratio: V L^-1 = diag(4, 1, 1) lambda.
GAIN = (4.0, 1.0, 1.0)


def states(aero) -> tuple:
    """The inflow states of a rotor with ``aero`` (none in vacuum or with uniform inflow)."""
    return STATES if aero is not None and aero.inflow == "dynamic" else ()


def own_arrays(aero, n_blades: int) -> np.ndarray:
    """The inflow's own terms as one blade's share, (2, 3, 5, 11, 11): its apparent mass
    [kg], and its damping per unit ``abs(lambda) Omega`` [kg], each on the inflow states'
    rows and columns (LOCAL_DOFS, then STATES), a 1/N share with each blade (the rows of
    the nonrotating coordinates are summed over the blades). Air density in the system's
    mass unit."""
    scale = aero.air_density * math.pi * aero.tip_radius**3 / n_blades
    out = np.zeros((2, 3, 5, 8 + len(STATES), 8 + len(STATES)))
    for i, (mass, gain) in enumerate(zip(APPARENT_MASS, GAIN)):
        out[0, 0, 0, 8 + i, 8 + i] = scale * mass
        out[1, 1, 0, 8 + i, 8 + i] = scale * gain
    return out
