"""Design studies (issue 11): grids of case keys, single failures, Dask, the store and resume.

The study's measures at a grid point must be those of ``groundres run`` on the
case with that value written into its file; a study on a local Dask cluster
of 2 workers must equal the same study computed in this process, bit for bit;
an interrupted study resumes without computing its finished chunks again.
"""

import tomllib

import numpy as np
import pytest
import xarray as xr
from click.testing import CliRunner

from conftest import HAMMOND_TOML
from groundres import analyze
from groundres.cli import main
from groundres.errors import StudyError
from groundres.model.schema import parse_case
from groundres.studies import run, store
from groundres.studies.grid import make_grid, numeric_keys, parse_values
from groundres.studies.study import study

# The Hammond rotor on its hub, a short sweep (Floquet where a damper fails).
SMALL = HAMMOND_TOML.replace("points = 60", "points = 24").replace("start = 0.5", "start = 10.0")


def small_case(text=SMALL):
    import tomllib

    return parse_case(tomllib.loads(text), "small", text)


VARY = {"rotor.lag_damping": "1500:6000:3", "body.damping_x": [2.0e4, 6.0e4]}


@pytest.fixture(scope="module")
def serial():
    return study(small_case(), VARY, failures="single")


def test_grid_dimensions_coordinates_and_attributes(serial):
    assert serial.max_real_part.dims == ("rotor.lag_damping", "body.damping_x", "failure")
    assert list(serial.failure.values) == ["none", "blade 1", "blade 2", "blade 3", "blade 4"]
    np.testing.assert_array_equal(serial["rotor.lag_damping"], [1500.0, 3750.0, 6000.0])
    assert serial["rotor.lag_damping"].attrs["units"] == "N m s/rad"
    assert serial["body.damping_x"].attrs["units"] == "N s/m"
    for name, unit in [
        ("max_real_part", "1/s"),
        ("unstable_width", "rad/s"),
        ("first_unstable_speed", "rad/s"),
    ]:
        assert serial[name].attrs["units"] == unit and serial[name].attrs["long_name"]
    assert serial.attrs["case_text"] == SMALL and serial.attrs["groundres_version"]
    assert (serial.error.values == "").all()
    # a failed damper is never better than all working, and the worst is unstable
    assert (serial.max_real_part.sel(failure="none") <= serial.max_real_part.max("failure")).all()


def test_each_point_equals_a_run_of_the_case_with_that_value_written_in(serial):
    for lag, hub, failure in [
        (1500.0, 2.0e4, "none"),
        (6000.0, 6.0e4, "blade 2"),
        (3750.0, 2.0e4, "blade 4"),
    ]:
        text = SMALL.replace("lag_damping = 4067.5", f"lag_damping = {lag!r}")
        text = text.replace("damping_x = 51078.7", f"damping_x = {hub!r}")
        if failure != "none":
            text += f"\n[[rotor.blade]]\nindex = {failure.split()[-1]}\nlag_damping = 0.0\n"
        stability = analyze(small_case(text), lag_damping_search=False).stability
        point = serial.sel({"rotor.lag_damping": lag, "body.damping_x": hub, "failure": failure})
        # (blade k's failure on alike blades is blade 1's turned: computed once, equal to the
        # run of blade k's case to the integration's accuracy, 1e-9 1/s in a real part and
        # 1e-10 relative in a range end)
        assert float(point.max_real_part) == pytest.approx(stability.max_real_part[0], rel=1e-9, abs=1e-9)
        assert float(point.min_damping_ratio) == pytest.approx(stability.min_damping_ratio[0], abs=1e-9)
        assert bool(point.stable) == stability.stable
        widths = sum(b - a for a, b in stability.unstable_ranges)
        assert float(point.unstable_width) == pytest.approx(widths, rel=1e-9, abs=1e-9)
        first = stability.unstable_ranges[0][0] if stability.unstable_ranges else np.nan
        np.testing.assert_allclose(float(point.first_unstable_speed), first, rtol=1e-10)
        if failure in ("none", "blade 1"):  # (computed as the run computes them: identical)
            assert float(point.max_real_part) == stability.max_real_part[0]


