"""groundres' unstable rotor-speed ranges against an independent model, on cases
with lag damper rods and rigid bodies on gear legs.

The independent model (tests/reference/independent_rods_gear.py) does not import
groundres: it reads the case TOML itself, writes the whole system's kinetic
energy, potential and dissipation from positions and velocities, linearises
them with its own second-order automatic differentiation, and finds stability
by Floquet theory (scipy DOP853, rtol 1e-11) for EVERY case, where groundres
uses multiblade eigen-analysis for identical blades.

Tolerances
----------
* Range ends: each within 0.2 % of the speed (the acceptance criterion). The
  model finds its ends to 1e-6 relative (Brent's method on a scan), so the
  tolerance is spent on groundres' side.
* Largest real part at a few speeds: 1e-6 1/s + 1e-6 relative. The model's
  multipliers carry errors of the order of the integrator's rtol 1e-11 times the
  transition matrix's size, i.e. an error of about 1e-11 / T in ln|mu| / T
  (T = 2 pi / Omega < 1.2 s here), far below 1e-6 1/s; the allowance is for
  groundres' own transition tolerance and root finding. It equals the growth
  threshold (1e-6 1/s per rad/s) at about 1 rad/s, so a disagreement this small
  could not change a stability verdict except at a range end.

Cases: the shipped cases with [[rotor.damper]] or [[body.gear]], plus variants
written here: a 3-bladed rotor with blade-to-next-but-one rods and one failed
(sweep in Hz); rods whose ends lie at different distances from their hinges and
off the blade plane, with rod stiffness, blade-to-hub and blade-to-blade rods,
flap, pitch and roll, hub offset and one heavier blade; a rigid body on four gear
legs with its centre of mass off the pivot, products of inertia, all six body
dofs and flap; and a 5-bladed rotor with next-but-one rods, one failed, on a
rigid body (x, y, roll, yaw).
"""

import time
import tomllib
from pathlib import Path

import independent_rods_gear as ind  # (beside this file: pytest puts this folder on the path)
import numpy as np
import pytest

from groundres import analyze, load_case
from groundres.model.casefile import shipped_cases

RANGE_RTOL = 2e-3  # acceptance: each range end within 0.2 % of the speed
REAL_ATOL = 1e-6  # [1/s]
REAL_RTOL = 1e-6
SCAN_POINTS = 48  # speeds of the model's coarse scan (the ends are then found by Brent's method)

THREE_BLADES_NEXT_BUT_ONE_ONE_FAILED = """
title = "three blades, next-but-one rods, one failed"
[rotor]
blades = 3
hinge_offset = 0.3048
blade_mass = 94.9
blade_static_moment = 289.1
blade_inertia = 1084.7
[[rotor.damper]]
kind = "blade-to-next-but-one"
damping = 20000.0
start_x = 0.35
start_y = 0.1
end_x = 0.35
end_y = -0.1
[[rotor.damper]]
kind = "blade-to-next-but-one"
blade = 2
damping = 0.0
[body]
dofs = ["x", "y"]
mass_x = 8026.6
mass_y = 3283.6
stiffness_x = 1240481.8
stiffness_y = 1240481.8
damping_x = 51078.7
damping_y = 25539.35
[sweep]
start = 0.8
stop = 6.0
points = 80
unit = "Hz"
"""

OFFSET_RODS_FLAP_PITCH_ROLL = """
title = "rods at different distances, z offsets, stiffness, flap, pitch and roll, one heavier blade"
[rotor]
blades = 4
hinge_offset = 0.3048
blade_mass = 94.9
blade_static_moment = 289.1
blade_inertia = 1084.7
lag_stiffness = 2000.0
flap = true
flap_stiffness = 5000.0
flap_damping = 300.0
[[rotor.blade]]
index = 3
blade_mass = 97.0
blade_static_moment = 296.0
[[rotor.damper]]
kind = "blade-to-hub"
damping = 15000.0
stiffness = 20000.0
start_x = 0.45
start_y = 0.12
start_z = 0.05
end_x = 0.1
end_y = 0.3
end_z = -0.04
[[rotor.damper]]
kind = "blade-to-blade"
damping = 8000.0
start_x = 0.5
start_y = 0.1
start_z = 0.03
end_x = 0.3
end_y = -0.08
[[rotor.damper]]
kind = "blade-to-blade"
blade = 4
damping = 0.0
[body]
dofs = ["x", "y", "pitch", "roll"]
hub_height = 1.8
hub_x = 0.2
hub_y = -0.05
mass_x = 8026.6
mass_y = 3283.6
stiffness_x = 1240481.8
stiffness_y = 1240481.8
damping_x = 21078.7
damping_y = 15539.35
inertia_pitch = 20000.0
inertia_roll = 6000.0
stiffness_pitch = 6.0e6
stiffness_roll = 2.0e6
damping_pitch = 6.0e4
damping_roll = 2.0e4
[sweep]
start = 5.0
stop = 45.0
points = 80
unit = "rad/s"
"""

