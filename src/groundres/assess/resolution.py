"""What the model can resolve: a case whose round-off would hide growth is refused.

Checked before any work; a case outside is refused with
:class:`~groundres.errors.ModelRangeError`, whose message names the key, its
value and the range this case allows (the command line exits 2). Its
magnitudes are kept in floating point by the mass unit its equations are
computed in (:class:`groundres.model.units.MassUnit`); what a periodic
analysis costs is :mod:`groundres.solve.floquet.cost`'s concern.

**Resolution.** Real parts come out of an eigen-solver (or a transition
matrix) with an absolute error of about eps times the fastest rate of the
system, eps = 2.2e-16. A root counts as growing above the growth threshold
(:func:`groundres.assess.stability.growth_threshold`), so a case is refused where
``ROUND_OFF * eps * fastest rate`` exceeds that threshold at some speed of
the sweep: a lag damper of 1e14 N m s/rad on a 1000 kg m^2 blade decays at
1e11 1/s and leaves the real parts uncertain by about 1e-5 1/s, too much to
tell growth from round-off at a few rad/s. The fastest rate is read from
the roots of the equations frozen at a few azimuths, coordinates scaled so
that the mass matrix has a unit diagonal.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ..errors import ModelRangeError
from ..model.body import BODY_DOFS, TRANSLATIONS, Body
from ..model.keys import key_text
from ..model.params import Rotor
from ..model.units import speed_text
from ..solve.modal import unit_mass_state_matrix

EPS = float(np.finfo(float).eps)
#: Real parts are trusted to ROUND_OFF * eps * (fastest rate of the system).
ROUND_OFF = 10.0


# -- resolution -------------------------------------------------------------------


@dataclass(frozen=True)
class RateSource:
    """A rate [1/s] one parameter sets on its own: rate = (value / coefficient)**(1/power).

    The parameter is ``name`` of the case file's ``table`` (``detail`` says which
    blade, rod or direction where the table has several).
    """

    table: str
    name: str
    detail: str
    value: float
    unit: str
    power: int
    coefficient: float
    what: str
    at_top: bool  # the rate grows with rotor speed (given at the stop speed)
    given_rate: float | None = None  # the rate where the formula above would overflow
    leg: int = 0  # the [[body.gear]] leg it belongs to (1-based), if any

    @property
    def key(self) -> str:
        """The parameter as a message names it (:func:`groundres.model.keys.key_text`; a
        leg's as the case reader does, ``[[body.gear]] 2: damping_z``)."""
        if self.leg:
            return f"{key_text(self.table)} {self.leg}: {self.name}"
        return key_text(self.table, self.name) + (f" ({self.detail})" if self.detail else "")

    @property
    def short(self) -> str:
        """The parameter named within its table: ``lag_damping (blade 2)``, ``leg 1's damping_z``."""
        if self.leg:
            return f"leg {self.leg}'s {self.name}"
        return self.name + (f" ({self.detail})" if self.detail else "")

    @property
    def rate(self) -> float:
        if self.given_rate is not None:
            return self.given_rate
        with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
            r = (
                (np.float64(self.value) / self.coefficient) ** (1.0 / self.power)
                if self.coefficient > 0
                else 0.0
            )
        return float(r) if math.isfinite(r) else math.inf

    def value_at(self, rate: float) -> float:
        """The value that sets ``rate`` (inf or nan where it is beyond floating point)."""
        with np.errstate(over="ignore", invalid="ignore"):
            return float(np.float64(self.coefficient) * np.float64(rate) ** self.power)


def rate_sources(rotor: Rotor, body: Body, top_speed: float, speed_unit=("rad/s", 1.0)) -> list[RateSource]:
    """Rates [1/s] the parameters of a case set on their own (dampers, springs, speed);
    the stop speed [rad/s] is named in ``speed_unit`` (name, rad/s per unit)."""
    out = []
    many = not rotor.blades_alike
    for k, b in enumerate(rotor.blades if many else rotor.blades[:1]):
        where = f"blade {k + 1}" if many else ""
        i = b.blade_inertia
        for kind in ("lag", "flap") if rotor.flap else ("lag",):
            what = f"with blade_inertia {i:.5g} kg m^2"
            c, s = getattr(b, f"{kind}_damping"), getattr(b, f"{kind}_stiffness")
            out.append(
                RateSource("rotor", f"{kind}_damping", where, c, "N m s/rad", 1, i, f"C/I {what}", False)
            )
            out.append(
                RateSource(
                    "rotor", f"{kind}_stiffness", where, s, "N m/rad", 2, i, f"sqrt(K/I) {what}", False
                )
            )
        if b.blade_static_moment > 0 and top_speed > 0:
            with np.errstate(over="ignore", under="ignore", divide="ignore"):
                # (in that order: Omega^2 alone overflows above 1e154 rad/s)
                coef = float(np.float64(i) / b.blade_static_moment / top_speed / top_speed)
                rate = float(top_speed * np.sqrt(np.float64(b.hinge_offset) * b.blade_static_moment / i))
            out.append(
                RateSource(
                    "rotor",
                    "hinge_offset",
                    where,
                    b.hinge_offset,
                    "m",
                    2,
                    coef,
                    "Omega sqrt(e S/I)",
                    True,
                    rate,
                )
            )
    offsets = [b.hinge_offset for b in rotor.blades]
    for damper in rotor.dampers:
        g2 = float(np.sum(damper.gradient(offsets, rotor.n_blades) ** 2))
        if not g2 > 0:  # (a rod whose length the blades' angles do not change sets no rate)
            continue
        i = rotor.blades[damper.blade - 1].blade_inertia
        where = f"{damper.kind} from blade {damper.blade}"
        what = f"with blade_inertia {i:.5g} kg m^2 and the rod's lever g^2 = {g2:.5g} m^2"
        out.append(
            RateSource(
                "rotor.damper",
                "damping",
                where,
                damper.damping,
                "N s/m",
                1,
                i / g2,
                f"c g^2/I {what}",
                False,
            )
        )
        out.append(
            RateSource(
                "rotor.damper",
                "stiffness",
                where,
                damper.stiffness,
                "N/m",
                2,
                i / g2,
                f"sqrt(k g^2/I) {what}",
                False,
            )
        )
    m_rotor = sum(b.blade_mass for b in rotor.blades)
    mats = body.matrices()
    for i, d in enumerate(body.dofs):
        added = m_rotor if d in TRANSLATIONS else rotor.inertia_about_pivot(body.hub_height, d)
        mass = mats[0, i, i] + added
        unit = ("N s/m", "N/m") if d in TRANSLATIONS else ("N m s/rad", "N m/rad")
        what = f"with the rotor's share, M = {mass:.5g}"
        if body.form == "rigid":  # (each leg's springs and dampers, by what they add in that direction)
            out += _leg_sources(body, i, d, mass, what)
            continue
        keys = [("body", f"{kind}_{d}", "") for kind in ("damping", "stiffness")]
        out.append(RateSource(*keys[0], mats[1, i, i], unit[0], 1, mass, f"C/M {what}", False))
        out.append(RateSource(*keys[1], mats[2, i, i], unit[1], 2, mass, f"sqrt(K/M) {what}", False))
    name, factor = speed_unit
    out.append(
        RateSource("sweep", "stop", "", top_speed / factor, name, 1, 1.0 / factor, "the rotor speed", True)
    )
    return out


def _leg_sources(body: Body, i: int, dof: str, mass: float, what: str) -> list[RateSource]:
    """The rates each leg's springs and dampers set in the body's ``i``-th coordinate ``dof``
    (inertia ``mass`` there), from what each adds to its diagonal (lever^2 g2 times the value)."""
    out = []
    full = BODY_DOFS.index(dof)
    translation = dof in TRANSLATIONS
    for n, leg in enumerate(body.gear, start=1):
        for a in "xyz":
            g2 = float(leg.along(**{a: 1.0})[full, full])  # [1] or [m^2]
            if not g2 > 0:  # (a spring that does not move this coordinate)
                continue
            lever = "" if translation else f", lever^2 {g2:.4g} m^2"
            for kind, unit, power, rate in (
                ("damping", "N s/m", 1, "C/M"),
                ("stiffness", "N/m", 2, "sqrt(K/M)"),
            ):
                value = getattr(leg, f"{kind}_{a}")
                how = f"{rate} in {dof} {what}{lever}"
                out.append(
                    RateSource(
                        "body.gear", f"{kind}_{a}", "", value, unit, power, mass / g2, how, False, leg=n
                    )
                )
    return out


#: Azimuths [rad] the equations are frozen at to read their magnitudes and rates.
_AZIMUTHS = np.linspace(0, 2 * np.pi, 4, endpoint=False)[:, None]


def _finite_matrices(system, speeds, psi=_AZIMUTHS):
    """M, C, K at ``speeds`` and azimuths ``psi``, or None where any entry overflows."""
    with np.errstate(over="ignore", invalid="ignore"):
        m, c, k = system.matrices(np.asarray(speeds, dtype=float), psi)
        finite = np.isfinite(m).all() and np.isfinite(c).all() and np.isfinite(k).all()
    return (m, c, k) if finite else None


def _finite_at(system, speeds, psi=_AZIMUTHS) -> bool:
    return _finite_matrices(system, speeds, psi) is not None


def _largest_finite_speed(system, lo: float, hi: float, psi=_AZIMUTHS) -> float:
    """The largest speed [rad/s] in [lo, hi] at which the equations are finite (lo is), to 1 %."""
    lo = max(lo, 1e-300)
    for _ in range(200):  # bisection on log speed
        if hi <= 1.01 * lo:
            break
        mid = math.sqrt(lo) * math.sqrt(hi)
        lo, hi = (mid, hi) if _finite_at(system, [mid], psi) else (lo, mid)
    return lo


def check_representable(system, speed: float, key: str, speed_unit=("rad/s", 1.0)) -> None:
    """Refuse a rotor speed [rad/s] at which the equations overflow, naming ``key``
    and the largest speed the case can be represented at (in the case's unit)."""
    if _finite_at(system, [speed]):
        return
    top = _largest_finite_speed(system, 0.0, speed)
    name, factor = speed_unit
    raise ModelRangeError(
        f"{key} = {speed / factor:.6g} {name}: the equations overflow in double precision at that "
        "rotor speed (their terms grow as Omega^2); this case can be represented up to about "
        f"{speed_text(top, speed_unit)}: keep the speed well below it"
    )


#: A mass matrix scaled to a unit diagonal whose smallest eigenvalue is below this is singular.
SINGULAR_MASS = 1e-12


def _unit_diagonal(m: np.ndarray) -> np.ndarray:
    """Mass matrices (..., n, n) with coordinates scaled to a unit diagonal."""
    d = np.sqrt(np.abs(np.diagonal(m, axis1=-2, axis2=-1)))
    return m / (d[..., :, None] * d[..., None, :])


def _mass_singular(rotor: Rotor, body: Body, speeds) -> bool:
    """Whether the case's mass matrix is singular to working precision (or overflows) at ``speeds``."""
    from ..model.system import System

    mats = _finite_matrices(System.in_mass_unit(rotor, body), speeds)
    return mats is None or np.linalg.eigvalsh(_unit_diagonal(mats[0])).min() <= SINGULAR_MASS


def check_mass(rotor: Rotor, body: Body, speeds) -> None:
    """Refuse a rigid body whose ``mass`` is so large against its moments of inertia that the
    case's mass matrix is singular to working precision, naming the mass, the inertias and the
    largest mass that would do (found by bisection on its logarithm)."""
    speeds = np.asarray(speeds, dtype=float)
    if body.form != "rigid" or not _mass_singular(rotor, body, speeds):
        return

    def fits(exponent: float) -> bool:
        return not _mass_singular(rotor, replace(body, mass=10.0**exponent), speeds)

    low, high = -300.0, math.log10(body.mass)  # (a mass of 1e-300 kg: the rotor's inertia alone)
    if not fits(low):  # (the mass is not what makes it singular: fastest_rate says what may)
        return
    while high - low > 0.5:  # (the largest mass that fits, to half a decade)
        middle = (low + high) / 2
        low, high = (middle, high) if fits(middle) else (low, middle)
    names = {"roll": "inertia_xx", "pitch": "inertia_yy", "yaw": "inertia_zz"}
    inertias = ", ".join(f"{k} = {getattr(body, k):.4g}" for d, k in names.items() if d in body.dofs)
    centre = math.hypot(body.centre_x, body.centre_y, body.centre_z)
    raise ModelRangeError(
        f"{key_text('body', 'mass')} = {body.mass:.6g} kg: so large against the body's moments of inertia "
        f"({inertias} kg m^2, about its centre of mass {centre:.4g} m from the pivot) that the mass matrix "
        "of this case is singular in double precision (the body's rotations about the pivot cannot be "
        f"told from its translations); allowed here: mass up to about {10.0**low:.1g} kg, or larger moments "
        "of inertia"
    )


def fastest_rate(system, speeds, speed_unit=("rad/s", 1.0)) -> np.ndarray:
    """Largest ``|root|`` [1/s] of the equations frozen at four azimuths, at each speed (n_s,).

    Raises
    ------
    ModelRangeError
        If the coefficients are not finite or the mass matrix is singular.
    """
    speeds = np.asarray(speeds, dtype=float)
    mats = _finite_matrices(system, speeds)
    slow, fast = float(speeds.min()), float(speeds.max())
    if mats is None and fast > 0 and _finite_at(system, [slow]):
        check_representable(system, fast, key_text("sweep", "stop"), speed_unit)
    if mats is None:
        raise ModelRangeError(
            "the equations of this case overflow in double precision: a length (hinge_offset, "
            "hub_height) or a product of parameters is too large; keep lengths below about 1e100 m "
            "and the ratios of like parameters within about 1e100"
        )
    m, c, k = mats
    unit_mass = _unit_diagonal(m)
    if np.linalg.eigvalsh(unit_mass).min() <= SINGULAR_MASS:
        raise ModelRangeError(
            "the mass matrix of this case is singular to working precision: some motion has almost "
            "no inertia of its own against the rest (a blade with blade_static_moment^2 = blade_mass * "
            "blade_inertia on a body of almost no mass, or a rigid body whose mass is so large against "
            "its moments of inertia that its translations and rotations cannot be told apart): bring the "
            "masses and inertias within about 1e10 of each other, or give the blade more inertia"
        )
    with np.errstate(over="ignore", invalid="ignore"):
        roots = np.linalg.eigvals(unit_mass_state_matrix(m, c, k)[0])
    return np.abs(roots).max(-1).max(0)


def check_resolution(rotor: Rotor, body: Body, system, speeds, threshold, speed_unit=("rad/s", 1.0)) -> None:
    """Refuse a case whose round-off would exceed the growth threshold (module docstring).

    Parameters
    ----------
    rotor, body : Rotor, Body
        The case's own (physical) parameters, to name the key.
    system : System
        The equations, in the mass unit they are computed in.
    speeds : ndarray
        The sweep [rad/s].
    threshold : callable
        Growth threshold [1/s] at given speeds.
    speed_unit : (str, float)
        The case's speed unit and its size [rad/s], for the message.

    Raises
    ------
    ModelRangeError
    """
    speeds = np.asarray(speeds, dtype=float)
    ends = np.array([speeds.min(), speeds.max()])
    tau = threshold(ends)
    with np.errstate(over="ignore"):
        allowed = tau / (ROUND_OFF * EPS)  # fastest rate resolved at each end [1/s]
    sources = rate_sources(rotor, body, float(ends[-1]), speed_unit)
    excess = [src.rate / allowed[int(src.at_top)] for src in sources]
    worst = sources[int(np.argmax(excess))]
    if max(excess) > 1.0:
        end = int(worst.at_top)
        rate = worst.rate
    else:
        check_mass(rotor, body, ends)
        rho = fastest_rate(system, ends, speed_unit)
        if (rho <= allowed).all():
            return
        end = int(np.argmax(rho / allowed))
        rate = float(rho[end])
        # the parameter that comes nearest to setting that rate on its own
        worst = max((src for src in sources if int(src.at_top) == end), key=lambda src: src.rate)
    if worst.rate >= 0.1 * rate and worst.rate > 0:
        head = f"{worst.key} = {worst.value:.6g} {worst.unit}: it sets a rate of {worst.rate:.3g} 1/s"
        head += f" ({worst.what})"
        top = worst.value_at(allowed[end])
        limit = (
            f"; allowed here: {worst.short} up to about {top:.3g} {worst.unit}" if 0 < top < math.inf else ""
        )
    else:
        head = f"the fastest root of this case moves at about {rate:.3g} 1/s"
        limit = ""
    raise ModelRangeError(
        f"{head}, so its real parts carry round-off of about {ROUND_OFF * EPS * rate:.2g} 1/s, above the "
        f"growth threshold ({tau[end]:.2g} 1/s at {speed_text(ends[end], speed_unit)}): growth could not "
        f"be told from round-off. The model resolves rates up to {allowed[end]:.3g} 1/s at that speed{limit}"
    )
