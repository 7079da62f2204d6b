"""Nonlinear lag damper laws (issue 26): the case file's [rotor.lag_damper], the laws' moments and
their describing functions.

The describing functions are checked by a second route that shares nothing with them: the law's
moment integrated over one cycle of theta = A cos(w t) in time (the trapezoidal rule on a fine
grid, spectrally exact for smooth periodic integrands; the friction link's slider followed step
by step, exactly for the ideal slider and by implicit Euler for the regularised one). The
dissipated energy W = -int M dtheta gives c_eq = W / (pi w A^2), the in-phase part k_eq.
"""

import math
import tomllib

import numpy as np
import pytest

from groundres import analyze
from groundres.errors import CaseError
from groundres.model import describing
from groundres.model.casefile import case_text
from groundres.model.damper_laws import DamperLaw
from groundres.model.schema import parse_case

LAWS = {
    "linear": {"law": "linear", "damping": 4067.5, "stiffness": 2000.0},
    "bilinear": {
        "law": "bilinear",
        "damping": 4067.5,
        "relief_moment": 700.0,
        "damping_after_relief": 406.75,
    },
    "progressive": {
        "law": "bilinear",
        "damping": 800.0,
        "relief_moment": 100.0,
        "damping_after_relief": 5000.0,
    },
    "friction": {
        "law": "friction",
        "friction_moment": 300.0,
        "regularisation_velocity": 0.005,
        "damping": 50.0,
    },
    "tanh": {"law": "tanh", "tanh_moment": 406.75, "tanh_rate": 10.0, "stiffness": 1500.0},
    "friction-link": {
        "law": "friction-link",
        "friction_moment": 300.0,
        "link_stiffness": 1.0e5,
        "regularisation_damping": 5.0,
        "damping": 40.0,
        "stiffness": 100.0,
    },
}


NO_DAMPING = {"lag_damping = 4067.5           # [N m s/rad]": ""}


def _case(name: str, replace: dict, extra: str = ""):
    text, source = case_text(name)
    for old, new in replace.items():
        assert old in text
        text = text.replace(old, new)
    text += extra
    return parse_case(tomllib.loads(text), source, text)


def _cycle(law: DamperLaw, amplitude: float, frequency: float, points: int = 20000, cycles: int = 3):
    """(c_eq, k_eq) from the law's moment over the last of ``cycles`` cycles of A cos(w t), in
    time (the second route of the module docstring)."""
    phase = np.linspace(0.0, 2 * np.pi * cycles, cycles * points + 1)
    angle = amplitude * np.cos(phase)
    rate = -amplitude * frequency * np.sin(phase)
    if law.has_slider:
        slider = np.zeros_like(angle)
        dt = (phase[1] - phase[0]) / frequency
        k, force, c = law.link_stiffness, law.friction_moment, law.regularisation_damping
        s = 0.0
        for i in range(1, len(phase)):  # implicit Euler: s_new = s + dt (|k (theta - s_new)| - F)+ sign / c
            m = k * (angle[i] - s)
            if abs(m) > force:
                excess = (abs(m) - force) / (1 + dt * k / c)
                s += np.sign(m) * dt * excess / c
            slider[i] = s
        moment = law.moment(angle, rate, slider)
    else:
        moment = law.moment(angle, rate)
    last = slice(-points - 1, None)
    p = phase[last] - phase[last][0]
    c_w = -np.trapezoid(moment[last] * np.sin(p), p) / (np.pi * amplitude)  # (theta' = -A w sin)
    k_eq = np.trapezoid(moment[last] * np.cos(p), p) / (np.pi * amplitude)
    return c_w / frequency, k_eq


# -- the case file ---------------------------------------------------------------------------


def test_a_linear_law_reproduces_lag_damping_exactly():
    """[rotor.lag_damper] law = "linear" is today's lag_damping, to the bit, whatever the
    method: every root of the sweep, the stable verdict and the exact minimum lag damping."""
    plain = _case("hammond-1974-one-damper", {})
    law = _case(
        "hammond-1974-one-damper",
        {
            "lag_damping = 4067.5           # [N m s/rad]": "",
            "[[rotor.blade]]": '[rotor.lag_damper]\nlaw = "linear"\ndamping = 4067.5\n\n[[rotor.blade]]',
            "lag_damping = 0.0              # the inoperative damper": 'lag_damper = "failed"',
        },
    )
    assert law.rotor.blades == plain.rotor.blades
    a, b = analyze(plain), analyze(law)
    np.testing.assert_array_equal(a.modes.eigenvalue, b.modes.eigenvalue)
    assert a.stability.unstable_ranges == b.stability.unstable_ranges


