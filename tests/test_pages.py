"""HTML pages (groundres report, groundres gallery): valid, self-contained, and their numbers are the data's.

Validity is checked with html5lib's strict parser (the WHATWG parsing
algorithm; strict mode raises on every parse error), self-containment by
every src and href of the page (data: URIs and in-page anchors only), and
the numbers by every ``data-key``/``data-value`` pair: the value must be the
one at that place of summary.json (report) or gallery.json (gallery), exactly.
"""

from __future__ import annotations

import json
import math
import re
from html.parser import HTMLParser
from pathlib import Path
from types import SimpleNamespace

import html5lib
import numpy as np
import pytest
from click.testing import CliRunner

from conftest import HAMMOND_TOML
from groundres.cli import main
from groundres.model.schema import load_case
from groundres.pages import figures, verdicts


def cli(*args):
    return CliRunner().invoke(main, list(args))


class _Collect(HTMLParser):
    def __init__(self):
        super().__init__()
        self.links, self.numbers, self.ids, self.sections = [], [], [], []

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        for name in ("src", "href"):
            if name in a:
                self.links.append(a[name])
        if "data-key" in a:
            self.numbers.append((a["data-key"], a["data-value"]))
        if "id" in a:
            self.ids.append(a["id"])
        if tag == "section":
            self.sections.append(a.get("id"))
        if tag in ("link", "script", "iframe", "object", "embed"):
            self.links.append(f"<{tag}>")


def page_facts(path) -> _Collect:
    text = path.read_text(encoding="utf-8")
    html5lib.HTMLParser(strict=True).parse(text)  # raises on any parse error
    facts = _Collect()
    facts.feed(text)
    return facts


def at(data, key: str):
    for part in key.split("."):
        data = data[int(part)] if isinstance(data, list) else data[part]
    return data


def check_self_contained(facts: _Collect) -> None:
    for link in facts.links:
        assert link.startswith(("data:", "#")), f"external or linked resource in the page: {link[:80]}"
    for link in facts.links:
        if link.startswith("#"):
            assert link[1:] in facts.ids, f"anchor {link} has no target"


def check_numbers(facts: _Collect, data: dict) -> int:
    assert facts.numbers
    for key, value in facts.numbers:
        expected = at(data, key)
        if value == "null":
            assert expected is None, key
        else:
            assert float(value) == expected, (key, value, expected)
    return len(facts.numbers)


#: The Hammond rotor with blade 1's damper failed on a short sweep in rpm, with a title and description
#: that a page must escape.
SMALL = (
    HAMMOND_TOML.replace(
        'title = "test"', 'title = "Small <b>case</b> & friends"\ndescription = "A short sweep."'
    )
    .replace("[body]", "[[rotor.blade]]\nindex = 1\nlag_damping = 0.0\n[body]")
    .replace(
        'start = 0.5\nstop = 40.0\npoints = 60\nunit = "rad/s"',
        'start = 120.0\nstop = 360.0\npoints = 50\nunit = "rpm"\nreference = 155.0',
    )
)


@pytest.mark.parametrize("method", ["floquet", "eigen"])
def test_report_is_valid_self_contained_and_its_numbers_are_summary_json(tmp_path, method):
    """One failed damper on the anisotropic hub (Floquet) and the same rotor with identical blades
    (eigen): both reports hold every section, and every number is summary.json's."""
    text = SMALL if method == "floquet" else SMALL.replace("lag_damping = 0.0", "lag_damping = 4067.5")
    case = tmp_path / "small.toml"
    case.write_text(text)
    out = tmp_path / "report"
    res = cli("report", str(case), "--out", str(out))
    assert res.exit_code == 0, res.output
    facts = page_facts(out / "index.html")
    check_self_contained(facts)
    summary = json.loads((out / "summary.json").read_text())
    assert summary["method"] == ("floquet" if method == "floquet" else "multiblade-eigen")
    n = check_numbers(facts, summary)
    assert n >= 10
    keys = {k for k, _ in facts.numbers}
    assert {"lag_damping.deutsch.0.required_lag_damping", "lag_frequency_at_reference.value"} <= keys
    for section in ("ranges", "coleman", "derived", "damping", "phasors", "case", "method"):
        assert section in facts.sections
    page = (out / "index.html").read_text()
    assert "<b>case</b>" not in page and "Small &lt;b&gt;case&lt;/b&gt; &amp; friends" in page  # escaped
    assert "@media print" in page
    assert (out / "coleman.png").read_bytes()[:4] == b"\x89PNG"
    if method == "floquet":
        assert summary["unstable_ranges"] and "unstable_ranges.0.start" in keys
        assert "Floquet exponents" in page  # the accuracy record of the periodic method
    else:
        assert summary["stable"]