@pytest.mark.slow
def test_a_local_cluster_of_two_workers_equals_the_serial_study(serial):
    client = run.local_client(2)
    try:
        assert len(client.scheduler_info()["workers"]) == 2
        distributed = study(small_case(), VARY, failures="single", client=client)
    finally:
        cluster = client.cluster
        client.close()
        cluster.close()
    xr.testing.assert_identical(distributed, serial)


def test_an_interrupted_study_resumes_without_computing_its_finished_chunks(tmp_path, monkeypatch, serial):
    computed = []
    original = run.compute_points

    def interrupted(data, source, grid, flats):
        if len(computed) == 3:
            raise KeyboardInterrupt
        computed.append(list(flats))
        return original(data, source, grid, flats)

    monkeypatch.setattr(run, "compute_points", interrupted)
    monkeypatch.setattr(run, "CHUNK_COUNT", 1000)  # (small chunks: several for this grid)
    with pytest.raises(KeyboardInterrupt):
        study(small_case(), VARY, failures="single", out=tmp_path)
    first = [tuple(c) for c in computed]
    assert len(first) == 3
    computed.clear()
    monkeypatch.setattr(run, "compute_points", lambda *a: (computed.append(list(a[3])), original(*a))[1])
    resumed = study(small_case(), VARY, failures="single", out=tmp_path)
    again = {tuple(c) for c in computed}
    assert not again & set(first)  # finished chunks are not computed again
    assert sum(map(len, first)) + sum(map(len, again)) == resumed.max_real_part.size
    xr.testing.assert_identical(resumed.drop_attrs(), serial.drop_attrs())
    on_disk = xr.open_dataset(tmp_path / "study.nc").load()
    np.testing.assert_array_equal(on_disk.max_real_part.values, serial.max_real_part.values)


def test_a_store_made_for_another_case_or_grid_is_refused(tmp_path):
    vary = {"rotor.lag_damping": [2000.0, 4000.0]}
    study(small_case(), vary, out=tmp_path)
    other = SMALL.replace("damping_y = 25539.35", "damping_y = 30000.0")
    with pytest.raises(StudyError, match="another case"):
        study(small_case(other), vary, out=tmp_path)
    with pytest.raises(StudyError, match="another grid"):
        study(small_case(), {"rotor.lag_damping": [2000.0, 5000.0]}, out=tmp_path)


def test_a_point_made_invalid_by_its_value_is_recorded_and_the_study_goes_on():
    ds = study(small_case(), {"rotor.lag_damping": [-100.0, 4067.5]})
    bad, good = ds.isel({"rotor.lag_damping": 0}), ds.isel({"rotor.lag_damping": 1})
    assert "lag_damping" in str(bad.error.values) and np.isnan(float(bad.max_real_part))
    assert str(good.error.values) == "" and np.isfinite(float(good.max_real_part))


def test_every_number_key_of_the_format_is_variable():
    keys = numeric_keys()
    for key in (
        "rotor.lag_damping",
        "body.damping_x",
        "sweep.stop",
        "rotor.blade[k].lag_damping",
        "rotor.blades",
    ):
        assert key in keys
    np.testing.assert_array_equal(parse_values("rotor.blade[2].lag_damping", "0:10:3"), [0.0, 5.0, 10.0])
    np.testing.assert_allclose(parse_values("body.damping_x", "1:100:3:log"), [1.0, 10.0, 100.0])
    grid = make_grid(small_case(), {"sweep.stop": "30:40:2", "rotor.blade[2].lag_damping": "0:4000:2"})
    assert grid.shape == (2, 2)


