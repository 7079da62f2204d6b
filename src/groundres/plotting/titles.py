"""Case titles as pictures show them."""

from __future__ import annotations

import unicodedata

#: Longest case title a picture shows [characters]; a longer one is cut with an ellipsis.
TITLE_LENGTH = 150


def figure_title(text: str) -> str:
    """A case title as a picture shows it: control characters (which no font draws)
    dropped, and cut to :data:`TITLE_LENGTH` characters (matplotlib lays out a long
    title slowly, and it would not fit the figure)."""
    text = "".join(ch for ch in text if unicodedata.category(ch) != "Cc")
    return text if len(text) <= TITLE_LENGTH else text[: TITLE_LENGTH - 1] + "\u2026"