def test_a_report_of_nonlinear_dampers_has_a_limit_cycle_section_with_its_numbers(tmp_path):
    """Issue 26, item 4: a case with a nonlinear law gets the limit cycles in the report, their
    words those of groundres cycles, the page still self-contained; a linear case gets none."""
    from groundres import limit_cycles, load_case

    out = tmp_path / "report"
    res = cli("report", "hammond-relief-valve", "--out", str(out))
    assert res.exit_code == 0, res.output
    facts = page_facts(out / "index.html")
    check_self_contained(facts)
    assert "cycles" in facts.sections and (out / "limit_cycles.png").read_bytes()[:4] == b"\x89PNG"
    found = limit_cycles(load_case("hammond-relief-valve"), linear=False)
    page = " ".join((out / "index.html").read_text().split())
    assert found.threshold_words(found.smallest_threshold()) in page.replace("&#39;", "'")
    assert "The other sections are linear" in page
    plain = tmp_path / "plain"
    assert cli("report", "hammond-1974", "--out", str(plain)).exit_code == 0
    assert (
        "cycles" not in page_facts(plain / "index.html").sections
        and not (plain / "limit_cycles.png").exists()
    )


def test_report_svg_and_a_study_folder(tmp_path):
    """--format svg embeds and writes svg; --study embeds the study's map and names what it varied."""
    import xarray as xr

    study = tmp_path / "study"
    study.mkdir()
    ds = xr.Dataset(
        {"stable": (("rotor.lag_damping",), np.array([0, 1, 1]))},
        coords={"rotor.lag_damping": [1000.0, 2000.0, 3000.0]},
    )
    ds.to_netcdf(study / "study.nc")
    (study / "case.toml").write_text(SMALL.replace("lag_damping = 0.0", "lag_damping = 4067.5"))
    (study / "provenance.json").write_text('{"generator": "groundres", "command": "study"}')
    from matplotlib.figure import Figure

    fig = Figure()
    fig.subplots().plot([0, 1], [1, 0])
    fig.savefig(study / "map.png")
    out = tmp_path / "report"
    res = cli("report", "--study", str(study), "--out", str(out), "--format", "svg")
    assert res.exit_code == 0, res.output
    facts = page_facts(out / "index.html")
    check_self_contained(facts)
    assert "study" in facts.sections
    page = (out / "index.html").read_text()
    assert "data:image/svg+xml;base64," in page and "2 of 3" in page
    assert (out / "coleman.svg").read_bytes().lstrip()[:5] in (b"<?xml", b"<svg ")


@pytest.mark.parametrize(
    "args, words",
    [
        (["--study", "nowhere"], "--study 'nowhere': not a folder"),
        (["hammond-1974", "--format", "bmp"], "--format"),
    ],
)
def test_report_bad_options_exit_2(tmp_path, args, words):
    res = cli("report", *args, "--out", str(tmp_path / "r"))
    assert res.exit_code == 2
    assert words in res.output
    assert "Traceback" not in res.output
    assert not (tmp_path / "r").exists()


def test_report_refuses_an_unreadable_study_before_any_work(tmp_path):
    study = tmp_path / "study"
    study.mkdir()
    (study / "study.nc").write_bytes(b"not a netCDF file")
    (study / "provenance.json").write_text('{"generator": "groundres", "command": "study"}')
    res = cli("report", "hammond-1974", "--study", str(study), "--out", str(tmp_path / "r"))
    assert res.exit_code == 2
    assert "study.nc cannot be read" in res.output and "Traceback" not in res.output
    assert not (tmp_path / "r").exists()


def test_report_refuses_a_folder_that_is_no_study(tmp_path):
    """A NetCDF file named study.nc in a folder no study wrote (here a run's modes.nc) is refused."""
    run = tmp_path / "run"
    assert cli("run", "hammond-1974", "--out", str(run)).exit_code == 0
    (run / "modes.nc").rename(run / "study.nc")
    res = cli("report", "hammond-1974", "--study", str(run), "--out", str(tmp_path / "r"))
    assert res.exit_code == 2 and "not the --out folder of a groundres study" in res.output
    assert not (tmp_path / "r").exists()


