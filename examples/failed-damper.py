"""A failed lag damper: Floquet analysis, checked by a time simulation at one rotor speed.

The Hammond (1974) rotor on its anisotropic hub with the lag damper of blade 1
inoperative (seed paper Figure 10). One blade unlike the others on an
anisotropic hub leaves periodic coefficients in every frame, so groundres
uses Floquet theory. Inside the unstable range the periodic equations are
then integrated in time from a small disturbance: the motion must grow at the
real part of the largest Floquet exponent. Last, the "smeared damper"
approximation (the three working dampers spread over four blades, which keeps
the equations time-invariant) shows what the failure would look like without
Floquet theory.

Run: python examples/failed-damper.py [OUTPUT_DIR]
(writes coleman.png and simulation.png into OUTPUT_DIR, by default
groundres-out/examples/failed-damper)
"""

import dataclasses
import math
import sys
from pathlib import Path

import numpy as np

import groundres

RPM = 60 / (2 * math.pi)  # rpm per rad/s
SPEED = 27.0  # [rad/s] (258 rpm), inside the unstable range


def ranges_in_rpm(result):
    """The unstable ranges of a result as text, in rpm."""
    ranges = result.stability.unstable_ranges
    return ", ".join(f"{a * RPM:.1f} to {b * RPM:.1f} rpm" for a, b in ranges) or "none"


out = Path(sys.argv[1] if len(sys.argv) > 1 else "groundres-out/examples/failed-damper")
out.mkdir(parents=True, exist_ok=True)
case = groundres.load_case("hammond-1974-one-damper")

# Floquet analysis over the case's sweep, with the speed to simulate added to it.
result = groundres.analyze(case, speeds=np.append(case.sweep.speeds, SPEED), lag_damping_search=False)
print(f"{case.title} [{result.method}]")
print(f"  unstable ranges: {ranges_in_rpm(result)}")
i = int(np.argmin(abs(result.rotor_speed - SPEED)))
j = int(np.argmax(result.real_part[i]))
floquet = result.real_part[i, j]  # [1/s]
print(f"  at {SPEED * RPM:.0f} rpm the {result.labels[j]} mode has Floquet real part {floquet:.4f} 1/s")

# The same equations in blade coordinates, integrated in time (DOP853), from 1 cm of hub
# displacement and 0.01 rad of lag on blade 1, over 80 revolutions.
start = {"x": 0.01, "y": 0.01, "lag1": 0.01}  # [m], [rad]
sim = groundres.simulate(case, SPEED, duration=80 * 2 * math.pi / SPEED, initial=start)
growth = sim.growth_rate()  # slope of the log amplitude, once a revolution, over the second half
print(f"  time simulation grows at {growth:.4f} 1/s ({100 * (growth / floquet - 1):+.2f} %)")

# The smeared damper: every blade with 3/4 of the damper, identical blades, eigenvalues.
blade = case.rotor.blades[1]  # a blade whose damper works
smeared_blade = dataclasses.replace(blade, lag_damping=0.75 * blade.lag_damping)
smeared = dataclasses.replace(case, rotor=groundres.Rotor.uniform(4, smeared_blade))
approx = groundres.analyze(smeared, lag_damping_search=False)
print(
    f"  smeared damper, {smeared_blade.lag_damping:.0f} N m s/rad on every blade ({approx.method}): "
    f"unstable ranges: {ranges_in_rpm(approx)}"
)

result.plot().savefig(out / "coleman.png", dpi=110)
sim.plot().savefig(out / "simulation.png", dpi=110)  # (the growth measured and predicted on it)
print(f"Wrote {out}")
