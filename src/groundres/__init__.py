"""groundres: helicopter ground resonance from equations it derives itself.

The public API, loaded on first use so that ``import groundres`` (and the
command line's ``--help``) stay fast:

    >>> import groundres
    >>> case = groundres.load_case("hammond-1974")    # doctest: +SKIP
    >>> result = groundres.analyze(case)              # doctest: +SKIP
    >>> result.stability.unstable_ranges              # doctest: +SKIP
    []
"""

from importlib import import_module

from ._version import __version__

_API = {
    "analyze": "analysis",
    "choose_method": "analysis",
    "MethodError": "analysis",
    "ModelRangeError": "limits",
    "load_case": "config",
    "parse_case": "config",
    "CaseError": "config",
    "Blade": "params",
    "Body": "params",
    "Case": "params",
    "ParameterError": "params",
    "Rotor": "params",
    "Sweep": "params",
    "SweepResult": "results",
    "System": "system",
    "study": "studies",
    "StudyError": "studies",
    "compare": "comparison",
    "Comparison": "comparison",
}

__all__ = ["__version__", *_API]


def __getattr__(name):
    if name in _API:
        value = getattr(import_module(f".{_API[name]}", __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'groundres' has no attribute {name!r}")


def __dir__():
    return sorted(__all__)