def test_the_linear_analysis_of_a_law_is_its_small_motion_linearisation():
    """A friction link is stuck for small motion: its blades get the link's spring and only the
    viscous part; a bilinear damper its first slope; friction its regularisation's slope."""
    for name, keys in LAWS.items():
        table = "\n".join(f"{k} = {v!r}".replace("'", '"') for k, v in keys.items())
        case = _case("hammond-1974", NO_DAMPING, f"\n[rotor.lag_damper]\n{table}\n")
        law = DamperLaw.from_keys(keys)
        c0, k0 = law.small_motion()
        for blade, entry in zip(case.rotor.blades, case.rotor.lag_laws):
            assert entry.law == law
            assert (blade.lag_damping, blade.lag_stiffness) == (c0, 0.0 + k0)
        assert case.rotor.nonlinear == (name != "linear")
    expected = {
        "bilinear": (4067.5, 0.0),
        "friction": (50.0 + 300.0 / 0.005, 0.0),
        "tanh": (406.75 * 10.0, 1500.0),
        "friction-link": (40.0, 100.0 + 1.0e5),
    }
    for name, values in expected.items():
        assert DamperLaw.from_keys(LAWS[name]).small_motion() == pytest.approx(values, rel=1e-15)


def test_a_blade_overrides_the_layout_with_keys_or_a_law_of_its_own():
    table = (
        '[rotor.lag_damper]\nlaw = "bilinear"\ndamping = 4067.5\nrelief_moment = 700.0\n'
        "damping_after_relief = 406.75\n"
    )
    extra = (
        "\n[[rotor.blade]]\nindex = 2\nlag_damper = { relief_moment = 350.0 }\n"
        '\n[[rotor.blade]]\nindex = 3\nlag_damper = { law = "linear", damping = 1000.0 }\n'
        '\n[[rotor.blade]]\nindex = 4\nlag_damper = "failed"\n'
    )
    case = _case("hammond-1974", NO_DAMPING, "\n" + table + extra)
    laws = case.rotor.lag_laws
    assert laws[0].law.relief_moment == 700.0 and laws[1].law.relief_moment == 350.0
    assert laws[1].law.damping_after_relief == 406.75
    assert laws[2].law.law == "linear" and case.rotor.blades[2].lag_damping == 1000.0
    assert laws[3] is None and case.rotor.blades[3].lag_damping == 0.0
    equivalent = case.rotor.equivalent([1.0, 2.0, 3.0, 4.0], [10.0, 20.0, 30.0, 40.0])
    assert [b.lag_damping for b in equivalent.blades] == [1.0, 2.0, 3.0, 0.0]
    assert [b.lag_stiffness for b in equivalent.blades] == [10.0, 20.0, 30.0, 0.0]


@pytest.mark.parametrize(
    "table, message",
    [
        ('law = "viscous"\ndamping = 1.0', "law = 'viscous': must be one of"),
        (
            'law = "bilinear"\ndamping = 1.0\nrelief_moment = 2.0',
            "damping_after_relief = (missing): is required",
        ),
        (
            'law = "bilinear"\ndamping = 0.0\nrelief_moment = 2.0\ndamping_after_relief = 1.0',
            "damping = 0.0: must be > 0",
        ),
        (
            'law = "friction"\nfriction_moment = 300.0\nregularisation_velocity = 0.0',
            "regularisation_velocity = 0.0",
        ),
        ('law = "friction"\nfriction_moment = -1.0\nregularisation_velocity = 0.1', "friction_moment = -1.0"),
        (
            'law = "tanh"\ntanh_moment = 1.0\ntanh_rate = 1.0\nrelief_moment = 3.0',
            "relief_moment = 3.0: does not apply",
        ),
        ('law = "linear"\ndamping = "a lot"', "damping = 'a lot': must be a number"),
        ('law = "linear"\ndampnig = 1.0', "did you mean 'damping'"),
        (
            'law = "table"\namplitudes = [1.0, 0.5]\nstorage_stiffness = [1.0, 1.0]\n'
            "loss_stiffness = [1.0, 1.0]\nreference_frequency = 5.0",
            "amplitudes = [1.0, 0.5]: must be > 0 and increasing",
        ),
        (
            'law = "table"\namplitudes = [0.5, 1.0]\nstorage_stiffness = [1.0]\n'
            "loss_stiffness = [1.0, 1.0]\nreference_frequency = 5.0",
            "storage_stiffness = 1: must list one value per amplitude (2)",
        ),
    ],
)
def test_bad_laws_are_refused_naming_the_key(table, message):
    with pytest.raises(CaseError) as err:
        _case("hammond-1974", NO_DAMPING, f"\n[rotor.lag_damper]\n{table}\n")
    assert message in str(err.value)
    assert str(err.value).startswith("[rotor.lag_damper] ") or "in [rotor.lag_damper]" in str(err.value)


