"""The gallery: the seed paper's figures computed from the shipped cases, judged, and put on one page.

Each figure of :mod:`groundres.pages.figures` is analysed (Coleman diagrams
in the paper's frame and the other, a Floquet diagram where the method is
Floquet, phasor diagrams below, inside and above the instability), judged by
:mod:`groundres.pages.verdicts`, and written as pictures, gallery.json and
an HTML page. Figures that share a case and method share its analysis.
"""

from __future__ import annotations

import numpy as np

from .figures import FIGURES, NUMBERS, Figure, figure
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

__all__ = ["FIGURES", "NUMBERS", "build", "gallery_page"]


class _Results:
    """Analyses of the gallery, each computed once (figures share cases and methods)."""

    def __init__(self, progress=None):
        self._done = {}
        self.progress = progress

    def get(self, case_name: str, method: str, frame: str, extra_speeds=()):
        from ..analysis import analyze
        from ..config import load_case

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
        verdict = compare_ranges(fig.ranges, main)
    else:
        verdict = _smeared_verdict(fig, main, results)
    extra = []
    if fig.method == "floquet":
        eigen = results.get(fig.case, "eigen", fig.frame) if fig.number == 9 else None
        if eigen is not None:
            diffs = [
                abs(a - b)
                for (s1, e1), (s2, e2) in zip(main.stability.unstable_ranges, eigen.stability.unstable_ranges)
                for a, b in ((s1, s2), (e1, e2))
            ]
            same = len(main.stability.unstable_ranges) == len(eigen.stability.unstable_ranges)
            worst = max(diffs, default=0.0)
            record["eigen_range_difference"] = worst
            extra.append(
                f"Against the eigen-analysis of Figure 8 the range ends differ by at most {worst:.2e} rad/s"
                + ("" if same else " (but the number of ranges differs)")
                + "."
            )
            if not same or worst > 1e-6 * main.case.sweep.reference:
                verdict.word = "differs"
                verdict.reason += " The Floquet and eigen-analyses of the same case disagree."
    return {"pictures": pictures, "extra": extra, "verdict": verdict}


def _smeared_verdict(fig: Figure, main, results: _Results) -> Verdict:
    """Figure 10: no number in the paper; the Floquet ranges against the smeared-damper approximation."""
    from ..analysis import analyze
    from ..config import load_case

    smeared, mean = smeared_case(load_case(fig.case))
    approx = analyze(smeared, frame=fig.frame, method="auto", lag_damping_search=False)
    found, near = ratio_ranges(main), ratio_ranges(approx)
    computed = (
        f"Floquet analysis: {ranges_text(found)}. The constant-coefficient approximation (every damper "
        f"{mean:.5g} N m s/rad, the average; {approx.method}): {ranges_text(near)}."
    )
    if found and not near:
        reason = (
            "The paper states no range; groundres finds the instability that only the periodic "
            "analysis sees: the smeared-damper approximation is stable, as Hammond (1974) found."
        )
        return Verdict("agrees in kind", computed, reason)
    reason = "The paper states no range; the numbers above are groundres's alone."
    return Verdict("agrees in kind", computed, reason)


def _phasors(fig: Figure, results: _Results, fmt: str, files: dict, record: dict) -> dict:
    from ..cli.common import fmt_speed
    from ..config import load_case
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
                "state": "growing" if shape.unstable else ("neutral" if shape.neutral else "decaying"),
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
        from ..config import load_case

        case = load_case(fig.case)
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


def gallery_page(data: dict, command_line: str = "") -> str:
    """The gallery's HTML page."""
    from .page import render

    counts = {}
    for s in data["sections"]:
        counts[s["verdict"].word] = counts.get(s["verdict"].word, 0) + 1
    return render(
        "gallery.html",
        title="groundres gallery: the seed paper's Figures 3 to 13",
        sections=data["sections"],
        counts=counts,
        tolerance=RANGE_TOLERANCE,
        quadrature=QUADRATURE_TOLERANCE,
        command_line=command_line,
    )