RIGID_ON_GEAR_ALL_DOFS_FLAP = """
title = "rigid body on four gear legs, centre off the pivot, products of inertia, flap, z and yaw"
[rotor]
blades = 4
hinge_offset = 0.2
blade_mass = 30.0
blade_static_moment = 75.0
blade_inertia = 260.0
flap = true
flap_damping = 50.0
[[rotor.damper]]
kind = "blade-to-blade"
damping = 5000.0
start_x = 0.3
start_y = 0.08
end_x = 0.3
end_y = -0.08
[body]
dofs = ["x", "y", "z", "pitch", "roll", "yaw"]
hub_height = 1.6
hub_x = 0.1
hub_y = 0.03
mass = 1500.0
inertia_xx = 600.0
inertia_yy = 2500.0
inertia_zz = 2200.0
inertia_xy = 20.0
inertia_xz = 180.0
inertia_yz = -15.0
centre_x = 0.15
centre_y = 0.05
centre_z = 0.4
[[body.gear]]
position_x = 1.0
position_y = 1.1
position_z = -0.9
stiffness_x = 6.0e4
stiffness_y = 5.0e4
stiffness_z = 2.0e5
damping_x = 2000.0
damping_y = 2000.0
damping_z = 3000.0
[[body.gear]]
position_x = 1.0
position_y = -1.1
position_z = -0.9
stiffness_x = 6.0e4
stiffness_y = 5.0e4
stiffness_z = 2.0e5
damping_x = 2000.0
damping_y = 2000.0
damping_z = 3000.0
[[body.gear]]
position_x = -1.2
position_y = 1.1
position_z = -0.9
stiffness_x = 6.0e4
stiffness_y = 5.0e4
stiffness_z = 1.6e5
damping_x = 2000.0
damping_y = 2000.0
damping_z = 3000.0
[[body.gear]]
position_x = -1.2
position_y = -1.1
position_z = -0.9
stiffness_x = 6.0e4
stiffness_y = 5.0e4
stiffness_z = 1.6e5
damping_x = 2000.0
damping_y = 2000.0
damping_z = 3000.0
[sweep]
start = 50.0
stop = 540.0
points = 80
unit = "rpm"
"""

RIGID_ON_GEAR_FIVE_BLADES_ONE_FAILED = """
title = "five blades, next-but-one rods with one failed, rigid body on gear legs"
[rotor]
blades = 5
hinge_offset = 0.2
blade_mass = 30.0
blade_static_moment = 75.0
blade_inertia = 260.0
[[rotor.damper]]
kind = "blade-to-next-but-one"
damping = 6000.0
start_x = 0.32
start_y = 0.06
end_x = 0.25
end_y = -0.09
[[rotor.damper]]
kind = "blade-to-next-but-one"
blade = 4
damping = 0.0
[body]
dofs = ["x", "y", "roll", "yaw"]
hub_height = 1.6
hub_x = 0.1
hub_y = 0.03
mass = 1500.0
inertia_xx = 600.0
inertia_yy = 2500.0
inertia_zz = 2200.0
inertia_xy = 20.0
inertia_xz = 180.0
inertia_yz = -15.0
centre_x = 0.15
centre_y = 0.05
centre_z = 0.4
[[body.gear]]
position_x = 1.0
position_y = 1.1
position_z = -0.9
stiffness_x = 6.0e4
stiffness_y = 5.0e4
stiffness_z = 2.0e5
damping_x = 2000.0
damping_y = 2000.0
damping_z = 3000.0
[[body.gear]]
position_x = 1.0
position_y = -1.1
position_z = -0.9
stiffness_x = 6.0e4
stiffness_y = 5.0e4
stiffness_z = 2.0e5
damping_x = 2000.0
damping_y = 2000.0
damping_z = 3000.0
[[body.gear]]
position_x = -1.2
position_y = 1.1
position_z = -0.9
stiffness_x = 6.0e4
stiffness_y = 5.0e4
stiffness_z = 1.6e5
damping_x = 2000.0
damping_y = 2000.0
damping_z = 3000.0
[[body.gear]]
position_x = -1.2
position_y = -1.1
position_z = -0.9
stiffness_x = 6.0e4
stiffness_y = 5.0e4
stiffness_z = 1.6e5
damping_x = 2000.0
damping_y = 2000.0
damping_z = 3000.0
[sweep]
start = 50.0
stop = 540.0
points = 80
unit = "rpm"
"""