def test_a_law_beside_lag_damping_or_a_blade_without_a_law_is_refused():
    law = '[rotor.lag_damper]\nlaw = "linear"\ndamping = 1.0\n'
    with pytest.raises(
        CaseError, match=r"\[rotor\] lag_damping = 4067.5: a \[rotor.lag_damper\] law replaces it"
    ):
        _case("hammond-1974", {}, "\n" + law)
    with pytest.raises(CaseError, match=r'index = 1: lag_damping = 0.0: .*lag_damper = "failed"'):
        _case("hammond-1974", NO_DAMPING, "\n" + law + "\n[[rotor.blade]]\nindex = 1\nlag_damping = 0.0\n")
    with pytest.raises(CaseError, match=r"index = 1: lag_damper has no law"):
        _case("hammond-1974", {}, "\n[[rotor.blade]]\nindex = 1\nlag_damper = { damping = 3.0 }\n")
    with pytest.raises(CaseError, match=r"\[\[rotor.blade\]\] index = 1: lag_damper.relief_moment = -3.0"):
        _case(
            "hammond-1974",
            {},
            '\n[[rotor.blade]]\nindex = 1\nlag_damper = { law = "bilinear", damping = 1.0, '
            "relief_moment = -3.0, damping_after_relief = 0.5 }\n",
        )


def test_a_failed_damper_without_laws_is_lag_damping_zero():
    a = _case("hammond-1974", {}, "\n[[rotor.blade]]\nindex = 1\nlag_damping = 0.0\n")
    b = _case("hammond-1974", {}, '\n[[rotor.blade]]\nindex = 1\nlag_damper = "failed"\n')
    assert a.rotor == b.rotor


# -- the laws ---------------------------------------------------------------------------------


@pytest.mark.parametrize("name", sorted(LAWS))
def test_every_law_is_odd_and_continuous(name):
    law = DamperLaw.from_keys(LAWS[name])
    rng = np.random.default_rng(3)
    angle, rate, slider = rng.normal(0, 0.05, 200), rng.normal(0, 0.5, 200), rng.normal(0, 0.01, 200)
    np.testing.assert_allclose(
        law.moment(-angle, -rate, -slider), -law.moment(angle, rate, slider), atol=1e-9
    )
    if law.law == "bilinear":  # (continuous through the knee)
        knee = law.relief_rate
        near = law.rate_moment(np.array([knee * (1 - 1e-12), knee * (1 + 1e-12)]))
        assert abs(near[1] - near[0]) < 1e-8 * law.relief_moment
    if law.has_slider:  # (the slider moves only beyond the break-out moment)
        stuck = law.friction_moment / law.link_stiffness
        assert law.slider_rate(0.999 * stuck, 0.0) == 0.0 and law.slider_rate(1.001 * stuck, 0.0) > 0


# -- describing functions -----------------------------------------------------------------------


