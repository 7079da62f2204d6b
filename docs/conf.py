"""Sphinx configuration of the groundres documentation.

Build (from the checkout): ``python -m sphinx -b html docs docs/_build/html``.
The pages are Markdown (MyST), readable on GitHub as they are; the API
reference comes from the numpydoc docstrings (autodoc + napoleon). Nothing is
fetched and no analysis runs at build time.
"""

import os
import re
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
REPOSITORY = DOCS.parent
# Document the package of this checkout, not whatever version is installed.
sys.path.insert(0, str(REPOSITORY / "src"))
# The docs' own Sphinx extension (math as MathML, docs/_ext/mathml.py).
sys.path.insert(0, str(DOCS / "_ext"))

from groundres import __version__  # noqa: E402

project = "groundres"
author = "the groundres developers"
copyright = "the groundres developers"
version = release = __version__

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.napoleon",
    "mathml",
    "sphinx.ext.viewcode",
]

source_suffix = {".md": "markdown"}
# Math is MathML written at build time (docs/_ext/mathml.py): the pages need no script
# and no network to show it.
html_math_renderer = "mathml"
root_doc = "index"
exclude_patterns = ["_build"]

# -- MyST (Markdown) -----------------------------------------------------------
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence"]
# Links such as [text](conventions.md#what-the-model-can-represent) resolve to the
# heading of that page, as they do on GitHub.
myst_heading_anchors = 3

# -- API reference -------------------------------------------------------------
napoleon_google_docstring = False
napoleon_numpy_docstring = True
autodoc_member_order = "bysource"
autodoc_typehints = "signature"
autodoc_default_options = {"members": True}


def _no_inline_type(app, what, name, obj, options, lines):
    """Keep napoleon from reading a property's or attribute's first line as "type: text".

    napoleon takes the part of an attribute docstring's first line before a
    colon for its type; groundres writes prose there ("True when ...: ...").
    A blank first line leaves the whole docstring as description.
    """
    if what in ("attribute", "property", "data") and lines and lines[0].strip():
        lines.insert(0, "")


#: A Markdown link or image target: ](target) or ](target#anchor), not a URL or an anchor.
_LINK = re.compile(r"\]\((?![a-z]+:|#)([^)\s#]+)(#[^)\s]*)?\)")


def _repository_links(app, relative_path, parent_docname, content):
    """Links of an included file outside docs/ (the README) to other repository files.

    The README's links are relative to the repository root. Those into docs/
    are made relative by the include directive's ``relative-docs`` and
    ``relative-images`` options; a link to any other file of the repository
    (``examples/README.md``, say) becomes a download of that file, so that it
    works in the built site too. A link to nothing that exists is left as it
    is, and the build warns.
    """
    included = (DOCS / relative_path).resolve()
    if included.is_relative_to(DOCS):
        return

    def relink(match):
        target, anchor = match.group(1), match.group(2) or ""
        path = (included.parent / target).resolve()
        if path.is_relative_to(DOCS) or not path.is_file():
            return match.group(0)
        return f"](path:{os.path.relpath(path, DOCS)}{anchor})"

    content[0] = _LINK.sub(relink, content[0])


def setup(app):
    # (runs before napoleon, which listens to the same event at the default priority 500)
    app.connect("autodoc-process-docstring", _no_inline_type, priority=100)
    app.connect("include-read", _repository_links)


# -- HTML ------------------------------------------------------------------------
html_theme = "furo"
html_title = f"groundres {release}"
html_static_path = ["_static"]
html_css_files = ["mathml.css"]