@pytest.mark.parametrize(
    "args, words",
    [
        (["--vary", "rotor.lag_dampin=0:1:2"], ["rotor.lag_dampin", "rotor.lag_damping"]),
        (["--vary", "rotor.flap=0:1:2"], ["rotor.flap", "not a number"]),
        (["--vary", "rotor.lag_damping=0:1"], ["rotor.lag_damping", "START:STOP:COUNT"]),
        (["--vary", "rotor.lag_damping=0:1:0"], ["rotor.lag_damping", "COUNT"]),
        (["--vary", "rotor.lag_damping=a:1:3"], ["rotor.lag_damping", "numbers"]),
        (["--vary", "rotor.lag_damping=0:1:3:lin"], ["rotor.lag_damping", "log"]),
        (["--vary", "rotor.lag_damping=0:1:3:log"], ["rotor.lag_damping", "> 0"]),
        (["--vary", "rotor.blades=2:5:3"], ["rotor.blades", "whole number"]),
        (["--vary", "rotor.blade[9].lag_damping=0:1:3"], ["blade 9", "blades = 4"]),
        (["--vary", "rotor.lag_damping"], ["rotor.lag_damping", "KEY="]),
        (["--vary", "rotor.lag_damping=0:1:2", "--vary", "rotor.lag_damping=0:1:2"], ["twice"]),
        (
            ["--vary", "rotor.lag_damping=0:1:2", "--boundary", "body.damping_x"],
            ["--boundary", "body.damping_x"],
        ),
    ],
)
def test_bad_vary_options_exit_2_naming_the_key(tmp_path, args, words):
    case = tmp_path / "case.toml"
    case.write_text(SMALL)
    result = CliRunner().invoke(main, ["study", str(case), *args, "--out", str(tmp_path / "out")])
    assert result.exit_code == 2, result.output
    assert "Traceback" not in result.output
    for word in words:
        assert word in result.output
    assert not (tmp_path / "out").exists()


@pytest.mark.slow
def test_the_command_writes_the_store_the_netcdf_and_the_map(tmp_path):
    case = tmp_path / "case.toml"
    case.write_text(SMALL)
    out = tmp_path / "out"
    args = ["study", str(case), "--vary", "rotor.lag_damping=2000:6000:2", "--failures", "single"]
    result = CliRunner().invoke(main, [*args, "--out", str(out), "--workers", "2"])
    assert result.exit_code == 0, result.output
    for name in ("study.zarr", "study.nc", "map.png", "case.toml", "provenance.json"):
        assert (out / name).exists()
    assert "10 grid points" in result.output
    # the same command again: everything is done, nothing is computed; its map in another format
    # replaces the earlier one (a folder holds one map, this study's)
    again = CliRunner().invoke(main, [*args, "--out", str(out), "--workers", "1", "--format", "svg"])
    assert again.exit_code == 0, again.output
    assert "10 of them were found done in the store" in again.output
    assert (out / "map.svg").exists() and not (out / "map.png").exists()
    assert store.load(out / "study.zarr").max_real_part.shape == (2, 5)


def test_the_boundary_search_agrees_with_the_grid_to_its_spacing():
    from groundres.studies.study import boundary

    vary = {"rotor.lag_damping": "500:8000:16", "body.damping_x": [2.0e4, 8.0e4]}
    grid = study(small_case(), vary)
    edge = boundary(small_case(), vary, "rotor.lag_damping")
    lag = grid["rotor.lag_damping"].values
    for hub in (2.0e4, 8.0e4):
        stable = grid.stable.sel({"body.damping_x": hub}).values
        assert not stable[0] and stable[-1]  # (a boundary inside the range)
        first = int(np.argmax(stable))
        at = float(edge.boundary.sel({"body.damping_x": hub}))
        assert lag[first - 1] <= at <= lag[first]
        assert int(edge.evaluations.sel({"body.damping_x": hub})) < len(lag)
    assert edge.boundary.attrs["units"] == "N m s/rad"


def test_the_map_draws_the_boundary_where_the_boundary_search_finds_it():
    """The growth margin is continuous across the stability boundary: its zero, read off the
    grid by linear interpolation (as the map's contour draws it), lies where the boundary
    search (root finding on the verdict) finds the boundary, to a small part of the grid's
    spacing. The largest real part of every root was flat on the stable side (a creeping lag
    root of -0.005 1/s), and a map drawn from it put the boundary at 3730 N m s/rad against
    3087 for the Hammond rotor at body.damping_x = 70000 N s/m."""
    from groundres import load_case
    from groundres.plotting.study_map import study_map
    from groundres.studies.study import boundary

    case = load_case("hammond-1974")
    vary = {"rotor.lag_damping": "1000:9000:9", "body.damping_x": [4.0e4, 7.0e4]}
    grid = study(case, vary)
    edge = boundary(case, vary, "rotor.lag_damping")
    lag = grid["rotor.lag_damping"].values
    step = lag[1] - lag[0]
    for hub in (4.0e4, 7.0e4):
        growth = grid.growth_margin.sel({"body.damping_x": hub}).values
        stable = grid.stable.sel({"body.damping_x": hub}).values
        assert np.array_equal(stable, growth <= 0)  # (the margin's sign is the verdict)
        i = int(np.flatnonzero(np.diff(np.sign(growth)))[0])
        drawn = lag[i] - growth[i] * step / (growth[i + 1] - growth[i])
        found = float(edge.boundary.sel({"body.damping_x": hub}))
        assert abs(drawn - found) <= 0.1 * step, (hub, drawn, found)
    fig = study_map(grid, title="map")
    assert "stability boundary" in fig.axes[0].get_legend_handles_labels()[1]


