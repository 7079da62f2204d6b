"""Mode shapes: phasors, rate phases, whirl, files."""

import json
from dataclasses import replace

import numpy as np
import pytest
import xarray as xr
from click.testing import CliRunner

from conftest import make_case
from groundres import analyze, load_case
from groundres.cli import main


@pytest.fixture(scope="module")
def undamped():
    return analyze(load_case("hammond-undamped"))


@pytest.mark.parametrize("frame", ["nonrotating", "rotating"])
@pytest.mark.parametrize("speed", [8.0, 20.5, 38.0])
def test_neutral_modes_have_rates_exactly_90_degrees_ahead(undamped, frame, speed):
    """Outside the unstable ranges of an undamped system every root is neutral."""
    for label in undamped.labels:
        shape = undamped.mode(label, speed)
        assert abs(shape.eigenvalue.real) < 1e-9 * speed
        for p in shape.phasors(frame):
            if abs(p.displacement) > 1e-6:
                assert p.rate_lead == pytest.approx(90.0, abs=1e-6), (label, p.name)
                assert p.in_phase == pytest.approx(0.0, abs=1e-8)


@pytest.mark.parametrize("frame", ["nonrotating", "rotating"])
def test_growing_mode_rate_has_an_in_phase_part_re_over_abs_lambda(undamped, frame):
    i = np.argmin(np.abs(undamped.rotor_speed - 26.6))
    label = undamped.labels[int(np.argmax(undamped.real_part[i]))]
    shape = undamped.mode(label, 26.6)
    assert shape.unstable
    rows = [p for p in shape.phasors(frame) if abs(p.displacement) > 1e-6]
    root = rows[0].rate / rows[0].displacement  # the root in this frame
    assert root.real == pytest.approx(shape.eigenvalue.real, rel=1e-12)
    for p in rows:
        assert p.in_phase == pytest.approx(root.real / abs(root), abs=1e-9)
        assert 0 < p.rate_lead < 90


def test_regressive_lag_whirl_directions():
    """nu < 1: the regressive lag mode whirls with the rotor, below 1/rev (Coleman and
    Feingold 1958); nu > 1 (stiff in-plane): against the rotor."""
    soft = analyze(load_case("hammond-1974"))
    for w in (8.0, 35.0):
        com = soft.mode("regressive lag", w).whirl()["centre_of_mass"]
        assert com["direction"].startswith("forward")
        assert com["frequency"] < soft.mode("regressive lag", w).rotor_speed
    stiff = analyze(load_case("stiff-inplane"))
    w = stiff.rotor_speed[len(stiff.rotor_speed) // 3]
    shape = stiff.mode("regressive lag", w)
    nu = stiff.case.rotor.blades[0].lag_frequency(shape.rotor_speed)
    assert nu > 1
    assert shape.whirl()["centre_of_mass"]["direction"].startswith("backward")
    lag = shape.whirl()["lag"]
    assert lag["backward_whirl"]["amplitude"] > lag["forward_whirl"]["amplitude"]


def test_phases_do_not_depend_on_the_eigenvector_scaling(undamped):
    shape = undamped.mode("regressive lag", 26.6)
    scaled = replace(shape, harmonics=shape.harmonics * 2.7 * np.exp(1.1j))
    for frame in ("nonrotating", "rotating"):
        for a, b in zip(shape.phasors(frame), scaled.phasors(frame)):
            assert a.displacement == pytest.approx(b.displacement, abs=1e-12)
            assert a.rate == pytest.approx(b.rate, rel=1e-12, abs=1e-12)
    com_a, com_b = shape.whirl()["centre_of_mass"], scaled.whirl()["centre_of_mass"]
    assert com_a["forward_amplitude"] == pytest.approx(com_b["forward_amplitude"], rel=1e-12)


def test_periodic_mode_phasors():
    """Floquet mode (failed damper) inside its unstable range: the same rate relation."""
    case = make_case(sweep=(20.0, 34.0, 30))
    case = replace(case, rotor=case.rotor.with_blade(1, lag_damping=0.0))
    result = analyze(case)
    assert result.method == "floquet"
    i = int(np.argmax(result.real_part.max(1)))
    label = result.labels[int(np.argmax(result.real_part[i]))]
    shape = result.mode(label, result.rotor_speed[i])
    assert shape.unstable
    lam = shape.eigenvalue
    for p in shape.phasors("nonrotating"):
        if abs(p.displacement) > 1e-6:
            assert p.in_phase == pytest.approx(lam.real / abs(lam), abs=1e-9)
    motion = shape.motion(np.linspace(0, 1, 5))
    assert motion["lag"].shape == (5, 4) and motion["hub"].shape == (5, 2)


def test_mode_shapes_are_in_the_netcdf(tmp_path):
    out = tmp_path / "o"
    result = CliRunner().invoke(main, ["run", "hammond-1974", "--out", str(out)])
    assert result.exit_code == 0, result.output
    ds = xr.open_dataset(out / "modes.nc")
    assert ds["shape_real"].dims == ("speed", "mode", "coordinate")
    assert "lag_1c" in list(ds["coordinate"].values)
    ds.close()


def test_phasors_command(tmp_path):
    out = tmp_path / "p"
    result = CliRunner().invoke(
        main, ["phasors", "soft-inplane-pitch-roll", "--speed", "250", "--out", str(out)]
    )
    assert result.exit_code == 0, result.output
    report = json.loads((out / "phasors.json").read_text())
    worst = next(iter(report))  # the least stable mode comes first
    slug = worst.replace(" ", "-")
    assert (out / f"phasors_{slug}.png").exists() and (out / f"mode_{slug}.gif").exists()
    entry = report[worst]
    assert entry["unstable"]
    assert {"nonrotating", "rotating"} == set(entry["phasors"])
    names = [p["coordinate"] for p in entry["phasors"]["rotating"]]
    assert "lag blade 1" in names and "flap blade 3" in names
    assert (out / "phasors.csv").read_text().startswith("mode,frame,coordinate")
    bad = CliRunner().invoke(main, ["phasors", "soft-inplane", "--speed", "250", "--mode", "lag", "--no-gif"])
    assert bad.exit_code == 2 and "'lag'" in bad.output and "regressive lag" in bad.output
