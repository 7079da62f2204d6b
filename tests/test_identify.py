"""Names and frequencies of roots (groundres.modes.identify): the same for every
method, continuous along the sweep, anchored to the time-invariant system as
the dissimilarity vanishes, and true to each mode's content."""

from dataclasses import replace

import numpy as np
import pytest
from scipy.optimize import linear_sum_assignment

from conftest import PITCH_ROLL, make_case
from groundres import analyze, load_case
from groundres.model.mbc import Coordinate
from groundres.modes.participation import label_groups

ISOTROPIC = dict(mass_y=8026.6, damping_y=51078.7)
SWEEP = (3.0, 42.0, 50)


def failed(case, *blades, fraction=0.0):
    """The case with the lag dampers of ``blades`` at ``fraction`` of nominal."""
    rotor = case.rotor
    for b in blades:
        rotor = rotor.with_blade(b, lag_damping=fraction * rotor.blades[b - 1].lag_damping)
    return replace(case, rotor=rotor)


# Cases that have a time-invariant form, so that eigen-analysis and Floquet
# analysis of the untransformed equations must agree root by root.
BOTH_WAYS = {
    "3 blades, anisotropic hub": lambda: make_case(n_blades=3, sweep=SWEEP),
    "4 blades, no damping, anisotropic hub": lambda: make_case(
        blade=dict(lag_damping=0.0), body=dict(damping_x=0.0, damping_y=0.0), sweep=SWEEP
    ),
    "5 blades with flap, anisotropic hub": lambda: make_case(
        n_blades=5, flap=True, blade=dict(flap_stiffness=1e5), sweep=SWEEP
    ),
    "3 blades with flap on x, y, pitch, roll": lambda: make_case(
        n_blades=3,
        flap=True,
        dofs=("x", "y", "pitch", "roll"),
        blade=dict(lag_stiffness=2e5, flap_stiffness=1e5),
        body=PITCH_ROLL,
        sweep=SWEEP,
    ),
    "2 blades, isotropic hub": lambda: make_case(n_blades=2, body=ISOTROPIC, sweep=SWEEP),
    "2 blades, one damper failed, isotropic hub": lambda: failed(
        make_case(n_blades=2, body=ISOTROPIC, sweep=SWEEP), 1
    ),
    "3 blades, one damper failed, isotropic hub": lambda: failed(
        make_case(n_blades=3, body=ISOTROPIC, sweep=SWEEP), 2
    ),
    "4 blades, two dampers failed, isotropic hub": lambda: failed(
        make_case(n_blades=4, body=ISOTROPIC, sweep=SWEEP), 1, 2
    ),
}


@pytest.mark.slow
@pytest.mark.parametrize("name", BOTH_WAYS)
def test_floquet_gives_the_eigen_labels_and_frequencies_in_both_frames(name):
    """Same labels, and per label the same frequency in both frames and real
    part at every speed, to 1e-8 of the rotor speed (Floquet multipliers are
    accurate to about 1e-10; the eigenvalues to round-off)."""
    case = BOTH_WAYS[name]()
    eigen = analyze(case)
    flq = analyze(case, method="floquet")
    assert eigen.method in ("multiblade-eigen", "rotating-eigen") and flq.method == "floquet"
    assert flq.labels == eigen.labels
    w = eigen.rotor_speed[:, None]
    for field in ("frequency_nonrotating", "frequency_rotating", "real_part"):
        a, b = getattr(eigen.modes, field), getattr(flq.modes, field)
        worst = np.unravel_index(np.argmax(np.abs(a - b) / w), a.shape)
        assert np.abs(a - b).max(initial=0) <= 1e-8 * w.max(), (field, eigen.labels[worst[1]], w[worst[0]])
        assert (np.abs(a - b) <= 1e-8 * w).all(), (field, eigen.labels[worst[1]], float(w[worst[0], 0]))


SHIPPED_PERIODIC = ["hammond-1974-one-damper", "two-bladed", "hammond-one-damper-isotropic"]


