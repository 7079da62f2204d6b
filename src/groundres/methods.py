"""The one vocabulary of analysis methods: which analysis a case gets, and its names.

A case is analysed by one of three methods, told apart by the transform that
removes the periodic coefficients of its equations (see ``docs/conventions.md``):

- ``Method.MULTIBLADE``, ``"multiblade-eigen"`` (form multiblade, option eigen):
  identical blades, N >= 3; multiblade coordinates make the equations
  time-invariant for any body;
- ``Method.ROTATING``, ``"rotating-eigen"`` (form rotating, option eigen):
  otherwise an isotropic body, in rotating axes;
- ``Method.FLOQUET``, ``"floquet"`` (form and option floquet): the equations
  are periodic in every frame (dissimilar blades, or two blades, on an
  anisotropic body).

A Method's value is the name results and files store (``summary.json``'s
``method``); ``option`` is the ``[sweep] method`` (and ``--method``) that
repeats it, one of :data:`OPTIONS`, where "auto" takes a time-invariant form
when the case has one. Every layer speaks of a Method: solvers carry one,
scans and searches ask ``method.periodic``, results store it.
"""

from __future__ import annotations

from enum import StrEnum

from .errors import MethodError

#: What ``[sweep] method`` and ``--method`` accept.
OPTIONS = ("auto", "eigen", "floquet")


class Method(StrEnum):
    """An analysis method; its value is the name results store."""

    MULTIBLADE = "multiblade-eigen"
    ROTATING = "rotating-eigen"
    FLOQUET = "floquet"

    @property
    def form(self) -> str:
        """The transform that makes the equations time-invariant, "multiblade" or "rotating";
        "floquet" where none does (the periodic equations are solved as they are)."""
        return self.value.removesuffix("-eigen")

    @property
    def option(self) -> str:
        """The method option that repeats this analysis: "eigen" or "floquet"."""
        return "floquet" if self is Method.FLOQUET else "eigen"

    @property
    def periodic(self) -> bool:
        """Whether the roots are Floquet exponents of periodic equations (each speed an
        integration over a period) rather than eigenvalues of time-invariant ones."""
        return self is Method.FLOQUET


def time_invariant(case) -> Method | None:
    """The eigen-analysis whose transform gives ``case`` constant coefficients, or None."""
    if case.rotor.identical and case.rotor.n_blades >= 3:
        return Method.MULTIBLADE
    if case.body.isotropic and not _tilts_under_torque(case):
        return Method.ROTATING
    return None


def _tilts_under_torque(case) -> bool:
    """A rotor in air on a body that pitches or rolls: the rotor's torque along the tilted
    shaft couples pitch and roll through the order of the gimbal's axes (roll, then pitch),
    which no turn about the shaft leaves alike: the body is isotropic only in vacuum."""
    return case.rotor.aero is not None and bool({"pitch", "roll"} & set(case.body.dofs))


def choose_method(case, option: str | None = None) -> Method:
    """The analysis of ``case`` for a method option ("auto", "eigen" or "floquet"; None:
    the case's own ``[sweep] method``).

    Raises
    ------
    MethodError
        For "eigen" on a case with periodic coefficients in every frame; its ``key`` is
        "method" for ``option`` and "[sweep] method" for the case's own.
    """
    key = "method" if option else "[sweep] method"  # (as an argument, or the case's own)
    option = option or case.sweep.method
    if option not in OPTIONS:
        raise MethodError(key, option, f"must be one of {list(OPTIONS)}")
    if option == "floquet":
        return Method.FLOQUET
    form = time_invariant(case)
    if option == "eigen" and form is None:
        raise MethodError(
            key,
            option,
            "this case has periodic coefficients in every frame (dissimilar blades or N = 2 on an "
            "anisotropic body, or on a body that pitches or rolls under a rotor in air), so it has no "
            "eigenvalues; use 'floquet' or 'auto'",
        )
    return form or Method.FLOQUET