@pytest.mark.slow
def test_the_command_runs_on_an_existing_cluster_by_its_address(tmp_path):
    case = tmp_path / "case.toml"
    case.write_text(SMALL)
    client = run.local_client(2)
    try:
        address = client.scheduler.address
        args = ["study", str(case), "--vary", "rotor.lag_damping=2000:6000:3", "--scheduler", address]
        result = CliRunner().invoke(main, [*args, "--out", str(tmp_path / "out")])
        assert result.exit_code == 0, result.output
        # the cluster is the user's: the study leaves it running
        assert len(client.scheduler_info()["workers"]) == 2
    finally:
        cluster = client.cluster
        client.close()
        cluster.close()
    ds = xr.open_dataset(tmp_path / "out" / "study.nc")
    assert ds.max_real_part.shape == (3,)


def test_an_unreachable_scheduler_is_a_clear_error(tmp_path):
    case = tmp_path / "case.toml"
    case.write_text(SMALL)
    args = ["study", str(case), "--vary", "rotor.lag_damping=2000:6000:3", "--scheduler", "tcp://127.0.0.1:9"]
    result = CliRunner().invoke(main, [*args, "--out", str(tmp_path / "out")])
    assert result.exit_code == 2, result.output
    assert "--scheduler" in result.output and "tcp://127.0.0.1:9" in result.output


@pytest.mark.parametrize(
    "args, words",
    [
        (
            ["--vary", "rotor.blade[2].lag_damping=0:1:2", "--vary", "rotor.blade[02].lag_damping=0:0:1"],
            ["twice"],
        ),
        (["--vary", "rotor.blade[2].index=1:3:2"], ["rotor.blade[2].index", "no number key"]),
        (["--vary", "rotor.blades=3:4:2", "--failures", "single"], ["--failures", "rotor.blades"]),
        (["--vary", "rotor.lag_damping=-1e308:1e308:3"], ["rotor.lag_damping", "too wide"]),
        (["--vary", "rotor.lag_damping=5:5:3"], ["rotor.lag_damping", "COUNT must be 1"]),
        (
            ["--vary", "rotor.lag_damping=0:1:2", "--out", "/proc/groundres-study"],
            ["--out", "cannot be made"],
        ),
    ],
)
def test_more_bad_studies_exit_2_before_any_work(tmp_path, args, words):
    case = tmp_path / "case.toml"
    case.write_text(SMALL)
    extra = [] if "--out" in args else ["--out", str(tmp_path / "out")]
    result = CliRunner().invoke(main, ["study", str(case), *args, *extra, "--workers", "1"])
    assert result.exit_code == 2, result.output
    assert "Traceback" not in result.output
    for word in words:
        assert word in result.output
    assert not (tmp_path / "out").exists()


def test_a_folder_of_another_study_is_refused(tmp_path):
    case, other = tmp_path / "case.toml", tmp_path / "other.toml"
    case.write_text(SMALL)
    other.write_text(SMALL.replace("damping_y = 25539.35", "damping_y = 30000.0"))
    out = ["--out", str(tmp_path / "out"), "--workers", "1"]
    assert (
        CliRunner()
        .invoke(main, ["study", str(case), "--vary", "rotor.lag_damping=2000:4000:2", *out])
        .exit_code
        == 0
    )
    for args, word in [
        (
            [str(other), "--vary", "rotor.lag_damping=2000:4000:2", "--boundary", "rotor.lag_damping"],
            "another case",
        ),
        (
            [str(case), "--vary", "rotor.lag_damping=2000:4000:2", "--boundary", "rotor.lag_damping"],
            "grid study",
        ),
    ]:
        result = CliRunner().invoke(main, ["study", *args, *out])
        assert result.exit_code == 2 and word in result.output, result.output


