"""Describing functions of the lag damper laws: the equivalent linear damper at an amplitude.

For a lag motion theta = A cos(w t), the first harmonic of a law's moment
(:mod:`groundres.model.damper_laws`) is k_eq theta + c_eq theta': the
equivalent stiffness [N m/rad] and damping [N m s/rad] at amplitude A [rad]
and frequency w [rad/s]. The damping carries the energy the law dissipates per
cycle, W = pi c_eq w A^2; the stiffness, the in-phase part. The rate laws
depend on A and w through the rate amplitude V = A w only.

* linear: c and K.
* bilinear: c_eq = c2 + (c1 - c2) N(v_r / V), N the saturation function,
  N(r) = (2 / pi) (asin r + r sqrt(1 - r^2)) for r < 1 and 1 beyond (the
  law stays on its first slope while V <= v_r).
* friction and tanh: a moment F tanh(V cos(phi) / v_eps) gives
  c_eq = F t(V / v_eps) / V, t(a) = (4 / pi) int_0^{pi/2} tanh(a cos phi) cos phi dphi,
  by Gauss-Legendre quadrature on panels graded to the width 1 / a of the
  regularisation (exact to round-off). t(a) -> a for small a (the slope F / v_eps),
  and -> 4 / pi for large a (Coulomb's 4 F / (pi V)).
* friction link, with the ideal slider (c_reg -> 0): stuck while k_l A <= F
  (the link is a spring k_l, dissipating nothing); slipping beyond, with
  cos(b) = 1 - 2 F / (k_l A), k_eq = (k_l / pi) (b - sin(2 b) / 2) and
  W = 4 F (A - F / k_l), the area of its parallelogram loop (Caughey 1960,
  "Sinusoidal excitation of a system with bilinear hysteresis"). The
  regularised slider slips at a moment F + c_reg s', above the ideal one's by
  about c_reg A w / F of it (:func:`link_regularisation`).
* table: k_eq = K'(A) and c_eq = K''(A) / w_ref, interpolated linearly in A and
  held at the table's ends: the measured damper as a viscous one at its
  reference frequency w_ref, where its energy per cycle is the measured one
  (the same value the linear analysis takes at small motion, so that the two
  agree; at other frequencies the energy scales with w).
"""

from __future__ import annotations

import numpy as np

from .damper_laws import DamperLaw

#: Gauss-Legendre nodes per panel, and the panels' edges in units of the regularisation's width.
_NODES = 24
_EDGES = (0.0, 0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 64.0)


def equivalent(law: DamperLaw, amplitude, frequency):
    """(c_eq [N m s/rad], k_eq [N m/rad]) of ``law`` at ``amplitude`` [rad] and ``frequency``
    [rad/s] (arrays broadcast; an amplitude of zero gives the small-motion values)."""
    amplitude, frequency = np.broadcast_arrays(np.asarray(amplitude, float), np.asarray(frequency, float))
    rate = amplitude * np.abs(frequency)
    ones = np.ones(amplitude.shape)
    if law.law == "linear":
        return law.damping * ones, law.stiffness * ones
    if law.law == "bilinear":
        with np.errstate(divide="ignore"):
            ratio = np.where(rate > 0, law.relief_rate / np.where(rate > 0, rate, 1.0), np.inf)
        c1, c2 = law.damping, law.damping_after_relief
        return c2 + (c1 - c2) * saturation(ratio), law.stiffness * ones
    if law.law == "friction":
        width = law.regularisation_velocity
        return law.damping + law.friction_moment * smoothed_sign_slope(rate, width), law.stiffness * ones
    if law.law == "tanh":
        return law.tanh_moment * smoothed_sign_slope(rate, 1.0 / law.tanh_rate), law.stiffness * ones
    if law.law == "friction-link":
        c_link, k_link = ideal_link(law.link_stiffness, law.friction_moment, amplitude, frequency)
        return law.damping + c_link, law.stiffness + k_link
    return table(law, amplitude, frequency)


def saturation(ratio):
    """The saturation function N(r) of a limit at r times the amplitude (module docstring)."""
    r = np.minimum(np.asarray(ratio, dtype=float), 1.0)
    return np.where(r >= 1.0, 1.0, (2 / np.pi) * (np.arcsin(r) + r * np.sqrt(1 - r * r)))


