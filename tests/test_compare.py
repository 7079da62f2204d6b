"""`groundres compare` and groundres.compare: entries, differences, files (docs/case-files.md)."""

import importlib
import json
import math

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402
from click.testing import CliRunner  # noqa: E402

import groundres  # noqa: E402
from groundres.cli import main  # noqa: E402
from groundres.model.casefile import shipped_cases  # noqa: E402
from groundres.results.comparison import pair_ranges  # noqa: E402

#: The seed paper's Figure 3 case (two unstable ranges) on 40 speeds instead of 400: fast.
UNDAMPED = shipped_cases()["hammond-undamped"].replace("points = 400", "points = 40")
#: The same rotor and sweep in rad/s, without a reference speed.
RPM = math.pi / 30
UNDAMPED_RAD = UNDAMPED.replace("start = 5.0", f"start = {5.0 * RPM!r}").replace(
    "stop = 400.0", f"stop = {400.0 * RPM!r}"
)
UNDAMPED_RAD = UNDAMPED_RAD.replace('unit = "rpm"', 'unit = "rad/s"').replace("reference = 155.0\n", "")


def run(*args):
    return CliRunner().invoke(main, [str(a) for a in args])


def write(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_small_cases_are_what_the_tests_assume():
    assert "points = 40\n" in UNDAMPED and 'unit = "rad/s"' in UNDAMPED_RAD
    assert "reference" not in UNDAMPED_RAD.split("[sweep]")[1]


def test_a_case_compared_with_itself_differs_by_exactly_zero(tmp_path):
    case = write(tmp_path, "undamped.toml", UNDAMPED)
    out = tmp_path / "out"
    result = run("compare", case, case, "--out", out)
    assert result.exit_code == 0, result.output
    data = json.loads((out / "differences.json").read_text())
    rows = data["differences"]
    quantities = [r["quantity"] for r in rows]
    assert quantities.count("range_start") == 2 == quantities.count("range_end")  # Figure 3: two ranges
    assert {r["entry"] for r in rows} == {2}
    for r in rows:
        assert r["difference"] == 0 and r["baseline"] == r["value"] is not None, r
    csv_rows = (out / "differences.csv").read_text().splitlines()
    assert csv_rows[0] == (
        "entry,name,quantity,range,unit,baseline,value,difference,note,tolerance,within_round_off"
    )
    assert len(csv_rows) == 1 + len(rows)
    assert {line.split(",")[7] for line in csv_rows[1:]} <= {"0", "0.0"}
    assert {line.split(",")[-1] for line in csv_rows[1:]} == {"true"}
    # every number the table shows as a difference is 0
    table = result.output.split("Differences from the baseline")[1].split("Speeds in")[0]
    lines = [line.split() for line in table.splitlines() if line.startswith("2 ")]
    assert len(lines) == len(rows) and all(line[-1] == "0" for line in lines)
    # both summaries are those of `groundres run`, identical here
    first, second = (json.loads((out / f"summary-{n}.json").read_text()) for n in (1, 2))
    assert first == second and first["speed_unit"] == "rad/s" and len(first["unstable_ranges"]) == 2
    record = json.loads((out / "provenance.json").read_text())
    assert record["command"] == "compare" and [e["entry"] for e in record["entries"]] == [1, 2]
    assert set(record["files"]) == {
        "compare.png",
        "differences.csv",
        "differences.json",
        "summary-1.json",
        "summary-2.json",
        "case.toml",
        "case-2.toml",
        "provenance.json",
    }
    assert (out / "case-2.toml").read_text() == (out / "case.toml").read_text() == UNDAMPED
    assert (out / "compare.png").read_bytes()[:4] == b"\x89PNG"


def test_an_entry_asked_twice_is_analysed_once():
    case = groundres.load_case("hammond-undamped")
    comparison = groundres.compare([case, case])
    first, second = comparison.entries
    assert first.result is second.result
    assert all(r["difference"] == 0 for r in comparison.differences())


@pytest.mark.parametrize(
    "name, method",
    [("hammond-undamped", None), ("hammond-one-damper-isotropic", "floquet")],
)
def test_a_copy_of_a_case_is_analysed_again_and_differs_by_exactly_zero(tmp_path, name, method):
    """A shipped case against its text with a comment added: another case text, so
    analysed a second time, from a fresh system (no result or grid shared). The
    computation is deterministic, threads or not, so every difference is exactly zero,
    not merely round-off: by eigen-analysis, and by Floquet theory (transition matrices
    integrated over the pool's threads)."""
    copy = write(tmp_path, "copy.toml", "# the same case, another text\n" + shipped_cases()[name])
    comparison = groundres.compare([name, str(copy)], methods=[method] if method else None)
    first, second = (e.result for e in comparison.entries)
    assert first is not second and first.case.text != second.case.text  # (analysed twice)
    rows = comparison.differences()
    assert any(r["quantity"] == "range_start" for r in rows)
    for r in rows:
        assert r["baseline"] is not None and r["difference"] == 0, r
    for quantity in ("real_part", "frequency", "rotor_speed"):
        assert np.array_equal(getattr(first, quantity), getattr(second, quantity), equal_nan=True)


def test_eigen_and_floquet_agree_on_the_isotropic_one_damper_case(tmp_path):
    """The seed paper's Figures 8 and 9: one case by rotating-axes eigen-analysis and by
    Floquet theory. Both find the range ends by root finding on the growth threshold,
    one from constant-coefficient eigenvalues, the other from Floquet exponents of a
    transition matrix integrated to about 1e-10 per entry: the ends agree to ~1e-10
    rad/s, so 1e-8 relative is a margin of about a hundred. The growth margin is a
    smooth maximum (agrees to ~1e-13 1/s); its speed is the argument of a flat maximum,
    where a value error d moves the speed by ~sqrt(2 d / |f''|), found by golden-section
    search to 1e-4 of the speed (Floquet): 1e-3 relative. The least damping ratio, a smooth
    minimum refined likewise, agrees to ~1e-8."""
    out = tmp_path / "out"
    result = run(
        "compare", "hammond-one-damper-isotropic", "--method", "eigen", "--method", "floquet", "--out", out
    )
    assert result.exit_code == 0, result.output
    data = json.loads((out / "differences.json").read_text())
    assert [e["method"] for e in data["entries"]] == ["rotating-eigen", "floquet"]
    assert [e["name"] for e in data["entries"]] == [
        "hammond-one-damper-isotropic (rotating-eigen)",
        "hammond-one-damper-isotropic (floquet)",
    ]
    rows = {(r["quantity"], r.get("range")): r for r in data["differences"]}
    assert rows["unstable_range_count", None]["difference"] == 0
    # the differences are round-off: kept as computed, flagged, never printed as results
    assert {r["within_round_off"] for r in rows.values()} == {True}
    assert all(0 <= r["tolerance"] for r in rows.values())
    assert rows["range_start", 1]["difference"] != 0  # (two methods: round-off, not exact)
    assert set(data["round_off"]["tolerance"]) == set(data["quantities"])
    assert data["round_off"]["speed_relative"] == 1e-7
    table = result.output.split("Differences from the baseline")[1].split("Speeds in")[0]
    assert "e-" not in table and table.count("0 (round-off)") == len(rows) - 1
    assert "0 (round-off): a difference within the round-off" in " ".join(result.output.split())
    for key in (("range_start", 1), ("range_end", 1), ("unstable_width", None)):
        r = rows[key]
        assert abs(r["difference"]) <= 1e-8 * r["baseline"], r
    assert abs(rows["growth_margin", None]["difference"]) <= 1e-9
    for quantity in ("growth_margin_speed", "least_damping_ratio_speed"):
        speed = rows[quantity, None]
        assert abs(speed["difference"]) <= 1e-3 * speed["baseline"], speed
    assert abs(rows["least_damping_ratio", None]["difference"]) <= 1e-7
    # the range in the paper's terms: 1.013 to 1.295 times 155 rpm
    assert "(1.013 ref)" in result.output and "(1.295 ref)" in result.output
    assert "range 1 start [rpm]" in result.output
    assert "ref: rotor speed / the first case's reference speed, 155 rpm." in " ".join(result.output.split())


def test_cases_in_different_units_share_the_first_case_s_unit(tmp_path):
    """One rotor swept in rad/s and in rpm: every speed on the first case's unit (rad/s),
    the ranges the same up to the rounding of the unit conversion."""
    rad = write(tmp_path, "rad.toml", UNDAMPED_RAD)
    rpm = write(tmp_path, "rpm.toml", UNDAMPED)
    out = tmp_path / "out"
    result = run("compare", rad, rpm, "--out", out)
    assert result.exit_code == 0, result.output
    assert "range 1 start [rad/s]" in result.output and "the cases' own units differ" in result.output
    for r in json.loads((out / "differences.json").read_text())["differences"]:
        if r["quantity"] in ("range_start", "range_end", "unstable_width"):
            assert abs(r["difference"]) <= 1e-9 * r["baseline"], r
    comparison = groundres.compare([str(rad), str(rpm)])
    fig = comparison.plot()
    assert fig.axes[-1].get_xlabel() == "rotor speed [rad/s]"  # no shared reference: the unit
    assert "reference" in groundres.compare([str(rpm), str(rpm)]).plot().axes[-1].get_xlabel()


def test_neutral_growth_margins_print_as_neutral_not_as_numbers(tmp_path):
    """An undamped stable rotor: its growth margin is round-off (~1e-15 1/s) by either
    method, and where it peaks is no result; its least damping ratio is 0, neutral; the
    table says so in words."""
    case = write(
        tmp_path, "stiff.toml", shipped_cases()["stiff-inplane"].replace("points = 400", "points = 40")
    )
    out = tmp_path / "out"
    result = run("compare", case, "--method", "eigen", "--method", "floquet", "--out", out)
    assert result.exit_code == 0, result.output
    rows = {r["quantity"]: r for r in json.loads((out / "differences.json").read_text())["differences"]}
    peak, speed = rows["growth_margin"], rows["growth_margin_speed"]
    assert abs(peak["baseline"]) < 1e-9 and peak["within_round_off"] is True
    assert speed["within_round_off"] is True and "neutral" in speed["note"]
    least, where = rows["least_damping_ratio"], rows["least_damping_ratio_speed"]
    assert least["baseline"] == least["value"] == 0.0 and "neutral" in where["note"]
    table = result.output.split("Differences from the baseline")[1].split("Speeds in")[0]
    assert "e-" not in table
    peak_line, speed_line = (
        next(line.split() for line in table.splitlines() if q in line) for q in ("growth margin", "at [")
    )
    assert peak_line[-4:] == ["neutral", "neutral", "0", "(round-off)"]
    assert speed_line[-4:] == ["-", "-", "-", "(neutral)"]
    assert "neutral: the growth margin within the growth threshold" in " ".join(result.output.split())


def test_ref_is_the_first_case_s_reference_for_every_entry(tmp_path):
    first = write(tmp_path, "a.toml", UNDAMPED)
    second = write(tmp_path, "b.toml", UNDAMPED.replace("reference = 155.0", "reference = 170.0"))
    result = run("compare", first, second, "--out", tmp_path / "out")
    assert result.exit_code == 0, result.output
    text = " ".join(result.output.split())
    assert "ref: rotor speed / the first case's reference speed, 155 rpm, for every entry" in text
    assert "the case's reference" not in text


def test_a_range_without_a_partner_has_no_difference():
    stable = groundres.load_case("hammond-1974")
    unstable = groundres.load_case("hammond-undamped")
    rows = groundres.compare([stable, unstable]).differences()
    count = next(r for r in rows if r["quantity"] == "unstable_range_count")
    assert (count["baseline"], count["value"], count["difference"]) == (0, 2, 2)
    starts = [r for r in rows if r["quantity"] == "range_start"]
    assert len(starts) == 2
    for r in starts:
        assert r["baseline"] is None and r["difference"] is None and r["note"] == "only in this entry"


def test_ranges_pair_where_they_overlap():
    a = [(1.0, 2.0), (3.0, 4.0), (7.0, 8.0)]
    b = [(1.1, 2.1), (5.0, 6.0), (7.5, 9.0)]
    assert pair_ranges(a, b) == [
        ((1.0, 2.0), (1.1, 2.1)),
        ((3.0, 4.0), None),
        (None, (5.0, 6.0)),
        ((7.0, 8.0), (7.5, 9.0)),
    ]
    assert pair_ranges([], b[:1]) == [(None, (1.1, 2.1))]
    assert pair_ranges(a[:1], []) == [((1.0, 2.0), None)]


@pytest.mark.parametrize(
    "args, words",
    [
        (["hammond-undamped"], ["one entry", "two or more", "--method"]),
        (["hammond-undamped", "--method", "eigen"], ["one entry", "two or more"]),
        (["hammond-undamped", "nope"], ["nope"]),
    ],
)
def test_fewer_than_two_entries_or_a_bad_case_is_refused(tmp_path, args, words):
    out = tmp_path / "out"
    result = run("compare", *args, "--out", out)
    assert result.exit_code == 2, result.output
    assert len(result.output.strip().splitlines()) == 1 and "Traceback" not in result.output
    for word in words:
        assert word in result.output
    assert not out.exists()


def test_python_api_is_exported_and_refuses_one_entry():
    assert callable(groundres.compare) and "compare" in dir(groundres)
    importlib.import_module("groundres.results.comparison")  # (the module does not shadow the function)

    assert callable(groundres.compare)
    with pytest.raises(ValueError, match="two or"):
        groundres.compare(["hammond-undamped"])