def test_a_fault_that_is_not_the_cases_is_not_recorded_as_a_failed_point(tmp_path, monkeypatch):
    """(A lost worker, memory: the task fails and its chunk is not done, so a resume computes it.)"""
    from groundres.studies import measures

    original = run.of_case

    def faulty(case):
        raise MemoryError("out of memory on this node")

    monkeypatch.setattr(run, "of_case", faulty)
    with pytest.raises(MemoryError):
        study(small_case(), {"rotor.lag_damping": [2000.0, 4000.0]}, out=tmp_path)
    monkeypatch.setattr(run, "of_case", original)
    ds = study(small_case(), {"rotor.lag_damping": [2000.0, 4000.0]}, out=tmp_path)
    assert (ds.error.values == "").all() and np.isfinite(ds.max_real_part.values).all()
    assert measures.POINT_ERRORS


def test_the_boundary_search_shares_a_failure_only_where_the_blades_are_alike_all_along():
    """Blade 2's own damper held at the rotor's value: alike at one point of the line only."""
    from groundres.studies.study import boundary

    vary = {"rotor.blade[2].lag_damping": [4067.5], "rotor.lag_damping": "500:6000:4"}
    edge = boundary(small_case(), vary, "rotor.lag_damping", failures="single")
    assert (edge.evaluations.values > 0).all()


def test_keys_of_repeated_tables_vary_the_entry_they_name():
    """rotor.damper[k] and body.gear[k]: the k-th table of the case file (1-based)."""
    from groundres import load_case
    from groundres.studies.grid import raw, varied_case

    assert {"rotor.damper[k].damping", "body.gear[k].stiffness_y", "rotor.blade[k].lag_damping"} <= set(
        numeric_keys()
    )
    skids = load_case("light-helicopter-skids")
    grid = make_grid(skids, {"body.gear[3].stiffness_y": "4e4:6e4:2"})
    varied = varied_case(raw(skids), grid.point(1)[0])
    assert [leg.stiffness_y for leg in varied.body.gear] == [5e4, 5e4, 6e4, 5e4]
    inter = load_case("hammond-interblade-one-failed")
    varied = varied_case(raw(inter), {"rotor.damper[2].damping": 1000.0})
    assert [d.damping for d in varied.rotor.dampers if d.blade == 1] == [1000.0]
    with pytest.raises(StudyError, match=r"body.gear\[5\].*1 to 4"):
        make_grid(skids, {"body.gear[5].stiffness_y": "4e4:6e4:2"})
    with pytest.raises(StudyError, match="no number key"):
        make_grid(skids, {"body.gear.stiffness_y": "4e4:6e4:2"})


def test_single_failures_of_damper_rods_equal_the_case_with_that_rod_failed():
    """--failures single on a rotor with inter-blade rods: one entry per rod, each the case with
    that rod overridden without damping (the shipped one-failed case for rod 1)."""
    import tomllib

    from groundres import load_case

    def short(name):
        text = (
            load_case(name)
            .text.replace("points = 400", "points = 24")
            .replace("start = 30.0", "start = 180.0")
        )
        return parse_case(tomllib.loads(text), name, text)

    ds = study(short("hammond-interblade"), {"rotor.damper[1].damping": [20086.42]}, failures="single")
    assert list(ds.failure.values) == ["none"] + [f"blade-to-blade rod {k}" for k in (1, 2, 3, 4)]
    stability = analyze(short("hammond-interblade-one-failed"), lag_damping_search=False).stability
    for k in (1, 3):  # (rods alike: every single failure is rod 1's turned, computed once)
        point = ds.sel(failure=f"blade-to-blade rod {k}").isel({"rotor.damper[1].damping": 0})
        assert float(point.max_real_part) == pytest.approx(stability.max_real_part[0], rel=1e-9, abs=1e-9)
        assert bool(point.stable) is False
    assert bool(ds.sel(failure="none").stable.values.all())


# -- studies at their promised speed (issue 23, item 4) ---------------------------------------


