"""Shared fixtures: small cases.

The blade equations are package code (groundres/symbolic/generated_*.py);
tests/test_codegen.py derives them afresh and checks the committed modules.
"""

import os

import pytest

os.environ.setdefault("MPLBACKEND", "Agg")

from groundres import Blade, Body, Case, Rotor, Sweep  # noqa: E402

# Hammond (1974) blade and hub, SI (see src/groundres/cases/hammond-1974.toml).
HAMMOND_BLADE = dict(blade_mass=94.9, blade_static_moment=289.1, blade_inertia=1084.7, hinge_offset=0.3048)
HAMMOND_HUB = dict(
    mass_x=8026.6,
    mass_y=3283.6,
    stiffness_x=1240481.8,
    stiffness_y=1240481.8,
    damping_x=51078.7,
    damping_y=25539.35,
)

#: The Hammond (1974) rotor (all dampers working) on its hub as a case file.
HAMMOND_TOML = """
title = "test"
[rotor]
blades = 4
hinge_offset = 0.3048
blade_mass = 94.9
blade_static_moment = 289.1
blade_inertia = 1084.7
lag_stiffness = 0.0
lag_damping = 4067.5
[body]
dofs = ["x", "y"]
mass_x = 8026.6
mass_y = 3283.6
stiffness_x = 1240481.8
stiffness_y = 1240481.8
damping_x = 51078.7
damping_y = 25539.35
[sweep]
start = 0.5
stop = 40.0
points = 60
unit = "rad/s"
"""

# A pitch-roll body (helicopter on its gear, pivot 1.8 m below the hub).
PITCH_ROLL = dict(
    inertia_pitch=2.5e4,
    inertia_roll=9e3,
    stiffness_pitch=4e6,
    stiffness_roll=2e6,
    damping_pitch=2e4,
    damping_roll=1e4,
    hub_height=1.8,
)


def make_case(n_blades=4, flap=False, dofs=("x", "y"), sweep=(1.0, 40.0, 200), blade=None, body=None):
    blade_kw = {**HAMMOND_BLADE, "lag_damping": 4067.5, **(blade or {})}
    body_kw = {**HAMMOND_HUB, **(body or {})}
    return Case(
        Rotor.uniform(n_blades, Blade(**blade_kw), flap=flap),
        Body(dofs=dofs, **body_kw),
        Sweep(*sweep),
        title="test case",
    )


@pytest.fixture
def hammond_case():
    return make_case()
