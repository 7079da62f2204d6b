"""An independent model of a helicopter on its landing gear, with lag damper rods.

Written from the physics alone, to check groundres on cases with damper rods
(blade-to-hub, blade-to-blade, blade-to-next-but-one) and rigid bodies on gear
legs. It does NOT import groundres: it reads the case TOML itself.

How it works (deliberately unlike groundres, which derives per-blade harmonic
matrices symbolically and uses multiblade / rotating transforms):

1. The WHOLE system's kinetic energy T, potential V and Rayleigh dissipation D
   are written numerically from positions and velocities of the blade line
   masses (T_blade = 1/2 m |A'|^2 + S A'.B' + 1/2 I |B'|^2, A the hinge, B the
   unit span vector, both in inertial axes), of the body (modal: diagonal; rigid:
   1/2 mass |G'|^2 + 1/2 w.J.w), of the rod ends (length l, V = k/2 (l - l0)^2,
   D = c/2 (dl/dt)^2) and of the gear leg points.
2. They are evaluated in a hand-written second-order forward-mode automatic
   differentiation (``Jet``: value, gradient, Hessian) over all coordinates q
   and rates u, about q = u = 0, at rotor speed Omega = 1 for a given azimuth psi.
   The velocity of every point is linear in (u, Omega), so at speed Omega
       T = T2(u, u) + Omega T1(u, q) + Omega^2 T0(q, q)       (to second order)
   and Lagrange's equations linearised read
       M q'' + C q' + K q = 0,
       M = d2T/du du,   G1 = d2T/du dq,   H0 = d2T/dq dq      (at Omega = 1)
       C = Omega (dM/dpsi + G1 - G1^T) + d2D/du du
       K = Omega^2 (dG1/dpsi - H0) + d2V/dq dq + d2D/du dq
   (the terms constant in q, a forcing by an unbalanced rotor, do not change
   stability and are dropped).
3. M, G1, H0, ... are sampled at 16 azimuths and represented by their Fourier
   series in psi (the rotor enters through cos and sin of the blade azimuths, so
   the series stop at the second harmonic; ``check_fourier`` verifies this at
   random azimuths); dM/dpsi and dG1/dpsi come from the series.
4. Stability: Floquet theory. The transition matrix of the first-order system
   over one period 2 pi / Omega is integrated with scipy's DOP853 (rtol 1e-11),
   and the largest real part is max ln|mu| / T over its multipliers mu.
5. Unstable ranges: a coarse scan of the sweep, then Brent's method on each sign
   change of (largest real part - (1e-6 Omega + 1e-9)) to 1e-6 relative.

Conventions (given, not derived): x forward, y left, z up; rotor counter-
clockwise from above; blade k at psi_k = Omega t + 2 pi (k - 1) / N; body
orientation R = R_z(yaw) R_x(roll) R_y(-pitch); hub at (hub_x, hub_y,
hub_height) in body axes, turning about body z; blade span R_z(-lag) R_y(-flap)
e_x in the blade's hub axes; rod points in the blade's own axes (span, leading
edge, up), or on the hub in blade k's hub axes at rest.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

# ----------------------------------------------------------------------------
# Second-order forward-mode automatic differentiation
# ----------------------------------------------------------------------------


class Jet:
    """A scalar function of m variables to second order about 0: value, gradient, Hessian."""

    __slots__ = ("v", "g", "h")

    def __init__(self, v, g, h):
        self.v = v
        self.g = g
        self.h = h

    @staticmethod
    def variable(i: int, m: int) -> Jet:
        g = np.zeros(m)
        g[i] = 1.0
        return Jet(0.0, g, np.zeros((m, m)))

    def __add__(self, o):
        if isinstance(o, Jet):
            return Jet(self.v + o.v, self.g + o.g, self.h + o.h)
        if o == 0.0:
            return self
        return Jet(self.v + o, self.g, self.h)

    __radd__ = __add__

    def __neg__(self):
        return Jet(-self.v, -self.g, -self.h)

    def __sub__(self, o):
        return self + (-o)

    def __rsub__(self, o):
        return (-self) + o

    def __mul__(self, o):
        if isinstance(o, Jet):
            outer = np.outer(self.g, o.g)
            return Jet(
                self.v * o.v, self.v * o.g + o.v * self.g, self.v * o.h + o.v * self.h + outer + outer.T
            )
        if o == 0.0:
            return 0.0
        return Jet(self.v * o, self.g * o, self.h * o)

    __rmul__ = __mul__

    def __truediv__(self, o):
        if isinstance(o, Jet):
            return self * o.reciprocal()
        return self * (1.0 / o)

    def _chain(self, f0, f1, f2):
        return Jet(f0, f1 * self.g, f1 * self.h + f2 * np.outer(self.g, self.g))

    def reciprocal(self):
        v = self.v
        return self._chain(1.0 / v, -1.0 / v**2, 2.0 / v**3)


def sin(a):
    if isinstance(a, Jet):
        s, c = math.sin(a.v), math.cos(a.v)
        return a._chain(s, c, -s)
    return math.sin(a)


def cos(a):
    if isinstance(a, Jet):
        s, c = math.sin(a.v), math.cos(a.v)
        return a._chain(c, -s, -c)
    return math.cos(a)


def sqrt(a):
    if isinstance(a, Jet):
        r = math.sqrt(a.v)
        return a._chain(r, 0.5 / r, -0.25 / r**3)
    return math.sqrt(a)


# 3-vectors and 3x3 matrices as nested lists of floats / Jets (zeros stay plain 0.0).


def madd(*ms):
    return [[sum((m[i][j] for m in ms), 0.0) for j in range(3)] for i in range(3)]


def mmul(a, b):
    return [[a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j] for j in range(3)] for i in range(3)]


def mscale(s, a):
    return [[s * a[i][j] for j in range(3)] for i in range(3)]


def mT(a):
    return [[a[j][i] for j in range(3)] for i in range(3)]


def mvec(a, v):
    return [a[i][0] * v[0] + a[i][1] * v[1] + a[i][2] * v[2] for i in range(3)]


def vadd(*vs):
    return [sum((v[i] for v in vs), 0.0) for i in range(3)]


def vsub(a, b):
    return [a[i] - b[i] for i in range(3)]


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def rot_x(a):
    c, s = cos(a), sin(a)
    return [[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]]


def drot_x(a):
    c, s = cos(a), sin(a)
    return [[0.0, 0.0, 0.0], [0.0, -s, -c], [0.0, c, -s]]


def rot_y(a):
    c, s = cos(a), sin(a)
    return [[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]]


def drot_y(a):
    c, s = cos(a), sin(a)
    return [[-s, 0.0, c], [0.0, 0.0, 0.0], [-c, 0.0, -s]]


def rot_z(a):
    c, s = cos(a), sin(a)
    return [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]


def drot_z(a):
    c, s = cos(a), sin(a)
    return [[-s, -c, 0.0], [c, -s, 0.0], [0.0, 0.0, 0.0]]


# ----------------------------------------------------------------------------
# The case, read from its TOML text
# ----------------------------------------------------------------------------

BODY_DOFS = ("x", "y", "z", "pitch", "roll", "yaw")
BLADE_KEYS = (
    "hinge_offset",
    "blade_mass",
    "blade_static_moment",
    "blade_inertia",
    "lag_stiffness",
    "lag_damping",
    "flap_stiffness",
    "flap_damping",
)
ROD_AHEAD = {"blade-to-hub": None, "blade-to-blade": 1, "blade-to-next-but-one": 2}


@dataclass
class Rod:
    blade: int  # 1-based start blade
    ahead: int | None  # other end on blade + ahead, or on the hub (None)
    damping: float
    stiffness: float
    start: tuple
    end: tuple


@dataclass
class Model:
    n_blades: int
    flap: bool
    blades: list  # dicts of BLADE_KEYS, blade 1 first
    rods: list
    dofs: tuple
    rigid: bool
    body: dict
    gear: list = field(default_factory=list)
    hub: tuple = (0.0, 0.0, 0.0)
    sweep: tuple = (0.0, 1.0, 200)  # start, stop [rad/s], points

    @property
    def coordinates(self) -> list:
        names = list(self.dofs) + [f"lag{k}" for k in range(1, self.n_blades + 1)]
        if self.flap:
            names += [f"flap{k}" for k in range(1, self.n_blades + 1)]
        return names


def parse(text: str) -> Model:
    data = tomllib.loads(text)
    rotor, body, sweep = data["rotor"], data["body"], data["sweep"]
    n = int(rotor["blades"])
    base = {k: float(rotor.get(k, 0.0)) for k in BLADE_KEYS}
    blades = [dict(base) for _ in range(n)]
    for entry in rotor.get("blade", []):
        for k, v in entry.items():
            if k != "index":
                blades[entry["index"] - 1][k] = float(v)

    layouts, overrides = {}, {}
    for entry in rotor.get("damper", []):
        values = {k: v for k, v in entry.items() if k not in ("kind", "blade")}
        if "blade" in entry:
            overrides[(entry["kind"], entry["blade"])] = values
        else:
            layouts[entry["kind"]] = values
    specs = []
    for kind, values in layouts.items():
        for k in range(1, n + 1):
            specs.append((kind, k, {**values, **overrides.pop((kind, k), {})}))
    specs += [(kind, k, v) for (kind, k), v in overrides.items()]
    rods = [
        Rod(
            blade=k,
            ahead=ROD_AHEAD[kind],
            damping=float(v["damping"]),
            stiffness=float(v.get("stiffness", 0.0)),
            start=(float(v["start_x"]), float(v["start_y"]), float(v.get("start_z", 0.0))),
            end=(float(v["end_x"]), float(v["end_y"]), float(v.get("end_z", 0.0))),
        )
        for kind, k, v in specs
    ]

    dofs = tuple(d for d in BODY_DOFS if d in body.get("dofs", ["x", "y"]))
    rigid = "mass" in body or "gear" in body
    values = {k: float(v) for k, v in body.items() if k not in ("dofs", "gear")}
    gear = [{k: float(v) for k, v in leg.items()} for leg in body.get("gear", [])]
    hub = (values.get("hub_x", 0.0), values.get("hub_y", 0.0), values.get("hub_height", 0.0))

    unit = sweep.get("unit", "rad/s")
    scale = {"rad/s": 1.0, "rpm": 2 * math.pi / 60, "Hz": 2 * math.pi}[unit]
    sw = (float(sweep["start"]) * scale, float(sweep["stop"]) * scale, int(sweep.get("points", 200)))
    return Model(n, bool(rotor.get("flap", False)), blades, rods, dofs, rigid, values, gear, hub, sw)


def load(path) -> Model:
    return parse(Path(path).read_text(encoding="utf-8-sig"))


# ----------------------------------------------------------------------------
# Energies of the whole system at one azimuth, as jets in (q, u), Omega = 1
# ----------------------------------------------------------------------------


def energies(model: Model, psi: float, omega: float = 1.0):
    """T, V, D of the whole system as Jets over z = (q, u) about z = 0, at rotor azimuth psi."""
    names = model.coordinates
    n = len(names)
    m = 2 * n
    q = {name: Jet.variable(i, m) for i, name in enumerate(names)}
    u = {name: Jet.variable(n + i, m) for i, name in enumerate(names)}

    def coord(name):
        return (q[name], u[name]) if name in q else (0.0, 0.0)

    (x, xd), (y, yd), (zz, zd) = coord("x"), coord("y"), coord("z")
    (th, thd), (ph, phd), (ch, chd) = coord("pitch"), coord("roll"), coord("yaw")

    r = [x, y, zz]
    rd = [xd, yd, zd]
    Rz, Rx, Ry = rot_z(ch), rot_x(ph), rot_y(-th)
    R = mmul(mmul(Rz, Rx), Ry)
    Rd = madd(
        mscale(chd, mmul(mmul(drot_z(ch), Rx), Ry)),
        mscale(phd, mmul(mmul(Rz, drot_x(ph)), Ry)),
        mscale(-thd, mmul(mmul(Rz, Rx), drot_y(-th))),
    )
    hub_c = vadd(r, mvec(R, list(model.hub)))
    hub_cd = vadd(rd, mvec(Rd, list(model.hub)))

    T = 0.0
    V = 0.0
    D = 0.0

    # --- body
    b = model.body
    if model.rigid:
        c = [b.get("centre_x", 0.0), b.get("centre_y", 0.0), b.get("centre_z", 0.0)]
        Gd = vadd(rd, mvec(Rd, c))
        T = T + 0.5 * b["mass"] * dot(Gd, Gd)
        W = mmul(mT(R), Rd)  # skew(angular velocity in body axes)
        w = [W[2][1], W[0][2], W[1][0]]
        J = [
            [b.get("inertia_xx", 0.0), b.get("inertia_xy", 0.0), b.get("inertia_xz", 0.0)],
            [b.get("inertia_xy", 0.0), b.get("inertia_yy", 0.0), b.get("inertia_yz", 0.0)],
            [b.get("inertia_xz", 0.0), b.get("inertia_yz", 0.0), b.get("inertia_zz", 0.0)],
        ]
        T = T + 0.5 * dot(w, mvec(J, w))
        for leg in model.gear:
            p = [leg["position_x"], leg["position_y"], leg["position_z"]]
            P = vadd(r, mvec(R, p))
            Pd = vadd(rd, mvec(Rd, p))
            for a, ax in enumerate("xyz"):
                dp = P[a] - p[a]
                V = V + 0.5 * leg.get(f"stiffness_{ax}", 0.0) * dp * dp
                D = D + 0.5 * leg.get(f"damping_{ax}", 0.0) * Pd[a] * Pd[a]
    else:
        for d in model.dofs:
            key = f"mass_{d}" if d in ("x", "y", "z") else f"inertia_{d}"
            T = T + 0.5 * b[key] * u[d] * u[d]
            V = V + 0.5 * b.get(f"stiffness_{d}", 0.0) * q[d] * q[d]
            D = D + 0.5 * b.get(f"damping_{d}", 0.0) * u[d] * u[d]

    # --- blades
    N = model.n_blades
    frames = []  # per blade: hub frame, its rate, blade frame, its rate, hinge, hinge rate
    for k in range(1, N + 1):
        bl = model.blades[k - 1]
        pk = psi + 2 * math.pi * (k - 1) / N
        Hk = mmul(R, rot_z(pk))
        Hkd = madd(mmul(Rd, rot_z(pk)), mscale(omega, mmul(R, drot_z(pk))))
        zeta, zetad = q[f"lag{k}"], u[f"lag{k}"]
        beta, betad = (q[f"flap{k}"], u[f"flap{k}"]) if model.flap else (0.0, 0.0)
        Lz, Ly = rot_z(-zeta), rot_y(-beta)
        Bk = mmul(Hk, mmul(Lz, Ly))
        Bkd = madd(
            mmul(Hkd, mmul(Lz, Ly)),
            mscale(-zetad, mmul(Hk, mmul(drot_z(-zeta), Ly))),
            mscale(-betad, mmul(Hk, mmul(Lz, drot_y(-beta)))),
        )
        e = [bl["hinge_offset"], 0.0, 0.0]
        A = vadd(hub_c, mvec(Hk, e))
        Ad = vadd(hub_cd, mvec(Hkd, e))
        span_d = [Bkd[0][0], Bkd[1][0], Bkd[2][0]]
        T = (
            T
            + 0.5 * bl["blade_mass"] * dot(Ad, Ad)
            + bl["blade_static_moment"] * dot(Ad, span_d)
            + 0.5 * bl["blade_inertia"] * dot(span_d, span_d)
        )
        V = V + 0.5 * bl["lag_stiffness"] * zeta * zeta
        D = D + 0.5 * bl["lag_damping"] * zetad * zetad
        if model.flap:
            V = V + 0.5 * bl["flap_stiffness"] * beta * beta
            D = D + 0.5 * bl["flap_damping"] * betad * betad
        frames.append((Hk, Hkd, Bk, Bkd, A, Ad))

    # --- damper rods
    for rod in model.rods:
        Hk, Hkd, Bk, Bkd, A, Ad = frames[rod.blade - 1]
        s = list(rod.start)
        P1 = vadd(A, mvec(Bk, s))
        P1d = vadd(Ad, mvec(Bkd, s))
        if rod.ahead is None:
            P2 = vadd(hub_c, mvec(Hk, list(rod.end)))
            P2d = vadd(hub_cd, mvec(Hkd, list(rod.end)))
        else:
            j = (rod.blade - 1 + rod.ahead) % N
            _, _, Bj, Bjd, Aj, Ajd = frames[j]
            P2 = vadd(Aj, mvec(Bj, list(rod.end)))
            P2d = vadd(Ajd, mvec(Bjd, list(rod.end)))
        d = vsub(P1, P2)
        dd = vsub(P1d, P2d)
        length = sqrt(dot(d, d))
        rate = dot(d, dd) / length
        l0 = length.v
        stretch = length - l0
        V = V + 0.5 * rod.stiffness * stretch * stretch
        D = D + 0.5 * rod.damping * rate * rate
    return T, V, D


def _hessian(f, m):
    if isinstance(f, Jet):
        return f.h
    return np.zeros((m, m))


def matrices_at(model: Model, psi: float) -> dict:
    """Second derivatives at Omega = 1: M, G1, H0 (kinetic), Kv (potential), Cd, Kd (dissipation)."""
    T, V, D = energies(model, psi)
    n = len(model.coordinates)
    hT, hV, hD = _hessian(T, 2 * n), _hessian(V, 2 * n), _hessian(D, 2 * n)
    return {
        "M": hT[n:, n:],
        "G1": hT[n:, :n],  # d2T / du_i dq_j
        "H0": hT[:n, :n],
        "Kv": hV[:n, :n],
        "Cd": hD[n:, n:],
        "Kd": hD[n:, :n],
    }


# ----------------------------------------------------------------------------
# Periodic matrices as Fourier series in psi
# ----------------------------------------------------------------------------

N_PSI = 16


class PeriodicSystem:
    """M(psi), C(psi), K(psi) for any rotor speed, from Fourier series in psi."""

    def __init__(self, model: Model):
        self.model = model
        self.n = len(model.coordinates)
        psis = 2 * np.pi * np.arange(N_PSI) / N_PSI
        samples = [matrices_at(model, p) for p in psis]
        self.coef = {}
        for key in samples[0]:
            X = np.array([s[key] for s in samples])  # (N_PSI, n, n)
            c = np.fft.fft(X, axis=0) / N_PSI
            c = c[: N_PSI // 2 + 1].copy()
            c[1 : N_PSI // 2] *= 2.0
            self.coef[key] = c  # X(psi) = Re sum_h c_h exp(i h psi)
        self.harm = np.arange(N_PSI // 2 + 1)
        # truncation: harmonics beyond those with content must vanish (checked in check_fourier)
        scale = max(np.abs(c).max() for c in self.coef.values())
        self.high_harmonics = max(np.abs(c[5:]).max() for c in self.coef.values()) / scale
        hmax = 4
        self.h = self.harm[: hmax + 1]
        c = {k: v[: hmax + 1] for k, v in self.coef.items()}
        # at Omega = 1: C = C1 + Cd, K = K2 + Kv + Kd (C1 scales as Omega, K2 as Omega^2)
        ih = 1j * self.h[:, None, None]
        self.cM = c["M"]
        self.cC1 = ih * c["M"] + c["G1"] - np.transpose(c["G1"], (0, 2, 1))
        self.cC0 = c["Cd"]
        self.cK2 = ih * c["G1"] - c["H0"]
        self.cK0 = c["Kv"] + c["Kd"]

    def _eval(self, c, psi):
        e = np.exp(1j * self.h * psi)
        return np.real(np.tensordot(e, c, axes=(0, 0)))

    def mck(self, psi: float, omega: float):
        M = self._eval(self.cM, psi)
        C = omega * self._eval(self.cC1, psi) + self._eval(self.cC0, psi)
        K = omega**2 * self._eval(self.cK2, psi) + self._eval(self.cK0, psi)
        return M, C, K

    def check_fourier(self, psis=(0.3, 1.7, 4.1)) -> float:
        """Largest relative mismatch of the truncated series against direct evaluation."""
        worst = self.high_harmonics
        # a matrix that is zero but for round-off (e.g. d2D/du dq) is measured against the others
        floor = 1e-9 * max(np.abs(c).max() for c in self.coef.values())
        for p in psis:
            direct = matrices_at(self.model, p)
            for key in direct:
                series = self._eval(self.coef[key][: len(self.h)], p)
                scale = max(np.abs(self.coef[key]).max(), floor)
                worst = max(worst, np.abs(series - direct[key]).max() / scale)
        return worst

    # ---- Floquet

    def monodromy(self, omega: float, rtol: float = 1e-11, atol: float = 1e-12) -> np.ndarray:
        n = self.n

        def rhs(t, y):
            M, C, K = self.mck(omega * t, omega)
            Phi = y.reshape(2 * n, 2 * n)
            acc = -np.linalg.solve(M, K @ Phi[:n] + C @ Phi[n:])
            return np.concatenate([Phi[n:], acc]).ravel()

        period = 2 * np.pi / omega
        sol = solve_ivp(rhs, (0.0, period), np.eye(2 * n).ravel(), method="DOP853", rtol=rtol, atol=atol)
        if not sol.success:
            raise RuntimeError(sol.message)
        return sol.y[:, -1].reshape(2 * n, 2 * n)

    def largest_real_part(self, omega: float, **kw) -> float:
        mu = np.linalg.eigvals(self.monodromy(omega, **kw))
        return float(np.max(np.log(np.abs(mu)))) * omega / (2 * np.pi)


# ----------------------------------------------------------------------------
# Unstable ranges
# ----------------------------------------------------------------------------


def threshold(omega: float) -> float:
    """Growth below this is round-off, not instability (the criterion groundres states)."""
    return 1e-6 * omega + 1e-9


def unstable_ranges(system: PeriodicSystem, start: float, stop: float, points: int = 48, xtol_rel=1e-6):
    """Unstable speed ranges [rad/s] in [start, stop]: a scan of ``points`` speeds, then Brent's
    method on each sign change of (largest real part - threshold), to ``xtol_rel`` of the speed.

    A range open at either end of the sweep is reported to that end. A sweep from rest is
    scanned from stop / 100 (a Floquet period needs Omega > 0; one at rest is endless)."""
    speeds = np.linspace(max(start, stop / 100.0), stop, points)

    def f(w):
        return system.largest_real_part(w) - threshold(w)

    values = [f(w) for w in speeds]
    ranges = []
    lo = start if values[0] > 0 else None
    for i in range(1, len(speeds)):
        a, b = speeds[i - 1], speeds[i]
        if (values[i - 1] > 0) != (values[i] > 0):
            root = brentq(f, a, b, xtol=xtol_rel * b, rtol=1e-12)
            if values[i] > 0:
                lo = root
            else:
                ranges.append((lo, root))
                lo = None
    if lo is not None:
        ranges.append((lo, stop))
    return [(float(a), float(b)) for a, b in ranges]