def smoothed_sign_slope(rate, width):
    """t(V / w) / V [s/rad] for a moment tanh(v / w) per unit moment (module docstring), at rate
    amplitudes ``rate`` [rad/s]; 1 / w at V = 0."""
    rate = np.asarray(rate, dtype=float)
    a = rate / width
    t = tanh_average(a)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(a > 0, t / np.where(rate > 0, rate, 1.0), 1.0 / width)


def tanh_average(a):
    """t(a) = (4 / pi) int_0^{pi/2} tanh(a cos phi) cos phi dphi, for a >= 0 (array).

    With s = pi/2 - phi the integrand is tanh(a sin s) sin s, which turns over
    within s ~ 1 / a: Gauss-Legendre on panels with edges at multiples of 1 / a
    up to 64 / a (tanh is 1 to round-off beyond), then one panel to pi / 2.
    """
    a = np.asarray(a, dtype=float)
    x, w = np.polynomial.legendre.leggauss(_NODES)
    scale = (1.0 / np.maximum(a, 1e-300))[..., None]  # (a = 0: every panel edge at pi / 2 but the first)
    edges = np.minimum(np.asarray(_EDGES) * scale, np.pi / 2)
    edges = np.concatenate([edges, np.full(a.shape + (1,), np.pi / 2)], axis=-1)
    low, high = edges[..., :-1, None], edges[..., 1:, None]  # (..., panels, 1)
    s = 0.5 * (high - low) * x + 0.5 * (high + low)  # (..., panels, nodes)
    f = np.tanh(a[..., None, None] * np.sin(s)) * np.sin(s)
    total = (0.5 * (high - low)[..., 0] * (f @ w)).sum(-1)
    return 4 / np.pi * total


def ideal_link(stiffness: float, break_out: float, amplitude, frequency):
    """(c_eq, k_eq) of a spring ``stiffness`` [N m/rad] in series with an ideal slider of
    ``break_out`` moment [N m] at ``amplitude`` [rad] and ``frequency`` [rad/s] (module
    docstring: stuck, or slipping on a parallelogram loop)."""
    amplitude, frequency = np.broadcast_arrays(np.asarray(amplitude, float), np.asarray(frequency, float))
    stuck = stiffness * amplitude <= break_out
    safe = np.where(stuck, 1.0, amplitude)
    cos_b = np.clip(1 - 2 * break_out / (stiffness * safe), -1.0, 1.0)
    b = np.arccos(cos_b)
    k_slip = stiffness / np.pi * (b - 0.5 * np.sin(2 * b))
    energy = 4 * break_out * (safe - break_out / stiffness)
    with np.errstate(divide="ignore", invalid="ignore"):
        c_slip = energy / (np.pi * np.abs(frequency) * safe**2)
    return np.where(stuck, 0.0, c_slip), np.where(stuck, stiffness, k_slip)


def link_regularisation(law: DamperLaw, amplitude, frequency):
    """How far the friction link's regularised slider departs from the ideal one at
    ``amplitude`` [rad] and ``frequency`` [rad/s]: c_reg A w / F, the moment by which the
    slider overshoots its break-out while it slips at the motion's rate, over the break-out
    (the describing function is the ideal slider's: its c_eq and k_eq differ from the
    regularised law's by less than this fraction of themselves)."""
    rate = np.asarray(amplitude, float) * np.abs(np.asarray(frequency, float))
    return law.regularisation_damping * rate / law.friction_moment


def table(law: DamperLaw, amplitude, frequency):
    """(c_eq, k_eq) of a table law (module docstring: viscous at the reference frequency, whatever
    ``frequency``); amplitudes outside the table take its end values (:func:`outside_table`)."""
    amplitude = np.asarray(amplitude, dtype=float)
    a = np.asarray(law.amplitudes)
    k_eq = np.interp(amplitude, a, np.asarray(law.storage_stiffness))
    c_eq = np.interp(amplitude, a, np.asarray(law.loss_stiffness)) / law.reference_frequency
    return c_eq * np.ones(np.shape(frequency)), k_eq * np.ones(np.shape(frequency))


def outside_table(law: DamperLaw, amplitude):
    """Where ``amplitude`` [rad] lies outside a table law's amplitudes (False for other laws)."""
    amplitude = np.asarray(amplitude, dtype=float)
    if law.law != "table":
        return np.zeros(amplitude.shape, bool)
    return (amplitude < law.amplitudes[0]) | (amplitude > law.amplitudes[-1])
