"""Every error groundres raises for an input it cannot use.

Each names the key or option, the value and what is allowed, in one line fit
for the user. They share :class:`InputError`, which the command line turns
into exit status 2 with that line and no traceback; any other exception is a
failure of groundres itself (exit status 1).

- :class:`CaseError`: a case file that cannot be read or breaks the format;
- :class:`ParameterError`: a parameter value outside what the model allows;
- :class:`StudyError`: a study that cannot be set up (a varied key, a range, a store);
- :class:`MethodError`: a method that cannot analyse the case (eigen on periodic equations);
- :class:`ModelRangeError`: a case the model cannot resolve in double precision, or too costly;
- :class:`SpeedRangeError`: a rotor speed too close to zero for a periodic analysis;
- :class:`OutputFolderError`: an output folder groundres will not replace.
"""

from __future__ import annotations

import math
import os
import unicodedata

#: Longest ``repr`` of a value a message shows whole; a longer one keeps its start and end.
SHOWN_LENGTH = 60


def printable(text, keep: str = "\n") -> str:
    """``text`` with every control character (C0, DEL and C1) but those in ``keep`` written
    as its escape (``\\x1b``), so that no user text can drive a terminal (a title's
    ``ESC ] 0 ; ... BEL`` would set its window title, ``ESC [ 2 J`` clear it); and a byte of a
    file name that is no UTF-8 (a lone surrogate, which no output can encode) as ``\\xff``."""
    text = str(text)
    if all(ch in keep or unicodedata.category(ch) not in _ESCAPED for ch in text):
        return text
    return "".join(
        ch if ch in keep or unicodedata.category(ch) not in _ESCAPED else _escape(ch) for ch in text
    )


#: Unicode categories :func:`printable` escapes: controls, and the lone surrogates of bytes
#: that are no UTF-8.
_ESCAPED = ("Cc", "Cs")


def _escape(ch: str) -> str:
    if unicodedata.category(ch) == "Cs":  # (a byte the file system gave: its escape)
        try:
            return ch.encode("utf-8", "surrogateescape").decode("ascii", "backslashreplace")
        except UnicodeEncodeError:  # (a surrogate no byte gave)
            return f"\\u{ord(ch):04x}"
    return ch.encode("unicode_escape").decode()


def shown(value) -> str:
    """``repr(value)`` fit for a one-line message: long whole numbers and texts shortened."""
    if isinstance(value, int) and not isinstance(value, bool):
        digits = math.floor(abs(value).bit_length() * math.log10(2)) + 1 if value else 1
        if digits > 20:
            if digits > 4000:  # too long to convert to text at all
                return f"{'-' if value < 0 else ''}<a whole number of about {digits} digits>"
            text = str(value)
            return f"{text[:8]}...{text[-4:]} ({len(text.lstrip('-'))} digits)"
        return repr(value)
    return brief(printable(repr(value), keep=""))  # (repr escapes a string's; an object's may not)


def brief(text: str) -> str:
    """``text`` (a name, a title) whole up to :data:`SHOWN_LENGTH` characters, else its start
    and end around an ellipsis."""
    return text if len(text) <= SHOWN_LENGTH else f"{text[:40]}...{text[-12:]}"


def shown_path(path) -> str:
    """A file or folder name fit for a one-line message: quoted as ``repr`` quotes it, and past
    100 characters shortened to its start and end with its length in bytes."""
    text = os.fsdecode(path)
    if len(text) <= 100:
        return repr(text)
    try:
        size = len(os.fsencode(text))
    except UnicodeError:  # (a lone surrogate no file system takes)
        size = len(text.encode("utf-8", "surrogatepass"))
    return f"{text[:56] + '...' + text[-32:]!r} ({size} bytes)"


class InputError(ValueError):
    """An input groundres cannot use; the message says which, and what is allowed.

    Its message is :func:`printable`: a path or a title quoted in it cannot drive a terminal.
    """

    def __init__(self, *args):
        super().__init__(*(printable(a) if isinstance(a, str) else a for a in args))


class CaseError(InputError):
    """A case file that cannot be used, with a message fit for the user."""


class ParameterError(InputError):
    """A parameter value outside what the model allows.

    Attributes
    ----------
    key : str
        Name of the parameter (dotted path once the case reader adds its table).
    value : object
        The offending value.
    allowed : str
        What is allowed, in words.
    """

    def __init__(self, key: str, value, allowed: str):
        self.key, self.value, self.allowed = key, value, allowed
        super().__init__(f"{key} = {shown(value)}: {allowed}")

    def under(self, prefix: str) -> ParameterError:
        """The same error with its key placed under a table name."""
        return ParameterError(f"{prefix}.{self.key}" if prefix else self.key, self.value, self.allowed)


class StudyError(CaseError):
    """A study that cannot be set up (a key, a range or a count), fit for the user."""


class MethodError(InputError):
    """The method asked for cannot analyse this case.

    Attributes
    ----------
    key : str
        Where the method was asked for: "method" (an argument) or "[sweep] method" (the case's own).
    value : str
        The method asked for.
    allowed : str
        Why it cannot, and what is allowed.
    entry : str
        Which analysis of several it was (a comparison's entry), or "".
    """

    def __init__(self, key: str, value, allowed: str, entry: str = ""):
        self.key, self.value, self.allowed, self.entry = key, value, allowed, entry
        super().__init__(self.named(f"{key} = {shown(value)}"))

    def __reduce__(self):
        return (type(self), (self.key, self.value, self.allowed, self.entry))

    def named(self, asked: str) -> str:
        """The message, the method named as ``asked`` (e.g. "--method eigen" on the command line)."""
        return f"{self.entry}: {asked}: {self.allowed}" if self.entry else f"{asked}: {self.allowed}"


class ModelRangeError(InputError):
    """A case the model cannot resolve, or a sweep too costly; the message says why and what is allowed."""


class SpeedRangeError(InputError):
    """A rotor speed too low (too close to zero, but not zero) for Floquet analysis.

    Attributes
    ----------
    speed : float
        The speed [rad/s].
    """

    def __init__(self, speed: float, why: str):
        super().__init__(
            f"[sweep] Floquet analysis at {speed:.4g} rad/s {why}: the case's dampers or springs "
            "decay too fast for the periodic analysis at that rotor speed; start the sweep at a "
            "speed a few times higher, or use method = 'auto' where the case has a time-invariant form"
        )
        self.speed = speed


class OutputFolderError(InputError):
    """An output folder groundres will not replace: it holds files groundres did not write."""