@pytest.mark.parametrize("name", sorted(LAWS))
@pytest.mark.parametrize("amplitude_deg", [0.02, 0.3, 2.0, 8.0])
def test_describing_functions_equal_the_cycle_integrated_from_the_law(name, amplitude_deg):
    """c_eq and k_eq against the energy and in-phase work of one cycle in time (module
    docstring). Tolerance: the trapezoidal rule on 20000 points is exact to round-off for the
    smooth laws; the bilinear knee's kink and the slider's switching leave O(h^2) = 1e-7;
    the regularised slider (implicit Euler) slips above the ideal one by c_reg A w / F of its
    moment, which bounds the difference (measured: at most 0.7 of it here)."""
    law = DamperLaw.from_keys(LAWS[name])
    amplitude, frequency = math.radians(amplitude_deg), 17.0
    c_eq, k_eq = describing.equivalent(law, amplitude, frequency)
    c_time, k_time = _cycle(law, amplitude, frequency)
    scale = max(abs(float(c_eq)), 1.0)
    if law.has_slider:  # (the ideal slider's describing function; the regularised law slips above it)
        overshoot = float(describing.link_regularisation(law, amplitude, frequency))
        assert overshoot < 0.05
        assert abs(c_time - c_eq) <= overshoot * abs(float(c_eq)) + 1e-6 * scale
        assert abs(k_time - k_eq) <= overshoot * abs(float(k_eq)) + 1e-6 * abs(float(k_eq))
    else:
        assert c_time == pytest.approx(float(c_eq), rel=1e-6)
        assert k_time == pytest.approx(float(k_eq), rel=1e-6, abs=1e-6)


def test_the_ideal_link_converges_to_the_regularised_one_as_its_regularisation_vanishes():
    keys = dict(LAWS["friction-link"], damping=0.0, stiffness=0.0)
    amplitude, frequency = math.radians(1.0), 17.0
    errors = []
    for c_reg in (5.0, 0.5, 0.05):
        law = DamperLaw.from_keys(dict(keys, regularisation_damping=c_reg))
        ideal = np.array(describing.equivalent(law, amplitude, frequency), float)
        errors.append(np.abs(np.array(_cycle(law, amplitude, frequency, points=40000)) - ideal) / ideal)
    errors = np.array(errors)
    assert (errors[1:] < 0.2 * errors[:-1] + 1e-6).all()  # (first order in c_reg)


def test_closed_forms_of_the_describing_functions():
    """Bilinear: the saturation function; Coulomb: 4 F / (pi V); the stuck link: k_l and no
    damping; every rate law's small-amplitude limit its slope at rest."""
    bilinear = DamperLaw.from_keys(LAWS["bilinear"])
    w = 20.0
    v_r = bilinear.relief_rate
    for r in (0.1, 0.5, 0.9):
        c, _ = describing.equivalent(bilinear, v_r / r / w, w)
        n = 2 / math.pi * (math.asin(r) + r * math.sqrt(1 - r * r))
        assert float(c) == pytest.approx(406.75 + (4067.5 - 406.75) * n, rel=1e-14)
    assert float(describing.equivalent(bilinear, 0.5 * v_r / w, w)[0]) == 4067.5
    friction = DamperLaw.from_keys(dict(LAWS["friction"], regularisation_velocity=1e-9, damping=0.0))
    for v in (0.01, 0.1, 1.0):
        c, _ = describing.equivalent(friction, v / w, w)
        assert float(c) == pytest.approx(4 * 300.0 / (math.pi * v), rel=1e-6)
    link = DamperLaw.from_keys(LAWS["friction-link"])
    stuck = 0.999 * link.friction_moment / link.link_stiffness
    assert tuple(map(float, describing.equivalent(link, stuck, w))) == (40.0, 100.0 + 1.0e5)
    for name in ("friction", "tanh", "bilinear", "linear", "friction-link"):
        law = DamperLaw.from_keys(LAWS[name])
        small = tuple(map(float, describing.equivalent(law, 1e-12, w)))
        assert small == pytest.approx(law.small_motion(), rel=1e-9)


def test_the_table_law_interpolates_and_holds_its_ends():
    law = DamperLaw.from_keys(
        {
            "law": "table",
            "amplitudes": [0.5, 1.0, 4.0],
            "storage_stiffness": [9.0e4, 6.0e4, 3.0e4],
            "loss_stiffness": [3.0e4, 3.6e4, 1.5e4],
            "reference_frequency": 3.0,
        }
    )
    w = 2 * math.pi * 3.0
    assert law.reference_frequency == pytest.approx(w)
    c, k = describing.equivalent(law, np.radians([0.1, 0.75, 2.5, 9.0]), w)
    np.testing.assert_allclose(k, [9.0e4, 7.5e4, 4.5e4, 3.0e4], rtol=1e-12)
    np.testing.assert_allclose(c * w, [3.0e4, 3.3e4, 2.55e4, 1.5e4], rtol=1e-12)
    assert list(describing.outside_table(law, np.radians([0.1, 0.75, 9.0]))) == [True, False, True]
    assert law.small_motion() == pytest.approx((3.0e4 / w, 9.0e4))
    assert not law.simulable
    with pytest.raises(ValueError, match="friction link"):
        law.moment(0.0, 0.0)


