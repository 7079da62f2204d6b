"""The documentation builds with Sphinx without a warning (docs/conf.py).

Every page (user guide, theory, nomenclature, gallery, the pages in docs/ and
the parts of the README they include) and the API reference from the
docstrings: a broken link, a heading an include no longer finds or a
docstring docutils cannot read fails the test, with Sphinx's messages. The
build runs in a subprocess, so that Sphinx's own deprecation warnings do not
meet this suite's warnings-as-errors; it runs no analysis (about 15 s).
"""

import re
import subprocess
import sys
from pathlib import Path

import pytest

DOCS = Path(__file__).resolve().parents[1] / "docs"


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    out = tmp_path_factory.mktemp("html")
    build = subprocess.run(
        [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html", str(DOCS), str(out)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    return build, out


def test_documentation_builds_without_warnings(built):
    build, out = built
    assert build.returncode == 0, f"sphinx-build failed:\n{build.stderr}\n{build.stdout}"
    assert (out / "index.html").is_file()
    assert (out / "api" / "public.html").is_file()


def test_pages_read_offline_with_their_math(built):
    """The math is MathML written at build time (docs/_ext/mathml.py): no page loads a script
    or a style sheet from the network, and no formula is left as raw LaTeX."""
    build, out = built
    assert build.returncode == 0
    theory = (out / "theory.html").read_text(encoding="utf-8")
    assert theory.count("<math") > 100  # (every formula of the theory page)
    for page in out.rglob("*.html"):
        html = page.read_text(encoding="utf-8")
        remote = re.findall(r"<(?:script|link)[^>]+(?:src|href)=\"(?:https?:)?//[^\"]+", html)
        assert not remote, (page.name, remote)
        assert "mathjax" not in html.lower().replace("mathjax_ignore", ""), page.name
        assert not re.search(r"\\\(|\\\[|\$\$", re.sub(r"<pre.*?</pre>", "", html, flags=re.S)), page.name
