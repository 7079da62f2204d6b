"""What the model can represent, and what a periodic analysis costs.

Checked before any work; a case outside them is refused with
:class:`ModelRangeError`, whose message names the key, its value and the
range this case allows (the command line exits 2).

**Magnitudes.** Every coefficient of the equations is linear in the masses,
static moments, inertias, springs and dampers, so dividing all of them by
one mass unit changes no root and no mode shape. Where the inertias of a
case lie outside 2^+-200 kg (kg m^2), they are computed in a mass unit that
is a power of two near the largest one (:func:`mass_unit`): exact in
floating point, so that the products of the equations cannot overflow or
underflow. Lengths and speeds are used as given.

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

**Work.** A Floquet analysis integrates one period per speed; the step count
grows as the fastest rate per radian, so as 1/Omega at low speed, and the
cost of a step as the square of the state size (measured: 12 to 44 states),
five times more where a period's grid is too fine to keep (low speeds).
:func:`floquet_work` estimates it before the integration starts, and
:func:`check_floquet_work` refuses a sweep above :data:`FLOQUET_WORK_LIMIT`
with the estimate and what to change.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace

import numpy as np

from ..model.body import TRANSLATIONS
from ..model.params import Blade, Body, Rotor
from ..model.system import System
from ..solve.modal import unit_mass_state_matrix

EPS = float(np.finfo(float).eps)
#: Real parts are trusted to ROUND_OFF * eps * (fastest rate of the system).
ROUND_OFF = 10.0
#: Inertias inside 2^+-MASS_RANGE are used as given; outside, a mass unit is used.
MASS_RANGE = 200
#: Estimated Floquet work above which an analysis is refused, in steps of a
#: 12-state system (0.005 to 0.3 ms each on two laptop cores, the estimate
#: being an upper bound: at most a few minutes).
FLOQUET_WORK_LIMIT = 2e6
#: State size of the work unit.
_WORK_STATE = 12
#: Work units per flop-cube of a nonsymmetric eigenvalue problem (measured: a
#: 1500-row problem costs about as much as 5e4 steps).
_EIG_PER_STEP = 1.6e-5
#: Work units of each speed beside its steps, for a 12-state system: its
#: multipliers, periodic eigenvectors, harmonics and their names (about as
#: much as 16 steps), and the memory they take.
_PER_SPEED = 16.0

_BLADE_MASS_LIKE = tuple(f.name for f in fields(Blade) if f.name != "hinge_offset")
_BODY_KINDS = ("mass", "inertia_", "stiffness_", "damping_")
_BY_MASS = ("stiffness", "damping")  # (of a leg or a damper rod: scale with the mass unit)


class ModelRangeError(ValueError):
    """A case the model cannot resolve, or a sweep too costly; the message says why and what is allowed."""


# -- magnitudes ------------------------------------------------------------------


def _inertias(rotor: Rotor, body: Body):
    values = [v for b in rotor.blades for v in (b.blade_mass, b.blade_inertia, b.blade_static_moment)]
    if body.form == "rigid":
        values += [body.mass, *np.abs(np.linalg.eigvalsh(body.inertia_tensor()))]
    else:
        values += [body.value("inertia", d) for d in body.dofs]
    return [v for v in values if v > 0]


def mass_unit(rotor: Rotor, body: Body) -> float:
    """The mass unit [kg] the equations of a case are computed in: 1 unless its
    inertias lie outside 2^+-MASS_RANGE, else the power of two nearest the largest."""
    big = max(_inertias(rotor, body))
    if 2.0**-MASS_RANGE <= big <= 2.0**MASS_RANGE:
        return 1.0
    return math.ldexp(1.0, min(round(math.log2(big)), 1023))  # (2^1024 is no float)


def in_mass_unit(rotor: Rotor, body: Body, unit: float) -> tuple[Rotor, Body]:
    """Rotor and body with every mass-like parameter divided by ``unit`` (exact for a power of two)."""
    if unit == 1.0:
        return rotor, body
    blades = tuple(replace(b, **{k: getattr(b, k) / unit for k in _BLADE_MASS_LIKE}) for b in rotor.blades)
    changes = {
        f.name: getattr(body, f.name) / unit
        for f in fields(Body)
        if f.name.startswith(_BODY_KINDS) and getattr(body, f.name)
    }
    changes["gear"] = tuple(_scaled(leg, unit) for leg in body.gear)
    dampers = tuple(_scaled(d, unit) for d in rotor.dampers)
    return replace(rotor, blades=blades, dampers=dampers), replace(body, **changes)


def _scaled(part, unit: float):
    """A leg or damper rod with its stiffnesses and dampings divided by ``unit``."""
    return replace(
        part, **{f.name: getattr(part, f.name) / unit for f in fields(part) if f.name.startswith(_BY_MASS)}
    )


def system_in_mass_unit(rotor: Rotor, body: Body) -> tuple[System, float]:
    """The equations of a case computed in its mass unit (:func:`mass_unit`), and that unit [kg]."""
    unit = mass_unit(rotor, body)
    return System(*in_mass_unit(rotor, body, unit)), unit


# -- resolution -------------------------------------------------------------------


@dataclass(frozen=True)
class RateSource:
    """A rate [1/s] one parameter sets on its own: rate = (value / coefficient)**(1/power)."""

    key: str
    value: float
    unit: str
    power: int
    coefficient: float
    what: str
    at_top: bool  # the rate grows with rotor speed (given at the stop speed)
    given_rate: float | None = None  # the rate where the formula above would overflow

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
        where = f" (blade {k + 1})" if many else ""
        i = b.blade_inertia
        for kind in ("lag", "flap") if rotor.flap else ("lag",):
            what = f"with blade_inertia {i:.5g} kg m^2"
            c, s = getattr(b, f"{kind}_damping"), getattr(b, f"{kind}_stiffness")
            out.append(
                RateSource(f"[rotor] {kind}_damping{where}", c, "N m s/rad", 1, i, f"C/I {what}", False)
            )
            out.append(
                RateSource(f"[rotor] {kind}_stiffness{where}", s, "N m/rad", 2, i, f"sqrt(K/I) {what}", False)
            )
        if b.blade_static_moment > 0 and top_speed > 0:
            with np.errstate(over="ignore", under="ignore", divide="ignore"):
                # (in that order: Omega^2 alone overflows above 1e154 rad/s)
                coef = float(np.float64(i) / b.blade_static_moment / top_speed / top_speed)
                rate = float(top_speed * np.sqrt(np.float64(b.hinge_offset) * b.blade_static_moment / i))
            out.append(
                RateSource(
                    f"[rotor] hinge_offset{where}",
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
                f"[[rotor.damper]] damping ({where})",
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
                f"[[rotor.damper]] stiffness ({where})",
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
        if body.form == "rigid":
            keys = (f"[[body.gear]] damping (in {d})", f"[[body.gear]] stiffness (in {d})")
        else:
            keys = (f"[body] damping_{d}", f"[body] stiffness_{d}")
        out.append(RateSource(keys[0], mats[1, i, i], unit[0], 1, mass, f"C/M {what}", False))
        out.append(RateSource(keys[1], mats[2, i, i], unit[1], 2, mass, f"sqrt(K/M) {what}", False))
    name, factor = speed_unit
    out.append(RateSource("[sweep] stop", top_speed / factor, name, 1, 1.0 / factor, "the rotor speed", True))
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
        check_representable(system, fast, "[sweep] stop", speed_unit)
    if mats is None:
        raise ModelRangeError(
            "the equations of this case overflow in double precision: a length (hinge_offset, "
            "hub_height) or a product of parameters is too large; keep lengths below about 1e100 m "
            "and the ratios of like parameters within about 1e100"
        )
    m, c, k = mats
    d = np.sqrt(np.abs(np.diagonal(m, axis1=-2, axis2=-1)))
    unit_mass = m / (d[..., :, None] * d[..., None, :])
    if np.linalg.eigvalsh(unit_mass).min() <= 1e-12:
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


def speed_text(w: float, speed_unit=("rad/s", 1.0)) -> str:
    """A speed [rad/s] in a case's unit (name, rad/s per unit), with rad/s beside it."""
    name, factor = speed_unit
    return f"{w:.4g} rad/s" if factor == 1.0 else f"{w / factor:.4g} {name} ({w:.4g} rad/s)"


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
        name = worst.key.split("] ")[-1]
        top = worst.value_at(allowed[end])
        limit = f"; allowed here: {name} up to about {top:.3g} {worst.unit}" if 0 < top < math.inf else ""
    else:
        head = f"the fastest root of this case moves at about {rate:.3g} 1/s"
        limit = ""
    raise ModelRangeError(
        f"{head}, so its real parts carry round-off of about {ROUND_OFF * EPS * rate:.2g} 1/s, above the "
        f"growth threshold ({tau[end]:.2g} 1/s at {speed_text(ends[end], speed_unit)}): growth could not "
        f"be told from round-off. The model resolves rates up to {allowed[end]:.3g} 1/s at that speed{limit}"
    )


