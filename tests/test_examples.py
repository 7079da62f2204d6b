"""Every example in examples/ runs headless, quickly, and writes what it says.

Each Python script or shell script found in examples/ is one test (a new
example is picked up without changes here): run as its own process, from an
empty working folder, with its output folder as the first argument. The
venv's ``groundres`` comes first on the PATH even when pytest was started
without activating the venv.
"""

import os
import subprocess
import sys
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
SCRIPTS = sorted(p for p in EXAMPLES.iterdir() if p.suffix in (".py", ".sh"))

#: Files each example must write into its output folder (glob patterns).
#: An example not listed here must write at least one file.
EXPECTED = {
    "failed-damper.py": ["coleman.png", "simulation.png"],
    "hammond-study.sh": ["map/study.nc", "map/map.png", "boundary/boundary.nc", "boundary/map.png"],
    "own-rotor.py": ["my-rotor.toml", "coleman.png"],
    "seed-figures-11-13.sh": [
        f"figure-{figure}/{where}/{name}"
        for figure in (11, 12, 13)
        for where in ("below", "inside", "above")
        for name in ("phasors.json", "phasors.csv", "phasors_regressive-lag.png")
    ],
    "shipped-case.py": [
        f"{kind}-{case}.{suffix}"
        for case in ("hammond-undamped", "hammond-1974", "hammond-1974-one-damper")
        for kind, suffix in (("coleman", "png"), ("summary", "json"))
    ],
    "xarray-netcdf.py": ["sweep.nc", "regressive-lag.csv", "damping-ratio.png"],
}

#: Seconds after which an example counts as hung (they take well under a minute).
TIMEOUT = 300


def test_examples_found():
    assert {p.name for p in SCRIPTS} >= set(EXPECTED)


@pytest.mark.parametrize("script", SCRIPTS, ids=lambda p: p.name)
def test_example(script, tmp_path):
    out = tmp_path / "out"
    runner = sys.executable if script.suffix == ".py" else "bash"
    env = dict(os.environ, MPLBACKEND="Agg")
    env["PATH"] = os.pathsep.join([str(Path(sys.executable).parent), env.get("PATH", "")])
    proc = subprocess.run(
        [runner, str(script), str(out)],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=TIMEOUT,
    )
    assert proc.returncode == 0, f"{script.name} exited {proc.returncode}:\n{proc.stdout}\n{proc.stderr}"
    assert [p.name for p in tmp_path.iterdir()] == ["out"], "an example writes only into its output folder"
    patterns = EXPECTED.get(script.name, ["**/*"])
    missing = [p for p in patterns if not any(f.is_file() for f in out.glob(p))]
    assert not missing, f"{script.name} did not write {missing}"
