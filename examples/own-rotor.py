"""Your own case, written in Python: how much lag damping does a three-bladed rotor need?

A light helicopter's articulated three-bladed rotor (400 rpm) on landing gear
modelled as two modal body degrees of freedom, x and y, each with its damper.
The rotor speed passes both body frequencies on run-up, so the regressive lag
mode is tuned to each body mode once. The case is a TOML text, exactly what a
case file holds (docs/case-files.md); the lag damper is left as a parameter.

Run: python examples/own-rotor.py [OUTPUT_DIR]
(writes my-rotor.toml, with the damper sized, and coleman.png into OUTPUT_DIR,
by default groundres-out/examples/own-rotor; `groundres run OUTPUT_DIR/my-rotor.toml`
analyses the case file again from the command line)
"""

import math
import sys
import tomllib
from pathlib import Path

import groundres

CASE = """
title = "Light helicopter, articulated three-bladed rotor, lag damper {lag_damping:.0f} N m s/rad"

[rotor]
blades = 3
hinge_offset = 0.20            # [m]
blade_mass = 40.0              # [kg]      mass beyond the hinge
blade_static_moment = 110.0    # [kg m]    centre of mass 2.75 m outboard of the hinge
blade_inertia = 400.0          # [kg m^2]  about the hinge
lag_stiffness = 0.0            # articulated: lag frequency sqrt(e S / I) = 0.23 per rev
lag_damping = {lag_damping:<16.1f} # [N m s/rad]

[body]
dofs = ["x", "y"]
mass_x = 1200.0                # [kg], blades excluded
mass_y = 800.0
stiffness_x = 260000.0         # [N/m]: 14 rad/s with the blades' 120 kg
stiffness_y = 370000.0         # [N/m]: 20 rad/s
damping_x = 9200.0             # [N s/m]: about 25 % of critical
damping_y = 9200.0

[sweep]
start = 20.0
stop = 450.0
points = 200
unit = "rpm"
reference = 400.0              # the operating speed: plots show speed / 400 rpm
"""

RPM = 60 / (2 * math.pi)  # rpm per rad/s


def ranges_in_rpm(result):
    """The unstable ranges of a result as text, in rpm."""
    ranges = result.stability.unstable_ranges
    return ", ".join(f"{a * RPM:.0f} to {b * RPM:.0f} rpm" for a, b in ranges) or "none"


def my_case(lag_damping):
    """The case with every blade's lag damper set to ``lag_damping`` [N m s/rad]."""
    text = CASE.format(lag_damping=lag_damping)
    return groundres.parse_case(tomllib.loads(text), source="my-rotor", text=text)


out = Path(sys.argv[1] if len(sys.argv) > 1 else "groundres-out/examples/own-rotor")
out.mkdir(parents=True, exist_ok=True)

# Without a lag damper: where is it unstable, and what do the criteria ask for? (Body damping
# alone destabilises the regressive lag mode of a rotor whose lag frequency is below 1/rev.)
result = groundres.analyze(my_case(0.0))
print(f"no lag damper: unstable ranges {ranges_in_rpm(result)}")
for entry in result.deutsch:  # Deutsch (1946), one line per body mode the lag mode is tuned to
    if entry.tuning_speed is not None:
        print(
            f"Deutsch, body {entry.body_mode} tuned at {entry.tuning_speed * RPM:.0f} rpm: "
            f"{entry.required_lag_damping:.0f} N m s/rad"
        )
exact = result.exact_lag_damping  # from the roots, over the whole sweep
if exact is None:  # (e.g. an undamped body mode tuned inside the sweep)
    sys.exit(f"no lag damper suffices: {result.summary()['lag_damping']['exact_minimum_reason']}")
print(f"exact minimum over the sweep: {exact:.0f} N m s/rad")

# Check the exact value from either side, then size the damper with a 50 % margin.
for factor in (0.9, 1.1):
    check = groundres.analyze(my_case(factor * exact), lag_damping_search=False)
    print(f"{factor:.0%} of it: unstable ranges {ranges_in_rpm(check)}")
design = my_case(round(1.5 * exact, -1))
sized = groundres.analyze(design)
least = sized.summary()["min_damping_ratio"]
print(
    f"sized with 50 % margin: {design.title}\n"
    f"  least damping ratio {least['value']:.3f} ({least['mode']} at {least['speed'] * RPM:.0f} rpm)"
)

(out / "my-rotor.toml").write_text(design.text)
sized.plot(show_damping_ratio=True).savefig(out / "coleman.png", dpi=110)
print(f"Wrote {out}")