@pytest.mark.slow
@pytest.mark.parametrize("name", SHIPPED_PERIODIC)
def test_frequencies_are_continuous_except_where_flagged(name):
    """Along every label, between neighbouring speeds, the frequency moves by
    less than a quarter of Omega (a harmonic is Omega) except where the label
    moved to another branch (a veering) or to another harmonic, both of which
    are flagged; and along every tracked root the real part is continuous."""
    result = analyze(load_case(name), method="floquet")
    m = result.modes
    w = result.rotor_speed
    for field, flag in (
        ("frequency_nonrotating", m.harmonic_change),
        ("frequency_rotating", m.harmonic_change_rotating),
    ):
        f = getattr(m, field)
        step = np.abs(np.diff(f, axis=0))
        free = ~(m.exchange[1:] | flag[1:])
        jumps = (step > 0.25 * w[1:, None]) & free
        assert not jumps.any(), [(float(w[i + 1]), result.labels[j]) for i, j in np.argwhere(jumps)][:5]
    # tracked roots do not swap: no two roots exchange their real parts between
    # neighbouring speeds (two roots that meet and part, at an exceptional
    # point, start from the same value and are not a swap)
    re = m.root_real_part
    step = np.abs(np.diff(re, axis=0))
    for s, c in np.argwhere(step > 0.01 * np.ptp(re)):
        onto = np.abs(re[s + 1, c] - re[s]) < step[s, c] / 3  # now where another root was
        back = np.abs(re[s + 1] - re[s, c]) < step[s, c] / 3  # another now where this was
        swapped = onto & back
        swapped[c] = False
        assert not swapped.any(), (float(w[s + 1]), c, np.flatnonzero(swapped))


def _per_label_gap(a, b):
    """Largest |a - b| / Omega per label, over frequency and real part, away
    from the speeds where either moves the label to another branch (a
    veering's exchange, whose place moves with the parameters by a grid step)."""
    w = a.rotor_speed
    out = {}
    for j, label in enumerate(a.labels):
        k = b.labels.index(label)
        moving = a.modes.exchange[:, j] | b.modes.exchange[:, k]
        near = moving | np.r_[moving[1:], False]  # the exchange and the speed before it
        gap = np.maximum(
            np.abs(a.frequency[:, j] - b.frequency[:, k]), np.abs(a.real_part[:, j] - b.real_part[:, k])
        )
        out[label] = float((gap / w)[~near].max())
    return out


@pytest.mark.slow
@pytest.mark.parametrize("hub", ["anisotropic", "isotropic"])
def test_a_damper_restored_to_99_percent_gives_the_identical_blade_diagram(hub):
    """Homotopy in the dissimilarity: a failed damper restored to 99 % of
    nominal gives, label by label, frequencies and real parts within 1 % of
    Omega of the identical-blade (time-invariant) diagram, in both frames,
    but for the grid step where a label changes branch. Above about 7 rad/s,
    where the lag mode is underdamped (nu Omega > C/2I): below it the
    overdamped cyclic lag roots lock onto Omega and split by the square root
    of the dissimilarity, which no labelling can undo."""
    body = ISOTROPIC if hub == "isotropic" else {}
    nominal = make_case(body=body, sweep=(8.0, 42.0, 80))
    restored = failed(nominal, 1, fraction=0.99)
    for frame in ("nonrotating", "rotating"):
        a = analyze(restored, frame=frame)
        b = analyze(nominal, frame=frame)
        assert a.method in ("floquet", "rotating-eigen") and a.labels == b.labels
        gaps = _per_label_gap(a, b)
        assert max(gaps.values()) < 0.01, (frame, gaps)


@pytest.mark.slow
def test_a_nearly_isotropic_hub_gives_the_isotropic_diagram_root_by_root():
    """Dissimilar blades on a hub 1 % from isotropic (Floquet) against the
    isotropic hub (rotating axes, time-invariant): at every speed the modes
    match one to one within 1 % of Omega in frequency and real part, but for
    the grid steps where a label changes branch. (The
    labels differ by design: an isotropic body moves in whirls, an
    anisotropic one along x and y.)"""
    iso = failed(make_case(body=ISOTROPIC, sweep=(8.0, 42.0, 60)), 1)
    near = replace(iso, body=replace(iso.body, mass_y=0.99 * iso.body.mass_y))
    a, b = analyze(near), analyze(iso)
    assert a.method == "floquet" and b.method == "rotating-eigen"
    moving = a.modes.exchange.any(1) | b.modes.exchange.any(1)
    steady = ~(moving | np.r_[moving[1:], False])  # away from exchanges, which move by a grid step
    assert steady.mean() > 0.8
    for i in np.flatnonzero(steady):
        w = a.rotor_speed[i]
        za = a.real_part[i] + 1j * a.frequency[i]
        zb = b.real_part[i] + 1j * b.frequency[i]
        d = np.abs(za[:, None] - zb[None, :])
        r, c = linear_sum_assignment(d)
        assert d[r, c].max() < 0.01 * w, w


