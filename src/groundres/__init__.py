"""groundres: helicopter ground resonance from equations it derives itself."""

from ._version import __version__
from .analysis import analyze, choose_method
from .config import CaseError, load_case, parse_case
from .params import Blade, Body, Case, ParameterError, Rotor, Sweep
from .results import SweepResult
from .system import System

__all__ = [
    "__version__",
    "analyze",
    "choose_method",
    "load_case",
    "parse_case",
    "CaseError",
    "ParameterError",
    "Blade",
    "Body",
    "Case",
    "Rotor",
    "Sweep",
    "SweepResult",
    "System",
]
