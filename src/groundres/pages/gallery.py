"""The gallery: the seed paper's figures computed from the shipped cases, judged, and put on one page.

Each figure of :mod:`groundres.pages.figures` is analysed (Coleman diagrams
in the paper's frame and the other, a Floquet diagram where the method is
Floquet, phasor diagrams below, inside and above the instability), judged by
:mod:`groundres.pages.verdicts`, and written as pictures, gallery.json and
an HTML page. Figures that share a case and method share its analysis.
"""

from __future__ import annotations

import numpy as np

from ..results.comparison import SPEED_ROUND_OFF
from .figures import NUMBERS, Figure, figure
from .verdicts import (
    QUADRATURE_TOLERANCE,
    RANGE_TOLERANCE,
    Verdict,
    compare_ranges,
    in_phase_part,
    other_frame,
    phasor_verdict,
    ranges_text,
    ratio_ranges,
    smeared_case,
    speed_place,
    speeds_si,
)


class _Results:
    """Analyses of the gallery, each computed once (figures share cases and methods)."""

    def __init__(self):
        self._done = {}

    def get(self, case_name: str, method: str, frame: str, extra_speeds=()):
        from ..analysis import analyze
        from ..model.schema import load_case

        key = (case_name, method, frame, tuple(extra_speeds))
        if key not in self._done:
            case = load_case(case_name)
            speeds = np.union1d(case.sweep.speeds, extra_speeds) if len(extra_speeds) else None
            self._done[key] = analyze(
                case, frame=frame, method=method, speeds=speeds, lag_damping_search=False
            )
        return self._done[key]


def _picture(fig, fmt: str, name: str, caption: str, files: dict) -> dict:
    """A picture of the page: embedded, and its file (in ``fmt``) added to ``files``."""
    from .page import picture

    pic = picture(fig, fmt)
    files[name] = pic["bytes"]
    return {"uri": pic["uri"], "file": name, "caption": caption}


def _coleman(fig: Figure, results: _Results, fmt: str, files: dict, record: dict) -> dict:
    main = results.get(fig.case, fig.method, fig.frame)
    other = results.get(fig.case, fig.method, other_frame(fig.frame))
    pictures = []
    for result, role in ((main, "the paper's frame"), (other, "the other frame")):
        name = f"figure-{fig.number:02d}-coleman-{result.frame}.{fmt}"
        caption = f"Coleman diagram, {result.frame} frame ({role})"
        pictures.append(_picture(result.plot(), fmt, name, caption, files))
    if main.method == "floquet":
        from ..plotting.multipliers import multiplier_diagram

        name = f"figure-{fig.number:02d}-multipliers.{fmt}"
        caption = (
            "Floquet diagram: the characteristic multipliers over one revolution; a root grows where its "
            "multiplier leaves the unit circle"
        )
        pictures.append(_picture(multiplier_diagram(main), fmt, name, caption, files))
    summary = main.summary()
    record["summary"] = summary
    record["method"] = main.method
    if fig.ranges is not None:
        verdict = compare_ranges(fig.ranges, main, fig.chosen)
    else:
        verdict = _smeared_verdict(fig, main)
    extra = []
    if fig.equals is not None:
        extra.append(_same_as(fig, main, results, verdict, record))
    return {"pictures": pictures, "extra": extra, "verdict": verdict}


def _same_as(fig: Figure, main, results: _Results, verdict: Verdict, record: dict) -> str:
    """The analysis of ``fig`` against that of the figure it repeats by another method (to round-off)."""
    twin = figure(fig.equals)
    other = results.get(twin.case, twin.method, fig.frame)
    mine, theirs = main.stability.unstable_ranges, other.stability.unstable_ranges
    same = len(mine) == len(theirs)
    worst = max((abs(a - b) / b for r, q in zip(mine, theirs) for a, b in zip(r, q)), default=0.0)
    record["range_difference_from_figure"] = {"figure": twin.number, "relative": worst if same else None}
    if same and worst <= SPEED_ROUND_OFF:
        return (
            f"Its range ends equal those of the {other.method} analysis of Figure {twin.number} to round-off "
            f"(relative difference under {SPEED_ROUND_OFF:g})."
        )
    verdict.word = "differs"
    verdict.reason += f" The {main.method} and {other.method} analyses of the same case disagree."
    if not same:
        return f"It finds {len(mine)} range(s), Figure {twin.number}'s {other.method} analysis {len(theirs)}."
    return f"Its range ends differ from those of Figure {twin.number} by up to {worst:.2g} of the speed."


def _smeared_verdict(fig: Figure, main) -> Verdict:
    """Figure 10: no number in the paper; the Floquet ranges against the smeared-damper approximation."""
    from ..analysis import analyze
    from ..model.schema import load_case

    smeared, mean = smeared_case(load_case(fig.case))
    approx = analyze(smeared, frame=fig.frame, method="auto", lag_damping_search=False)
    found, near = ratio_ranges(main), ratio_ranges(approx)
    computed = (
        f"Floquet analysis: {ranges_text(found)}. The constant-coefficient approximation (every damper "
        f"{mean:.5g} N m s/rad, the average; {approx.method}): {ranges_text(near)}."
    )
    reason = "The paper states no range for this figure, so there is nothing to check against it."
    if found and not near:
        reason += (
            " The periodic analysis finds an instability that the smeared-damper approximation misses "
            "altogether (Hammond 1974 reports that this approximation underestimates it)."
        )
    return Verdict("nothing to compare", computed, reason)