# -- groundres damper -----------------------------------------------------------------------------


def _cli(*args):
    from click.testing import CliRunner

    from groundres.cli import main

    return CliRunner().invoke(main, list(args))


def test_the_damper_command_draws_and_tabulates_every_law(tmp_path):
    text, _ = case_text("hammond-1974")
    text = text.replace("lag_damping = 4067.5           # [N m s/rad]", "")
    text += (
        '\n[rotor.lag_damper]\nlaw = "bilinear"\ndamping = 4067.5\nrelief_moment = 700.0\n'
        "damping_after_relief = 406.75\n"
        '\n[[rotor.blade]]\nindex = 2\nlag_damper = { law = "friction-link", friction_moment = 300.0, '
        "link_stiffness = 1.0e5, regularisation_damping = 5.0 }\n"
        '\n[[rotor.blade]]\nindex = 4\nlag_damper = "failed"\n'
    )
    path = tmp_path / "laws.toml"
    path.write_text(text)
    out = tmp_path / "out"
    result = _cli("damper", str(path), "--out", str(out), "--frequency", "20")
    assert result.exit_code == 0, result.output
    assert "blades 1, 3: law 'bilinear', at 20 rad/s" in result.output
    assert (
        "blade 2: law 'friction-link'" in result.output and "blade 4: no lag damper (failed)" in result.output
    )
    import json

    report = json.loads((out / "damper.json").read_text())
    bilinear = report["laws"][0]
    c, _ = describing.equivalent(
        DamperLaw.from_keys(LAWS["bilinear"]), np.radians(bilinear["amplitude"]), 20.0
    )
    np.testing.assert_allclose(bilinear["equivalent_damping"], c, rtol=1e-14)  # (deg and back)
    assert {p.name for p in out.iterdir()} == {"damper.png", "damper.json", "case.toml", "provenance.json"}


@pytest.mark.parametrize(
    "args, message",
    [
        (("hammond-1974",), "its blades have no [rotor.lag_damper] law"),
        (("--amplitudes", "5:1"), "--amplitudes '5:1': must be 1e-6 <= START < STOP <= 90"),
        (("--amplitudes", "1e-320:1"), "--amplitudes '1e-320:1': must be 1e-6 <= START"),
        (("--amplitudes", "x"), "--amplitudes 'x': must be START:STOP"),
        (("--frequency", "-3"), "--frequency = -3.0: must be a finite number > 0"),
    ],
)
def test_the_damper_command_refuses_bad_input_with_exit_2(tmp_path, args, message):
    text, _ = case_text("hammond-1974")
    path = tmp_path / "laws.toml"
    path.write_text(
        text.replace("lag_damping = 4067.5           # [N m s/rad]", "") + "\n[rotor.lag_damper]\n"
        'law = "tanh"\ntanh_moment = 400.0\ntanh_rate = 10.0\n'
    )
    case = args[0] if args[0] == "hammond-1974" else str(path)
    rest = args[1:] if args[0] == "hammond-1974" else args
    result = _cli("damper", case, "--out", str(tmp_path / "out"), *rest)
    assert result.exit_code == 2, result.output
    assert message in result.output
    assert "Traceback" not in result.output and not (tmp_path / "out").exists()


def test_studies_vary_a_law_key_and_fail_a_blade_s_law_whole():
    """rotor.lag_damper.relief_moment is a study key like any other; a blade failed by a study
    under a law has lag_damper = "failed" (no damper), not lag_damping = 0 (refused beside a law)."""
    from groundres.studies.grid import numeric_keys, varied_case

    assert "rotor.lag_damper.relief_moment" in numeric_keys()
    text, _ = case_text("hammond-1974")
    text = text.replace("lag_damping = 4067.5           # [N m s/rad]", "") + (
        '\n[rotor.lag_damper]\nlaw = "bilinear"\ndamping = 4067.5\nrelief_moment = 700.0\n'
        "damping_after_relief = 406.75\n"
    )
    data = tomllib.loads(text)
    case = varied_case(data, {"rotor.lag_damper.relief_moment": 350.0}, "blade 2")
    assert [e and e.law.relief_moment for e in case.rotor.lag_laws] == [350.0, None, 350.0, 350.0]
    assert case.rotor.blades[1].lag_damping == 0.0