UNSTABLE = {
    "4 blades, one damper failed": lambda: failed(make_case(sweep=(10.0, 40.0, 60)), 2),
    "5 blades, two adjacent dampers failed": lambda: failed(
        make_case(n_blades=5, sweep=(10.0, 40.0, 60)), 1, 2
    ),
    "5 blades, two dampers apart failed": lambda: failed(make_case(n_blades=5, sweep=(10.0, 40.0, 60)), 1, 3),
    "3 blades, one damper failed, isotropic hub": lambda: failed(
        make_case(n_blades=3, body=ISOTROPIC, sweep=(10.0, 40.0, 60)), 1
    ),
}


@pytest.mark.slow
@pytest.mark.parametrize("name", UNSTABLE)
def test_a_growing_mode_is_named_by_its_largest_content(name):
    """Every growing mode's label is the one its content (Modes.energy, in
    multiblade coordinates of the actual motion) ranks first; summary.json
    names the unstable modes by those labels."""
    result = analyze(UNSTABLE[name]())
    m = result.modes
    grows = m.real_part > 1e-6 * result.rotor_speed[:, None]
    assert grows.any()
    for i, j in np.argwhere(grows):
        assert int(np.argmax(m.energy[i, j])) == j, (result.rotor_speed[i], result.labels[j], m.energy[i, j])
    summary = result.summary()
    i = int(np.argmin(np.abs(result.rotor_speed - summary["max_real_part"]["speed"])))
    worst = int(np.argmax(m.real_part[i]))
    assert summary["max_real_part"]["mode"] == result.labels[worst]
    assert result.labels[int(np.argmax(m.energy[i, worst]))] == result.labels[worst]
    for entry in summary["unstable_ranges"]:
        assert set(entry["modes"]) <= set(result.labels[j] for _, j in np.argwhere(grows))


@pytest.mark.parametrize(
    "case",
    [
        make_case(n_blades=7, sweep=(4.0, 20.0, 40)),
        failed(make_case(n_blades=7, sweep=(4.0, 20.0, 40)), 3),
    ],
    ids=["7 blades, multiblade", "one damper failed, Floquet"],
)
def test_body_modes_in_rotating_axes_follow_their_whirl(case):
    """On an anisotropic hub a body x or y mode is a mixture of forward and
    backward whirl; seen from rotating axes its frequency is that of one of
    them, |omega - Omega| (forward) or omega + Omega (backward), not a fixed
    choice. The line keeps the whirl it follows (continuity, as in nonrotating
    axes) until the other holds ROTATING_RATIO times more: where one whirl
    holds more than R / (1 + R) of the hub motion the frequency is that
    whirl's, and the choice changes only where the label moves to another
    branch or the change is flagged."""
    from groundres.modes.frequencies import ROTATING_RATIO

    clear = ROTATING_RATIO / (1 + ROTATING_RATIO)
    result = analyze(case)
    m, w = result.modes, result.rotor_speed
    for label in ("body x", "body y"):
        j = result.labels.index(label)
        x, y = m.shape[:, 0, j], m.shape[:, 1, j]
        fwd, bwd = np.abs(x + 1j * y) ** 2, np.abs(x - 1j * y) ** 2
        share = bwd / (fwd + bwd)
        f = m.frequency_nonrotating[:, j]
        backward = np.isclose(m.frequency_rotating[:, j], f + w, rtol=1e-9)
        forward = np.isclose(m.frequency_rotating[:, j], np.abs(f - w), rtol=1e-9)
        assert (backward | forward).all(), label
        assert backward[share > clear].all() and forward[share < 1 - clear].all()
        changes = np.flatnonzero(backward[1:] != backward[:-1]) + 1
        for i in changes:
            assert m.exchange[i, j] or m.harmonic_change_rotating[i, j], (label, w[i])


def test_label_groups_name_every_coordinate():
    coords = [Coordinate("body", "x"), Coordinate("body", "y"), Coordinate("lag", "0")]
    coords += [Coordinate("lag", "1c", 1), Coordinate("lag", "1s", 1), Coordinate("lag", "d", 2)]
    names = [n for g in label_groups(coords) for n in g.labels]
    assert names == [
        "body x",
        "body y",
        "collective lag",
        "regressive lag",
        "progressive lag",
        "differential lag",
    ]
    iso = [n for g in label_groups(coords, [("x", "y")]) for n in g.labels]
    assert iso[:2] == ["body forward whirl", "body backward whirl"]