def test_the_store_opens_by_consolidated_metadata_without_a_warning(tmp_path):
    import warnings

    import zarr

    study(small_case(), {"rotor.lag_damping": "1500:6000:2"}, out=tmp_path)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # (xarray warns about a store without consolidated metadata)
        ds = xr.open_zarr(tmp_path / "study.zarr")
        assert ds.growth_margin.shape == (2,)
    assert zarr.open_consolidated(str(tmp_path / "study.zarr"), mode="r") is not None


def test_a_complete_study_answers_without_starting_a_cluster(tmp_path, monkeypatch):
    from groundres.cli import study as cli_study

    args = ["study", "small.toml", "--vary", "rotor.lag_damping=1500:6000:2", "--out", str(tmp_path / "s")]
    (tmp_path / "small.toml").write_text(SMALL)
    monkeypatch.chdir(tmp_path)
    started = []
    monkeypatch.setattr(cli_study, "_client", lambda *a: started.append(a) or None)
    first = CliRunner().invoke(main, args)
    assert first.exit_code == 0, first.output
    assert len(started) == 1  # (the first run asks for its cluster: here, none, so it computes in place)

    def no_cluster(*a):
        raise AssertionError("a cluster was started for a study that is complete")

    monkeypatch.setattr(cli_study, "_client", no_cluster)
    again = CliRunner().invoke(main, args)
    assert again.exit_code == 0, again.output
    assert "2 of them were found done in the store" in again.output


def test_worker_memory_is_bounded_and_reported():
    from distributed.system import MEMORY_LIMIT

    from groundres.cli.study import _memory_text

    for workers in (1, 2, 64):
        limit = run.worker_memory(workers)
        assert 0 < limit <= run.WORKER_MEMORY and limit <= MEMORY_LIMIT / workers + 1
    text = _memory_text([(int(0.5 * 2**30), 4 * 2**30), (int(0.25 * 2**30), 4 * 2**30)])
    assert text == "Workers: 2 (limit 4 GiB each); peak memory 0.5, 0.25 GiB."
    assert "limits set by the cluster" in _memory_text([(2**30, 0)])


def test_points_sets_the_speeds_of_every_sweep_and_the_store_records_them(tmp_path):
    from groundres.studies.grid import with_points

    fewer = study(small_case(), {"rotor.lag_damping": "1500:6000:2"}, points=12, out=tmp_path)
    written = small_case(SMALL.replace("points = 24", "points = 12"))
    same = study(written, {"rotor.lag_damping": "1500:6000:2"})
    for name in ("growth_margin", "max_real_part", "least_damping_ratio", "unstable_width"):
        np.testing.assert_array_equal(fewer[name].values, same[name].values)
    assert "points = 12" in fewer.attrs["case_text"]
    with pytest.raises(StudyError, match="another case"):
        study(small_case(), {"rotor.lag_damping": "1500:6000:2"}, points=13, out=tmp_path)
    with pytest.raises(StudyError, match=r"--points 1: \[sweep\] points = 1: must be a whole number from 2"):
        with_points(small_case(), 1)
    assert with_points(small_case(), None) is not None
    no_points = small_case(SMALL.replace("points = 24\n", ""))
    assert "points = 7" in with_points(no_points, 7).text


