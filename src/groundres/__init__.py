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
    "ModelRangeError": "assess.resolution",
    "load_case": "model.schema",
    "parse_case": "model.schema",
    "CaseError": "model.schema",
    "Blade": "model.params",
    "Body": "model.params",
    "Case": "model.params",
    "ParameterError": "model.params",
    "Rotor": "model.params",
    "Sweep": "model.params",
    "SweepResult": "results.sweep",
    "System": "model.system",
    "study": "studies.study",
    "StudyError": "studies.study",
    "compare": "results.comparison",
    "Comparison": "results.comparison",
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