# -- work of a periodic analysis ---------------------------------------------------


def floquet_work_per_speed(system, speeds, lift: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """Estimated work of a Floquet analysis at each speed and its steps per period (:func:`floquet_work`)."""
    from ..solve.floquet.coefficients import GRID_CACHE_SIZE, grid_values
    from ..solve.floquet.exponents import estimated_cost
    from ..solve.floquet.transition import DOP8

    steps, rows = estimated_cost(system, speeds, lift)
    n = system.size
    # a grid too fine to keep has its coefficient matrices formed again for every
    # speed and every pass, which costs about four times the steps themselves
    fresh = grid_values(n, steps, len(DOP8.c)) > GRID_CACHE_SIZE
    per_step = (2 * n / _WORK_STATE) ** 2 * np.where(fresh, 5.0, 1.0)
    moving = np.asarray(speeds) > 0
    return (steps + _PER_SPEED * moving) * per_step + _EIG_PER_STEP * rows**3, steps


def floquet_work(system, speeds, repeats: float = 1.0, lift: bool = True) -> tuple[float, np.ndarray]:
    """Estimated work of Floquet analyses at ``speeds``
    (:func:`groundres.solve.floquet.exponents.estimated_cost`).

    Returns
    -------
    work : float
        In steps of a 12-state system, for ``repeats`` analyses of every speed;
        a lifted matrix of L rows counts as the eigenvalue problem's L^3 flops.
    steps : ndarray (n_s,)
        Estimated integration steps over one (reduced) period at each speed.
    """
    each, steps = floquet_work_per_speed(system, speeds, lift)
    return float(repeats * each.sum()), steps


def check_floquet_work(
    work: float, steps, speeds, what: str = "this sweep", speed_unit=("rad/s", 1.0), time_invariant=None
) -> None:
    """Refuse Floquet work above :data:`FLOQUET_WORK_LIMIT`, with the estimate and what to change.

    ``speed_unit`` (name, rad/s per unit) names speeds as the case does;
    ``time_invariant`` says whether the case has a time-invariant form (then
    method = 'auto' is advised), None if not known.
    """
    if work <= FLOQUET_WORK_LIMIT:
        return
    speeds = np.asarray(speeds, dtype=float)
    i = int(np.argmax(steps))
    advice = {
        True: "; this case has a time-invariant form: method = 'auto' analyses it in seconds",
        False: "",
        None: ", or method = 'auto' where the case has a time-invariant form",
    }[time_invariant]
    raise ModelRangeError(
        f"[sweep] Floquet analysis of {what} needs an estimated {work:.2g} integration steps "
        f"(in steps of a 12-state system; {len(speeds)} speeds, up to {steps[i]:.3g} steps per period "
        f"at {speed_text(speeds[i], speed_unit)}), above the limit of {FLOQUET_WORK_LIMIT:.2g} "
        "(a few minutes): use fewer points or start the sweep higher (the steps per period grow as "
        "1/speed)" + advice
    )


#: Work [steps of a 12-state system] one Floquet analysis below the sweep's
#: first turning speed may cost while a range's start is followed down to rest
#: (some twenty such analyses at most: well inside the work limit).
REST_BUDGET = FLOQUET_WORK_LIMIT / 50
#: Halvings of the first turning speed tried below it, at most (2^-40: round-off).
REST_HALVINGS = 40


def lowest_periodic_speed(system, speeds, probe) -> float:
    """Lowest speed [rad/s] a Floquet analysis looks at between rest and the
    first turning speed of the sweep and its grid, where a range is open there
    (:func:`groundres.assess.stability.find_ranges`): the slowest of first / 2^k whose
    analysis costs at most :data:`REST_BUDGET` (the cost grows as 1/speed)."""
    grid = np.union1d(speeds, probe)
    moving = grid[grid > 0]
    if not len(moving):
        return 0.0
    first = float(moving.min())
    w = first * 2.0 ** -np.arange(1, REST_HALVINGS + 1)
    work, _ = floquet_work_per_speed(system, w, lift=False)
    ok = np.flatnonzero(work <= REST_BUDGET)
    return float(w[ok[-1]]) if len(ok) else first