def test_a_study_beyond_its_time_limit_is_refused_before_any_cluster_with_its_estimate(tmp_path, monkeypatch):
    """A 1000 x 1000 grid of the Hammond rotor (about 0.1 s a sweep: days on two cores) is
    refused in about a second, before a cluster starts or the folder is made, with the estimate
    and what to change; --max-hours moves the limit, whose default is the library's."""
    from groundres.cli import study as cli_study
    from groundres.studies import cost

    monkeypatch.setattr(cli_study, "_client", lambda *a: pytest.fail("a cluster was started"))
    big = ["--vary", "rotor.lag_damping=1000:9000:1000", "--vary", "body.damping_x=10000:100000:1000"]
    out = tmp_path / "out"
    result = CliRunner().invoke(main, ["study", "hammond-1974", *big, "--out", str(out)])
    assert result.exit_code == 2, result.output
    message = " ".join(result.output.split())
    assert "1000000 sweeps of about" in message and "more than --max-hours 4" in message
    assert "--points" in message and "--boundary" in message
    assert not out.exists()
    option = next(p for p in cli_study.command.params if p.name == "max_hours")
    assert option.default == cost.MAX_HOURS
    # the estimate counts the failures (alike blades: one failure computed for all) and the lines
    case = parse_case(tomllib.loads(HAMMOND_TOML), "hammond", HAMMOND_TOML)
    grid = make_grid(case, {"rotor.lag_damping": "1000:9000:10", "body.damping_x": "1e4:1e5:3"}, "single")
    monkeypatch.setattr(cost, "sweep_seconds", lambda case, failure="none": 0.1 if failure == "none" else 0.4)
    est = cost.estimate(case, grid, grid.size, 2)
    assert (est.analyses, est.seconds) == (60, pytest.approx(0.25))
    lines = cost.estimate(case, grid, grid.size, 2, boundary="rotor.lag_damping")
    assert lines.analyses == 3 * 2 * cost.SWEEPS_PER_LINE
    half = cost.estimate(case, grid, grid.size // 2, 2)
    assert half.analyses == 30 and half.hours == pytest.approx(est.hours / 2)
    with pytest.raises(StudyError, match="more than --max-hours 0.001"):
        cost.check(est, hours=0.001)
    cost.check(est, hours=1.0)


def test_more_local_workers_than_the_machine_can_run_are_refused(tmp_path, monkeypatch):
    """--workers 512 on a two-core machine started hundreds of processes; the local cluster is
    held to four workers a core, refused before any work with the limit and the way to more."""
    from groundres.cli import study as cli_study

    monkeypatch.setattr(cli_study, "_client", lambda *a: pytest.fail("a cluster was started"))
    limit = cli_study.most_workers()
    args = ["study", "hammond-1974", "--vary", "rotor.lag_damping=1000:3000:2", "--out", str(tmp_path / "o")]
    result = CliRunner().invoke(main, [*args, "--workers", str(limit + 1)])
    assert result.exit_code == 2
    assert f"--workers {limit + 1}: at most {limit}" in " ".join(result.output.split())
    assert not (tmp_path / "o").exists()


def test_two_studies_into_one_folder_at_once_both_finish(tmp_path):
    """Two identical studies started at once into one folder wrote study.nc through one shared
    temporary name, and one failed (exit 1, PermissionError, or FileNotFoundError as one store
    was written over the other); a study now holds its folder while it writes there, and each
    writes study.nc through a name of its own."""
    import subprocess
    import sys

    case = tmp_path / "case.toml"
    case.write_text(HAMMOND_TOML)
    args = [
        sys.executable,
        "-m",
        "groundres.cli",
        "study",
        str(case),
        "--vary",
        "rotor.lag_damping=1000:3000:2",
    ]
    runs = [
        subprocess.Popen(
            [*args, "--workers", "1", "--out", str(tmp_path / "out")],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        for _ in range(2)
    ]
    outputs = [run.communicate(timeout=120) for run in runs]
    codes = sorted(run.returncode for run in runs)
    assert codes in ([0, 0], [0, 2]), outputs  # (one finishes; the other finishes too, or is refused)
    if codes == [0, 2]:
        assert any("another study is writing there now" in " ".join(err.split()) for _, err in outputs)
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == [
        ".groundres-study.lock",
        "case.toml",
        "map.png",
        "provenance.json",
        "study.nc",
        "study.zarr",
    ]


def test_a_boundary_along_a_range_of_one_value_is_refused_before_any_work(tmp_path, monkeypatch):
    """--boundary along a key of one value was refused only after the cluster had started and
    the folder been made; it is refused first, leaving nothing."""
    from groundres.cli import study as cli_study

    monkeypatch.setattr(cli_study, "_client", lambda *a: pytest.fail("a cluster was started"))
    args = ["study", "hammond-1974", "--vary", "rotor.lag_damping=1000:1000:1"]
    result = CliRunner().invoke(
        main, [*args, "--boundary", "rotor.lag_damping", "--out", str(tmp_path / "o")]
    )
    assert result.exit_code == 2 and "needs two different ends" in result.output
    assert not (tmp_path / "o").exists()


def test_a_law_s_keys_vary_its_limit_cycles_each_as_the_prediction_on_that_case():
    """Issue 26, item 6: a study of a relief valve's relief moment records the smallest threshold
    and the largest stable cycle (NaN without one) at every point, with one damper failed too
    (the Floquet route, each blade at its own amplitude), equal to the prediction on the case with
    that value written in; a linear case records NaN."""
    import math

    from groundres.assess.limit_cycles import predict
    from groundres.model.casefile import case_text

    text = (
        case_text("hammond-relief-valve")[0]
        .replace("points = 100", "points = 6")
        .replace("points = 400", "points = 30")
    )
    ds = study(
        parse_case(tomllib.loads(text), "relief", text),
        {"rotor.lag_damper.relief_moment": [600.0, 1000.0]},
        failures="single",
    )
    assert ds["rotor.lag_damper.relief_moment"].attrs["units"] == "N m"
    assert ds.smallest_threshold.attrs["units"] == "rad"
    for moment in (600.0, 1000.0):
        for failure in ("none", "blade 1"):
            written = text.replace("relief_moment = 813.5", f"relief_moment = {moment!r}")
            if failure != "none":
                written += '\n[[rotor.blade]]\nindex = 1\nlag_damper = "failed"\n'
            case = parse_case(tomllib.loads(written), "relief", written)
            speeds = np.linspace(case.sweep.start, case.sweep.stop, 6)
            found = predict(case, speeds, searched=case.limit_cycle.searched)
            thresholds = [c for c in found.cycles if not c.stable]
            point = ds.sel({"rotor.lag_damper.relief_moment": moment, "failure": failure})
            assert float(point.unbounded_speed_count) == len(found.unbounded())
            if found.unbounded():  # (blade 1 failed: at 242 rpm the linear rotor is unstable)
                assert failure != "none" and found.unbounded() == [3]
                assert float(point.smallest_threshold) == 0.0
                assert float(point.smallest_threshold_speed) == speeds[3]
            else:
                smallest = min(thresholds, key=lambda c: c.amplitude)
                assert float(point.smallest_threshold) == pytest.approx(smallest.amplitude, rel=1e-9)
                assert float(point.smallest_threshold_speed) == smallest.speed
            assert math.isnan(float(point.largest_stable_cycle))
    # the threshold rises with the relief moment
    assert float(ds.smallest_threshold.sel(failure="none")[1]) > float(
        ds.smallest_threshold.sel(failure="none")[0]
    )
    assert np.isnan(study(small_case(), {"rotor.lag_damping": [4067.5]}).smallest_threshold.values).all()


def test_where_any_disturbance_grows_at_some_speed_the_smallest_threshold_is_zero():
    """hammond-friction-link grows from any disturbance above 1.4 times its reference speed: the
    smallest threshold is 0 there (a threshold of 1.9 deg at a lower speed, which it used to
    record, flatters the design), with the number of such speeds, and the map draws them on its
    floor."""
    from groundres.assess.limit_cycles import predict
    from groundres.model.schema import load_case
    from groundres.plotting.study_map import _cycle_panel
    from groundres.studies.measures import MEASURES, cycle_measures

    case = load_case("hammond-friction-link")
    speeds = np.linspace(case.sweep.start, case.sweep.stop, case.limit_cycle.points)
    found = predict(case, speeds)
    unbounded = found.unbounded()
    assert unbounded and all(found.verdict(i) == "grows from any disturbance" for i in unbounded)
    assert any(not c.stable for c in found.cycles)  # (thresholds at lower speeds)
    measures = cycle_measures(case)
    assert measures["smallest_threshold"] == 0.0 and measures["unbounded_speed_count"] == len(unbounded)
    assert measures["smallest_threshold_speed"] == speeds[unbounded[0]]
    assert "0 where" in MEASURES["smallest_threshold"][2]
    from matplotlib.figure import Figure

    ax = Figure().subplots()
    part = xr.Dataset(
        {
            "smallest_threshold": ("p", [0.0, 0.02]),
            "largest_stable_cycle": ("p", [0.01, 0.015]),
        }
    )
    _cycle_panel(ax, np.array([1.0, 2.0]), [("none", part)], failures=False)
    floor = [line for line in ax.get_lines() if line.get_marker() == "v"]
    assert len(floor) == 1 and floor[0].get_xdata()[0] == 1.0
    assert floor[0].get_ydata()[0] == ax.get_ylim()[0]
