"""Case titles and names as pictures show them: literally.

matplotlib reads text between two ``$`` as mathtext (and raises on what it
cannot parse, e.g. ``$\\frac{1}{2}$``): user text (a case's title, a case
file's stem) has every ``$`` escaped, so that it shows as typed.
"""

from __future__ import annotations

import textwrap
import unicodedata

#: Longest case title a picture shows [characters]; a longer one is cut with an ellipsis.
TITLE_LENGTH = 150
#: Longest line of a title [characters]: a longer title is broken into lines (the narrowest
#: picture, the Coleman diagram's frequency panel, holds about 100 characters at its title's size).
TITLE_LINE = 90


def _drawable(text) -> str:
    """``text`` without control characters (which no font draws)."""
    return "".join(ch for ch in str(text) if unicodedata.category(ch) != "Cc")


def _escaped(text: str) -> str:
    """Every ``$`` escaped: matplotlib draws ``\\$`` as ``$``, and text without an
    unescaped ``$`` is never mathtext."""
    return text.replace("$", r"\$")


def literal(text: str) -> str:
    """User text (a case file's stem, a name) as a picture shows it, literally:
    control characters dropped and every ``$`` escaped."""
    return _escaped(_drawable(text))


def figure_title(text: str, line: int = 0) -> str:
    """A case title as a picture shows it: as :func:`literal`, cut to
    :data:`TITLE_LENGTH` characters (matplotlib lays out a long title slowly, and
    it would not fit the figure) and broken into lines of ``line`` characters
    (:data:`TITLE_LINE` by default; fewer over narrow axes)."""
    text = " ".join(_drawable(text).split())
    text = text if len(text) <= TITLE_LENGTH else text[: TITLE_LENGTH - 1] + "\u2026"
    return _escaped("\n".join(textwrap.wrap(text, line or TITLE_LINE)) or text)