VARIANTS = {
    "three-blades-next-but-one-one-failed": THREE_BLADES_NEXT_BUT_ONE_ONE_FAILED,
    "offset-rods-flap-pitch-roll": OFFSET_RODS_FLAP_PITCH_ROLL,
    "rigid-on-gear-all-dofs-flap": RIGID_ON_GEAR_ALL_DOFS_FLAP,
    "rigid-on-gear-five-blades-one-failed": RIGID_ON_GEAR_FIVE_BLADES_ONE_FAILED,
}


def _shipped_with_rods_or_gear():
    out = []
    for name, text in shipped_cases().items():
        data = tomllib.loads(text)
        if (
            name.startswith("light-helicopter-")
            or "damper" in data.get("rotor", {})
            or "gear" in data.get("body", {})
        ):
            out.append((name, text))
    return out


SHIPPED = _shipped_with_rods_or_gear()
PARAMS = [pytest.param(("shipped", name), id=name) for name, _ in SHIPPED] + [
    pytest.param(("text", name), id=name) for name in VARIANTS
]


def test_the_shipped_inter_blade_cases_are_included():
    names = {name for name, _ in SHIPPED}
    assert {"hammond-interblade", "hammond-interblade-one-failed"} <= names


def _case_path(which, tmp_path) -> Path:
    kind, value = which
    path = tmp_path / f"{value}.toml"
    path.write_text(dict(SHIPPED)[value] if kind == "shipped" else VARIANTS[value], encoding="utf-8")
    return path


def _close(a, b):
    return abs(a - b) <= RANGE_RTOL * abs(b)


@pytest.mark.slow
@pytest.mark.parametrize("which", PARAMS)
def test_unstable_ranges_and_growth_agree(which, tmp_path):
    path = _case_path(which, tmp_path)

    t0 = time.perf_counter()
    result = analyze(load_case(path), lag_damping_search=False)
    theirs = [(float(a), float(b)) for a, b in result.stability.unstable_ranges]
    t1 = time.perf_counter()

    model = ind.load(path)
    system = ind.PeriodicSystem(model)
    # the model's own check: its Fourier series in psi reproduce the matrices at other azimuths
    assert system.check_fourier() < 1e-9
    start, stop, _ = model.sweep
    mine = ind.unstable_ranges(system, start, stop, points=SCAN_POINTS)
    t2 = time.perf_counter()
    report = f"{path.name}: groundres {theirs} ({t1 - t0:.1f} s), model {mine} ({t2 - t1:.1f} s) [rad/s]"
    print(report)

    assert len(mine) == len(theirs), report
    for (a, b), (c, d) in zip(mine, theirs):
        assert _close(a, c) and _close(b, d), report

    # the largest real part at a few speeds: across the sweep and inside each unstable range
    speeds = [start + f * (stop - start) for f in (0.2, 0.5, 0.8)]
    speeds += [0.5 * (c + d) for c, d in theirs]
    speeds = np.array(sorted(speeds))
    at = analyze(load_case(path), speeds=speeds, lag_damping_search=False)
    theirs_re = np.max(at.modes.real_part, axis=1)
    mine_re = np.array([system.largest_real_part(w) for w in speeds])
    text = f"{path.name}: speeds {speeds}, groundres {theirs_re}, model {mine_re} [1/s]"
    print(text)
    np.testing.assert_allclose(mine_re, theirs_re, rtol=REAL_RTOL, atol=REAL_ATOL, err_msg=text)