@pytest.mark.parametrize("name", sorted(LAWS) + ["plain-friction", "undamped-linear", "table"])
def test_the_damper_command_draws_every_law(tmp_path, name):
    """(tanh, friction without a viscous part and a linear law without damping crashed the drawing:
    the bilinear knee was computed for every law)."""
    keys = {
        "plain-friction": {"law": "friction", "friction_moment": 300.0, "regularisation_velocity": 0.01},
        "undamped-linear": {"law": "linear", "damping": 0.0},
        "table": {
            "law": "table",
            "amplitudes": [0.5, 1.0],
            "storage_stiffness": [9.0e4, 6.0e4],
            "loss_stiffness": [3.0e4, 3.6e4],
            "reference_frequency": 3.0,
        },
    }.get(name, LAWS.get(name))
    table = "\n".join(f"{k} = {v!r}".replace("'", '"') for k, v in keys.items()) + "\n"
    text, _ = case_text("hammond-1974")
    path = tmp_path / "laws.toml"
    path.write_text(
        text.replace("lag_damping = 4067.5           # [N m s/rad]", "") + "\n[rotor.lag_damper]\n" + table
    )
    result = _cli("damper", str(path), "--out", str(tmp_path / "out"))
    assert result.exit_code == 0, result.output
    assert (tmp_path / "out" / "damper.png").exists()


def test_a_table_law_is_the_same_damper_in_the_linear_analysis_and_in_its_describing_function():
    """The linear analysis takes the table at its smallest amplitude, viscous at the reference
    frequency; so does the describing function at any frequency (they disagreed: the cycles
    said 'grows' where the linear analysis beside them said stable)."""
    law = DamperLaw.from_keys(
        {
            "law": "table",
            "amplitudes": [0.5, 1.0],
            "storage_stiffness": [9.0e4, 6.0e4],
            "loss_stiffness": [2.0e4, 2.0e4],
            "reference_frequency": 1.0,
        }
    )
    for w in (1.0, 6.2832, 40.0):
        assert tuple(map(float, describing.equivalent(law, 1e-6, w))) == pytest.approx(
            law.small_motion(), rel=1e-15
        )


@pytest.mark.parametrize(
    "extra, message",
    [
        (
            "\n[limit_cycle]\namplitude_min = 5e-324\n",
            "[limit_cycle] amplitude_min = 5e-324: must be a finite number from 1e-6 to 90",
        ),
        (
            "\n[limit_cycle]\namplitude_max = 1e-300\n",
            "[limit_cycle] amplitude_max = 1e-300: must be above amplitude_min",
        ),
        (
            '\n[rotor.lag_damper]\nlaw = "bilinear"\ndamping = 1.0\nrelief_moment = 1.0\n'
            "damping_after_relief = 1e308\n",
            "damping_after_relief = 1e+308: must be at most 1e+12",
        ),
        (
            '\n[rotor.lag_damper]\nlaw = "friction"\nfriction_moment = 1e6\n'
            "regularisation_velocity = 1e-10\n",
            "regularisation_velocity = 1e-10: gives a slope at rest of 1e+16",
        ),
        (
            '\n[rotor.lag_damper]\nlaw = "table"\namplitudes = [0.5, 1.0]\nstorage_stiffness = [1.0, 1.0]\n'
            "loss_stiffness = [1.0, 1.0]\nreference_frequency = -1.0\n",
            "reference_frequency = -1.0: must be > 0",
        ),
        (
            "\n[[rotor.blade]]\nindex = 2\nlag_damping = 100.0\n"
            'lag_damper = { law = "tanh", tanh_moment = 1.0, tanh_rate = 1.0 }\n',
            "index = 2: lag_damping = 100.0:",
        ),
    ],
)
def test_out_of_range_law_and_search_values_are_refused_naming_the_key(extra, message):
    with pytest.raises(CaseError) as err:
        _case("hammond-1974", NO_DAMPING if "rotor.lag_damper" in extra else {}, extra)
    assert message in str(err.value)
