"""Seed paper, Figure 3: articulated four-bladed rotor, no damping, anisotropic hub.

"Multibladed rotor helicopter ground resonance including eigenvector
analysis" (the project's seed paper) reports two instability ranges, "one
between 0.85 and 1.2 and another ranging from 1.3 to 2.0" in rotor speed over
155 rpm, where the regressive lag mode coalesces with the two body modes.
The numbers are read from a figure and rounded to about 0.05, which is the
tolerance used here.
"""

import numpy as np

from groundres import analyze, load_case

REFERENCE = 155.0 * 2 * np.pi / 60  # [rad/s]


def test_two_instability_ranges_as_in_the_paper():
    result = analyze(load_case("hammond-undamped"))
    ranges = np.array(result.stability.unstable_ranges) / REFERENCE
    np.testing.assert_allclose(ranges, [[0.85, 1.2], [1.3, 2.0]], atol=0.05)


def test_coalescence_partners_are_regressive_lag_and_body_modes():
    result = analyze(load_case("hammond-undamped"))
    freq = dict(zip(result.labels, result.frequency.T))
    w = result.rotor_speed
    for (start, end), body in zip(result.stability.unstable_ranges, ("body x", "body y")):
        mid = np.argmin(np.abs(w - 0.5 * (start + end)))
        # inside a coalescence the two modes share one frequency
        assert abs(freq["regressive lag"][mid] - freq[body][mid]) < 1e-6 * w[mid]