def test_gallery_bad_figures_exit_2(tmp_path):
    for value in ("2", "3-14", "x", "5-3", "", "13-3"):
        res = cli("gallery", "--figures", value, "--out", str(tmp_path / "g"))
        assert res.exit_code == 2, (value, res.output)
        assert "--figures" in res.output and "from 3 to 13" in res.output, res.output
        assert not (tmp_path / "g").exists()


def _stub(ranges, reference=1.0, start=0.1, stop=3.0, modes=("regressive lag",)):
    sweep = SimpleNamespace(reference=reference, start=start, stop=stop)
    return SimpleNamespace(
        case=SimpleNamespace(sweep=sweep),
        stability=SimpleNamespace(unstable_ranges=[(s * reference, e * reference) for s, e in ranges]),
        unstable_modes=lambda s, e: list(modes),
    )


def test_verdicts_of_ranges():
    """The verdict's rules: within the tolerance agrees; beyond it, agrees in kind only where the case
    had to choose what the paper does not give, each range overlaps the paper's and is grown by the
    regressive lag mode; another count, no overlap, or unstable where the paper says stable, differs."""
    t = verdicts.RANGE_TOLERANCE
    paper = ((0.85, 1.2),)
    chosen = "this rotor's parameters"
    assert verdicts.compare_ranges(paper, _stub([(0.85 + 0.9 * t, 1.2)])).word == "agrees"
    assert verdicts.compare_ranges(paper, _stub([(0.85 + 1.1 * t, 1.2)]), chosen).word == "agrees in kind"
    assert verdicts.compare_ranges(paper, _stub([(0.85 + 1.1 * t, 1.2)])).word == "differs"  # nothing chosen
    assert verdicts.compare_ranges(paper, _stub([(1.3, 1.9)]), chosen).word == "differs"  # no overlap
    other = _stub([(0.95, 1.2)], modes=("collective lag",))
    assert verdicts.compare_ranges(paper, other, chosen).word == "differs"  # another mode grows
    assert verdicts.compare_ranges(((0.85, 1.2), (1.3, 2)), _stub([(0.85, 1.2)]), chosen).word == "differs"
    assert verdicts.compare_ranges((), _stub([])).word == "agrees"
    assert verdicts.compare_ranges((), _stub([(1, 2)])).word == "differs"


def test_phasor_verdict_rules():
    cell = dict(speed_text="", mode="regressive lag", placed=True)
    good = [
        dict(cell, where="below", state="neutral", in_phase=1e-16),
        dict(cell, where="inside", state="growing", in_phase=0.1),
        dict(cell, where="above", state="neutral", in_phase=-1e-15),
    ]
    assert verdicts.phasor_verdict(good).word == "agrees"
    bad = [dict(good[0], in_phase=0.01), *good[1:]]
    assert verdicts.phasor_verdict(bad).word == "differs"
    decaying_inside = [good[0], dict(good[1], state="decaying", in_phase=-0.1), good[2]]
    assert verdicts.phasor_verdict(decaying_inside).word == "differs"
    misplaced = [good[0], dict(good[1], placed=False), good[2]]
    assert verdicts.phasor_verdict(misplaced).word == "differs"


def test_smeared_case_averages_the_dampers():
    case = load_case("hammond-1974-one-damper")
    smeared, mean = verdicts.smeared_case(case)
    assert mean == pytest.approx(0.75 * 4067.5, rel=1e-15)
    assert smeared.rotor.identical
    assert all(b.lag_damping == mean for b in smeared.rotor.blades)


def test_every_figure_has_a_shipped_case_and_phasor_speeds_in_its_unit():
    from groundres.model.casefile import shipped_cases

    assert figures.NUMBERS == tuple(range(3, 14))
    for f in figures.FIGURES:
        assert f.case in shipped_cases()
        assert (len(f.speeds) == 3) == (f.kind == "phasors")
        if f.ranges is not None:
            assert all(0 < s < e for s, e in f.ranges)


