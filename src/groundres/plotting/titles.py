"""Case titles and names as pictures show them: literally.

matplotlib reads text between two ``$`` as mathtext (and raises on what it
cannot parse, e.g. ``$\\frac{1}{2}$``): user text (a case's title, a case
file's stem) has every ``$`` escaped, so that it shows as typed. A character
the pictures' fonts cannot draw (an emoji in a title, with matplotlib's own
DejaVu Sans) is shown as the replacement character, the rest as typed; control
characters are dropped.
"""

from __future__ import annotations

import functools
import textwrap
import unicodedata

#: Longest case title a picture shows [characters]; a longer one is cut with an ellipsis.
TITLE_LENGTH = 150
#: Longest line of a title [characters]: a longer title is broken into lines (the narrowest
#: picture, the Coleman diagram's frequency panel, holds about 100 characters at its title's size).
TITLE_LINE = 90


#: What a character no font of the pictures has is drawn as (or "?" where the fonts lack it too).
REPLACEMENT = "\ufffd"


def _drawable(text) -> str:
    """``text`` without control characters (which no font draws), and each character the
    pictures' fonts lack (:func:`_glyphs`) replaced by :data:`REPLACEMENT` (marks and format
    characters, an emoji's variation selector or joiner, dropped), so that matplotlib draws
    all of it without a missing-glyph warning."""
    text = "".join(ch for ch in str(text) if unicodedata.category(ch) != "Cc")
    if text.isascii():
        return text
    glyphs = _glyphs()
    replacement = REPLACEMENT if ord(REPLACEMENT) in glyphs else "?"
    return "".join(
        ch
        if ch == "\n" or ord(ch) in glyphs
        else ("" if unicodedata.category(ch) in ("Mn", "Me", "Cf") else replacement)
        for ch in text
    )


def _glyphs() -> frozenset:
    """Code points the default font of the pictures, with its fallbacks, can draw."""
    from matplotlib import font_manager

    prop = font_manager.FontProperties()
    # (the fonts text is drawn with: the family's list, each found font a fallback of the first)
    find = getattr(font_manager.fontManager, "_find_fonts_by_props", None)
    return _charmap(tuple(find(prop)) if find is not None else (font_manager.findfont(prop),))


@functools.lru_cache(maxsize=8)
def _charmap(paths: tuple) -> frozenset:
    from matplotlib.font_manager import get_font

    return frozenset().union(*(get_font(path).get_charmap() for path in paths))


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
