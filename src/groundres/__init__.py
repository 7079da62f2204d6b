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
    "load_case": "model.schema",
    "parse_case": "model.schema",
    "Blade": "model.params",
    "Rotor": "model.params",
    "Sweep": "model.params",
    "Case": "model.params",
    "Body": "model.body",
    "System": "model.system",
    "choose_method": "methods",
    "Method": "methods",
    "analyze": "analysis",
    "simulate": "analysis",
    "compare": "analysis",
    "limit_cycles": "analysis",
    "run_nonlinear": "nonlinear_runs",
    "search_threshold": "nonlinear_runs",
    "SweepResult": "results.sweep",
    "Simulation": "results.simulation",
    "Comparison": "results.comparison",
    "study": "studies.study",
    "InputError": "errors",
    "CaseError": "errors",
    "ParameterError": "errors",
    "MethodError": "errors",
    "ModelRangeError": "errors",
    "SpeedRangeError": "errors",
    "OutputFolderError": "errors",
    "StudyError": "errors",
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