def _phasors(fig: Figure, results: _Results, fmt: str, files: dict, record: dict) -> dict:
    from ..model.schema import load_case
    from ..model.units import fmt_speed
    from ..plotting.phasors import phasor_diagram

    case = load_case(fig.case)
    ws = speeds_si(fig, case)
    result = results.get(fig.case, "auto", "nonrotating", tuple(ws))
    ranges = result.stability.unstable_ranges
    i_in = int(np.argmin(np.abs(result.rotor_speed - ws[1])))
    label = result.labels[int(np.argmax(result.real_part[i_in]))]
    cells, pictures = [], []
    for where, w in zip(("below", "inside", "above"), ws):
        shape = result.mode(label, w)
        text = fmt_speed(shape.rotor_speed, case.sweep)
        name = f"figure-{fig.number:02d}-phasors-{where}.{fmt}"
        caption = (
            f"phasors of the {label} mode {where} the instability, at {text}; "
            "top row nonrotating, bottom row rotating axes"
        )
        pictures.append(_picture(phasor_diagram(shape, speed_text=text), fmt, name, caption, files))
        cells.append(
            {
                "where": where,
                "speed": shape.rotor_speed,
                "speed_text": text,
                "mode": label,
                "real_part": shape.eigenvalue.real,
                "state": shape.state,
                "in_phase": in_phase_part(shape),
                "placed": speed_place(shape.rotor_speed, ranges, where),
            }
        )
    record["phasors"] = cells
    record["method"] = result.method
    return {"pictures": pictures, "extra": [], "verdict": phasor_verdict(cells)}


def build(numbers=NUMBERS, fmt: str = "png", progress=None) -> tuple[dict, dict[str, bytes]]:
    """Compute the gallery's figures.

    Returns ``(data, files)``: ``data`` is the page's content and gallery.json
    (``data["json"]``); ``files`` maps picture file names to their bytes.
    ``progress(done, total)`` is called after each figure.
    """
    results = _Results()
    files: dict[str, bytes] = {}
    sections, records = [], []
    chosen = [figure(n) for n in numbers]
    for k, fig in enumerate(chosen):
        record = {"number": fig.number, "case": fig.case, "kind": fig.kind, "frame": fig.frame}
        body = (_coleman if fig.kind == "coleman" else _phasors)(fig, results, fmt, files, record)
        verdict = body["verdict"]
        record.update(verdict=verdict.word, computed=verdict.computed, reason=verdict.reason)
        records.append(record)
        from ..model.schema import load_case

        case = load_case(fig.case)
        record["configuration"] = configuration_text(case)
        sections.append({"figure": fig, "case": case, "record": record, "index": k, **body})
        if progress is not None:
            progress(k + 1, len(chosen))
    data = {
        "sections": sections,
        "json": {
            "paper": "Multibladed rotor helicopter ground resonance including eigenvector analysis",
            "range_tolerance": RANGE_TOLERANCE,
            "quadrature_tolerance": QUADRATURE_TOLERANCE,
            "figures": records,
        },
    }
    return data, files


def configuration_text(case) -> str:
    """The case in one line: blades, body, dampers and the lag frequency at the reference speed."""
    from ..assess.deutsch import lag_frequency_per_rev

    rotor, body, sweep = case.rotor, case.body, case.sweep
    dampers = sorted({b.lag_damping for b in rotor.blades})
    if len(dampers) == 1:
        lag = f"lag dampers {dampers[0]:g} N m s/rad" if dampers[0] else "no lag dampers"
    else:
        lag = (
            "lag dampers "
            + ", ".join(f"{b.lag_damping:g}" for b in rotor.blades)
            + " N m s/rad (blade by blade)"
        )
    if rotor.dampers:
        kinds = sorted({d.kind for d in rotor.dampers})
        lag = ("" if lag == "no lag dampers" else f"{lag}, ") + f"damper rods ({', '.join(kinds)})"
    hub = "isotropic" if body.isotropic else "anisotropic"
    if body.form == "modal":
        damped = any(getattr(body, f"damping_{d}", 0.0) for d in body.dofs)
        support = f"body {', '.join(body.dofs)} ({hub}, {'damped' if damped else 'undamped'})"
    else:
        support = f"rigid body on {len(body.gear)} gear legs, moving in {', '.join(body.dofs)}"
    parts = [f"{rotor.n_blades} blades" + (" with flap" if rotor.flap else ""), lag, support]
    if sweep.reference:
        nu = lag_frequency_per_rev(rotor, sweep.reference)
        parts.append(f"lag frequency {nu:.3g}/rev at the reference speed")
    return "; ".join(parts) + "."


def figures_text(sections) -> str:
    """ "Figures 3 to 13", "Figure 9" or "Figures 3, 5 and 9" for the figures on a page."""
    numbers = [s["figure"].number for s in sections]
    if len(numbers) == 1:
        return f"Figure {numbers[0]}"
    if numbers == list(range(numbers[0], numbers[-1] + 1)):
        return f"Figures {numbers[0]} to {numbers[-1]}"
    return f"Figures {', '.join(map(str, numbers[:-1]))} and {numbers[-1]}"


def gallery_page(data: dict, command_line: str = "") -> str:
    """The gallery's HTML page."""
    from .page import render

    counts = {}
    for s in data["sections"]:
        counts[s["verdict"].word] = counts.get(s["verdict"].word, 0) + 1
    return render(
        "gallery.html",
        title=f"groundres gallery: the seed paper's {figures_text(data['sections'])}",
        heading=figures_text(data["sections"]),
        sections=data["sections"],
        counts=counts,
        tolerance=RANGE_TOLERANCE,
        quadrature=QUADRATURE_TOLERANCE,
        command_line=command_line,
    )
