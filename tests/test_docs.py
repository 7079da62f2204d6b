"""The documentation builds with Sphinx without a warning (docs/conf.py).

Every page (user guide, theory, nomenclature, gallery, the pages in docs/ and
the parts of the README they include) and the API reference from the
docstrings: a broken link, a heading an include no longer finds or a
docstring docutils cannot read fails the test, with Sphinx's messages. The
build runs in a subprocess, so that Sphinx's own deprecation warnings do not
meet this suite's warnings-as-errors; it runs no analysis (about 15 s).
"""

import subprocess
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parents[1] / "docs"


def test_documentation_builds_without_warnings(tmp_path):
    build = subprocess.run(
        [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html", str(DOCS), str(tmp_path)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert build.returncode == 0, f"sphinx-build failed:\n{build.stderr}\n{build.stdout}"
    assert (tmp_path / "index.html").is_file()
    assert (tmp_path / "api" / "public.html").is_file()
