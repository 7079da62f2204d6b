"""Math rendered at build time as MathML, which browsers display without scripts.

The pages must read offline: MathJax from a network CDN leaves raw LaTeX
on a machine without one. latex2mathml (a maintained, pure-Python
converter) turns each formula into MathML Core while Sphinx writes the
page; every current browser draws it natively. A formula the converter
cannot read fails the build with its text, rather than reaching a reader as
raw LaTeX.
"""

from __future__ import annotations

from docutils import nodes
from latex2mathml.converter import convert
from sphinx.errors import ExtensionError


def _mathml(latex: str, display: bool) -> str:
    try:
        return convert(latex.strip(), display="block" if display else "inline")
    except Exception as err:  # (any failure of the converter: name the formula)
        raise ExtensionError(f"math cannot be rendered as MathML: {latex.strip()!r} ({err})") from err


def visit_math(self, node):
    self.body.append(_mathml(node.astext(), display=False))
    raise nodes.SkipNode


def visit_math_block(self, node):
    number = node.get("number")
    label = f'<span class="eqno">({number})</span>' if number else ""
    ident = f' id="{node["ids"][0]}"' if node.get("ids") else ""
    self.body.append(f'<div class="math"{ident}>{label}{_mathml(node.astext(), display=True)}</div>\n')
    raise nodes.SkipNode


def setup(app):
    # (its style sheet, docs/_static/mathml.css, is the docs' html_css_files)
    app.add_html_math_renderer("mathml", (visit_math, None), (visit_math_block, None))
    return {"parallel_read_safe": True, "parallel_write_safe": True}
