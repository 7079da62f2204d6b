"""What the Coleman diagram shows a reader (issue 9: results you can trust at a glance)."""

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402

from groundres import analyze  # noqa: E402
from groundres.model.schema import load_case  # noqa: E402
from groundres.plotting.coleman import coleman_diagram  # noqa: E402


def test_a_range_too_narrow_for_a_band_is_marked():
    """soft-inplane-pitch-roll has a range 0.011 rad/s wide (0.0006 of the 155 rpm
    reference, 0.03 % of the axis): shaded alone it would be invisible, so it has
    a line in every panel and a triangle on the frequency panel, and the legend
    says what they mean. The ground-resonance range (1.17 to 2.19) is a band only."""
    result = analyze(load_case("soft-inplane-pitch-roll"))
    (s, e), big = result.stability.unstable_ranges[0], result.stability.unstable_ranges[1]
    assert e - s < 0.02 and big[1] - big[0] > 10
    fig = coleman_diagram(result)
    ref = result.case.sweep.reference
    middle = 0.5 * (s + e) / ref
    lines = [
        line
        for ax in fig.axes
        for line in ax.get_lines()
        if np.allclose(line.get_xdata(), middle, rtol=1e-9) and line.get_color() == "#d62728"
    ]
    assert any(line.get_marker() == "v" for line in lines)
    assert sum(line.get_marker() in ("None", "", None) for line in lines) == len(fig.axes)
    legend = [t.get_text() for leg in fig.legends for t in leg.get_texts()]
    assert any(t.startswith("narrow unstable range") for t in legend)
    # no line for the wide range
    assert not any(
        np.allclose(line.get_xdata(), 0.5 * sum(big) / ref, rtol=1e-6)
        for ax in fig.axes
        for line in ax.get_lines()
    )
