"""What every page shares: the templates, embedded pictures and numbers that carry their value."""

from __future__ import annotations

import base64
import io
import unicodedata
from datetime import UTC, datetime

from markupsafe import Markup, escape

from ..model.units import significant

#: MIME types of the pictures a page can embed.
MIME = {"png": "image/png", "svg": "image/svg+xml", "gif": "image/gif", "jpeg": "image/jpeg"}
#: Resolution of embedded raster pictures [dots per inch].
DPI = 110


def environment():
    """The Jinja2 environment of the shipped templates (autoescaping, undefined names an error)."""
    import jinja2

    env = jinja2.Environment(
        loader=jinja2.PackageLoader("groundres", "templates"),
        autoescape=True,
        undefined=jinja2.StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
        keep_trailing_newline=True,
    )
    env.globals["num"] = number
    env.globals["significant"] = significant
    env.finalize = printable
    return env


def printable(value):
    """What a page prints of a value: control characters (which HTML forbids or no browser shows) dropped
    from user text, tabs and line ends kept; the page's own markup (Markup) as it is."""
    if isinstance(value, str) and not isinstance(value, Markup):
        return "".join(ch for ch in value if ch in "\t\n\r" or unicodedata.category(ch) != "Cc")
    return value


def render(template: str, **context) -> str:
    """The page ``template`` filled with ``context`` (plus ``generated``, the UTC time)."""
    from .._version import __version__

    context.setdefault("generated", datetime.now(UTC).isoformat(timespec="seconds"))
    context.setdefault("version", __version__)
    return environment().get_template(template).render(**context)


def data_uri(data: bytes, fmt: str) -> str:
    """``data:`` URI of a picture's bytes."""
    return f"data:{MIME[fmt]};base64,{base64.b64encode(data).decode('ascii')}"


def figure_bytes(fig, fmt: str = "png", dpi: int = DPI) -> bytes:
    """A matplotlib figure saved into memory (png, svg or pdf)."""
    buffer = io.BytesIO()
    metadata = {"Date": None} if fmt == "svg" else None  # (an svg without a time stamp: reproducible)
    fig.savefig(buffer, format=fmt, dpi=dpi, metadata=metadata)
    return buffer.getvalue()


def picture(fig, fmt: str = "png") -> dict:
    """A figure to embed: ``{"uri": data URI, "bytes": file bytes in fmt, "fmt": fmt}``.

    A page embeds png or svg; for pdf the page embeds a png and ``bytes`` is
    the pdf, for the file written beside the page.
    """
    data = figure_bytes(fig, fmt)
    shown = data if fmt in ("png", "svg") else figure_bytes(fig, "png")
    return {"uri": data_uri(shown, "svg" if fmt == "svg" else "png"), "bytes": data, "fmt": fmt}


def number(value, key: str, text: str | None = None) -> Markup:
    """A number as a page shows it: ``text`` (default: 4 significant digits), its full
    value in ``data-value`` (Python's repr: round-trips) and its summary.json place in ``data-key``."""
    if value is None:
        return Markup('<span class="num none" data-key="{}" data-value="null">{}</span>').format(
            key, text if text is not None else "none"
        )
    shown = text if text is not None else f"{float(value):.4g}"
    return Markup('<span class="num" data-key="{}" data-value="{}">{}</span>').format(
        key, repr(float(value)), shown
    )


def paragraphs(text: str) -> Markup:
    """Plain text (a case's description) as paragraphs, escaped; blank lines separate them."""
    parts = [" ".join(p.split()) for p in text.strip().split("\n\n") if p.strip()]
    return Markup("").join(Markup("<p>{}</p>").format(escape(p)) for p in parts)