def test_gallery_whole(tmp_path):
    """The whole gallery (about 20 s): every figure with a verdict and its pictures, the page valid and
    self-contained, its numbers gallery.json's; the figures whose parameters the paper gives agree, and
    the Floquet analysis of Figure 9 equals the eigen-analysis of Figure 8 to round-off."""
    out = tmp_path / "gallery"
    res = cli("gallery", "--out", str(out))
    assert res.exit_code == 0, res.output
    facts = page_facts(out / "index.html")
    check_self_contained(facts)
    data = json.loads((out / "gallery.json").read_text())
    check_numbers(facts, data)
    by_number = {f["number"]: f for f in data["figures"]}
    assert sorted(by_number) == list(range(3, 14))
    for n, f in by_number.items():
        assert f["verdict"] in ("agrees", "agrees in kind", "differs", "nothing to compare")
        assert f["reason"] and f["computed"]
        assert f"figure-{n}" in facts.ids
    names = {p.name for p in out.iterdir()}
    for n in range(3, 11):
        assert {f"figure-{n:02d}-coleman-nonrotating.png", f"figure-{n:02d}-coleman-rotating.png"} <= names
    for n in range(11, 14):
        assert {f"figure-{n}-phasors-{w}.png" for w in ("below", "inside", "above")} <= names
    for n in (3, 5, 6, 7, 11, 12, 13):
        assert by_number[n]["verdict"] == "agrees", (n, by_number[n]["reason"])
    # Figure 3: the paper's two ranges, 0.85-1.2 and 1.3-2.0 times 155 rpm (read off its plot)
    ref = by_number[3]["summary"]["sweep"]["reference"]
    ends = [(r["start"] / ref, r["end"] / ref) for r in by_number[3]["summary"]["unstable_ranges"]]
    assert np.allclose(ends, [(0.85, 1.2), (1.3, 2.0)], atol=verdicts.RANGE_TOLERANCE)
    assert by_number[9]["range_difference_from_figure"] == {
        "figure": 8,
        "relative": pytest.approx(0, abs=1e-7),
    }
    assert by_number[10]["verdict"] == "nothing to compare"  # the paper states no range for Figure 10
    assert math.isclose(
        by_number[8]["summary"]["unstable_ranges"][0]["start"],
        by_number[9]["summary"]["unstable_ranges"][0]["start"],
        rel_tol=1e-7,
    )
    assert "stable over the whole sweep" in by_number[10]["computed"]  # the smeared approximation misses it
    # docs/gallery.md shows this version's verdicts (docs/make_gallery_images.py writes its table)
    text = (Path(__file__).parents[1] / "docs" / "gallery.md").read_text(encoding="utf-8")
    rows = re.findall(
        r"^\| (\d+) \| `([^`]+)` \| .* \| (agrees in kind|agrees|differs|nothing to compare) \|$", text, re.M
    )
    assert {int(n): (c, v) for n, c, v in rows} == {
        n: (f["case"], f["verdict"]) for n, f in by_number.items()
    }


def test_control_characters_of_a_title_reach_neither_the_page_nor_the_terminal(tmp_path):
    """BEL, ESC and NUL in a title: dropped from the HTML (NUL is not allowed there) and the console."""
    case = tmp_path / "ctrl.toml"
    case.write_text(
        SMALL.replace('title = "Small <b>case</b> & friends"', 'title = "a\\u0007b\\u001b[31mc\\u0000d"')
    )
    out = tmp_path / "r"
    res = cli("report", str(case), "--out", str(out))
    assert res.exit_code == 0, res.output
    page = (out / "index.html").read_text()
    assert not any(ch in page for ch in "\x00\x07\x1b")
    assert "ab[31mcd" in page
    page_facts(out / "index.html")  # still valid
    assert not any(ch in res.output for ch in "\x00\x07\x1b")


@pytest.mark.parametrize("limits", ["1e308:1.7e308", "-1e308:1e308", "0:1e-101"])
def test_limits_too_large_or_too_narrow_for_an_axis_exit_2(tmp_path, limits):
    res = cli("report", "hammond-1974", "--real-limits", limits, "--out", str(tmp_path / "r"))
    assert res.exit_code == 2 and "--real-limits" in res.output and "1e+100" in res.output
    assert not (tmp_path / "r").exists()


@pytest.mark.parametrize("reference", ["1e-300", "1e300"])
def test_a_reference_speed_far_out_of_scale_reports_without_overflow(tmp_path, reference):
    """The lag frequency at the reference speed is divided by the speed twice, never squared: a
    reference of 1e-300 or 1e300 rpm gives a number or a reasoned null, not an overflow."""
    case = tmp_path / "ref.toml"
    text = SMALL.replace("lag_damping = 0.0", "lag_damping = 4067.5").replace(
        "reference = 155.0", f"reference = {reference}"
    )
    case.write_text(text)
    res = cli("report", str(case), "--out", str(tmp_path / "r"))
    assert res.exit_code == 0, res.output
    entry = json.loads((tmp_path / "r" / "summary.json").read_text())["lag_frequency_at_reference"]
    assert entry["value"] is not None or entry["value_reason"]
