"""Pictures a reader can compare: phasors on a common physical scale with translations and
rotations apart, readable animations with a side view, continuous rotating-frame diagrams of
periodic cases, and a simulation picture that says what its amplitudes mean."""

import math

import numpy as np
import pytest
from PIL import Image

from groundres import analyze, load_case, simulate
from groundres.plotting.animation import mode_animation, write_gif
from groundres.plotting.phasors import phasor_diagram


@pytest.fixture(scope="module")
def pitch_roll():
    """soft-inplane-pitch-roll at 249 rpm: body roll grows (about 1.7 1/s, inside its unstable range)."""
    case = load_case("soft-inplane-pitch-roll")
    w = 249 * 2 * math.pi / 60
    result = analyze(case, speeds=np.union1d(case.sweep.speeds, [w]), lag_damping_search=False)
    return result.mode("body roll", w), result.mode("regressive lag", w)


def _titles(fig):
    return [ax.get_title() for ax in fig.axes]


def test_phasors_put_translations_and_rotations_on_panels_of_their_own_with_units():
    case = load_case("light-helicopter-skids")  # (x, y, pitch and roll: both kinds of body motion)
    w = float(case.sweep.speeds[len(case.sweep.speeds) // 2])
    result = analyze(case, speeds=np.union1d(case.sweep.speeds, [w]), lag_damping_search=False)
    fig = phasor_diagram(result.mode(result.labels[0], w))
    titles = _titles(fig)
    assert "body translation, nonrotating axes [m]" in titles
    assert "body rotation, nonrotating axes [rad]" in titles
    for ax in fig.axes:
        unit = "m" if "translation" in ax.get_title() else "rad"
        assert ax.get_xlabel() == f"real part [{unit}]" and ax.get_ylabel() == f"imaginary part [{unit}]"
    # (no panel mixes metres and radians: the translations' panel holds x, y only)
    for ax in fig.axes:
        names = {t.get_text() for t in ax.texts if t.get_text()}
        if "translation" in ax.get_title():
            assert names <= {"x", "y", "x_r", "y_r"} | {t for t in names if t.startswith("too small")}


def test_a_common_scale_draws_every_panel_to_one_physical_size(pitch_roll):
    shape, _ = pitch_roll
    fig = phasor_diagram(shape, scale="common")
    limits = {ax.get_xlim() for ax in fig.axes}
    assert len(limits) == 1  # (one scale: hub rotation and lag amplitude compare as drawn)
    largest = max(abs(p.displacement) for f in ("nonrotating", "rotating") for p in shape.phasors(f))
    assert limits.pop()[1] == pytest.approx(1.45 * largest)
    own = phasor_diagram(shape)  # (the default: each panel to its own largest)
    assert len({ax.get_xlim() for ax in own.axes}) > 1
    with pytest.raises(ValueError, match="scale='both': must be one of panel, common"):
        phasor_diagram(shape, scale="both")


def test_no_phasor_label_piles_on_the_origin_and_round_off_is_not_printed(pitch_roll):
    _, lag = pitch_roll
    fig = phasor_diagram(lag, scale="common")
    for ax in fig.axes:
        radius = ax.get_xlim()[1] / 1.45
        for text in ax.texts:
            if text.get_transform() is ax.transData:
                x, y = text.get_position()
                assert math.hypot(x, y) >= 0.04 * radius, text.get_text()
            else:  # (the note of the small ones: amplitudes, never round-off)
                assert "e-1" not in text.get_text(), text.get_text()


def test_the_animation_is_wide_fast_and_shows_the_centre_of_mass_and_a_side_view(pitch_roll, tmp_path):
    shape, _ = pitch_roll
    anim = mode_animation(shape, speed_text="249 rpm")
    titles = _titles(anim.fig)
    assert "side view (pitch)" in titles and "rear view (roll)" in titles
    for ax in anim.fig.axes:  # (the rotor's centre of mass drawn above everything else)
        tops = sorted(ax.get_children(), key=lambda a: a.get_zorder())
        marker = [a for a in ax.lines if a.get_color() == "#ff9f1c" and a.get_marker() == "o"]
        assert marker and marker[0].get_zorder() >= max(a.get_zorder() for a in tops if a is not ax.patch) - 1
    path = tmp_path / "mode.gif"
    write_gif(anim, path)
    with Image.open(path) as gif:
        assert gif.size[0] >= 1000 and gif.n_frames == 40
    assert anim.fig.texts[0].get_fontsize() >= 11  # (the status line: text of normal size)


@pytest.mark.parametrize("name", ["hammond-1974-one-damper", "hammond-1974"])
def test_rotating_frame_diagrams_are_as_continuous_as_the_nonrotating_ones(name):
    """A label's rotating-frame frequency is |f +- Omega| of its nonrotating one on the line's
    harmonic: between two speeds it moves by at most the nonrotating step plus the speed step
    (x 2.5 for the fold at zero and round-off). Before, body x broke off at 0.67 ref (a step of
    about 240 speed steps where the nonrotating one was 23) and body y jumped from 0.45 to
    1.95 per rev at 0.94 ref, in the Floquet and the multiblade analyses alike."""
    result = analyze(load_case(name), frame="rotating", lag_damping_search=False)
    m, w = result.modes, result.rotor_speed
    rotating = np.abs(np.diff(m.frequency_rotating, axis=0))
    nonrotating = np.abs(np.diff(m.frequency_nonrotating, axis=0))
    jumps = np.argwhere(rotating > nonrotating + 2.5 * np.diff(w)[:, None])
    assert not len(jumps), [(result.labels[j], w[i]) for i, j in jumps]
    assert not m.harmonic_change_rotating.any()


def test_the_simulation_picture_says_the_model_is_linear_and_scales_to_the_disturbance():
    sim = simulate(load_case("hammond-1974-one-damper"), 26.7, duration=4.0)
    fig = sim.plot()
    title = fig._suptitle.get_text()
    assert "Linear model" in title and "relative to the initial disturbance" in title
    assert "x = 0.01 m" in title and "lag1 = 0.01 rad" in title
    labels = [ax.get_ylabel() for ax in fig.axes]
    assert labels[0] == "amplitude / d [-]" and "lag angle / d [-]" in labels
    line = fig.axes[2].lines[0]  # (lag of blade 1, which starts at d: it reads 1 at t = 0)
    assert line.get_ydata()[0] == pytest.approx(1.0)
