"""`groundres gallery`: the seed paper's Figures 3 to 13 from the shipped cases, on one HTML page."""

from __future__ import annotations

import shlex

import click

from ..errors import shown
from .common import FORMAT, Steps, check_out, fail_user, invocation, make_console, out_name, out_option, plain


def parse_figures(text: str | None) -> tuple[int, ...]:
    """--figures: comma-separated numbers and ranges (3,4,8-10) of the paper's figures."""
    from ..pages.figures import NUMBERS

    if text is None:
        return NUMBERS
    allowed = f"numbers and ranges from {NUMBERS[0]} to {NUMBERS[-1]}, e.g. 3,4,8-10"
    chosen = []
    for part in text.split(","):
        ends = part.strip().split("-")
        try:
            low, high = (int(ends[0]), int(ends[-1])) if len(ends) <= 2 else (None, None)
        except ValueError:
            low = high = None
        if low is not None and low > high:
            fail_user(f"--figures {shown(text)}: {shown(part.strip())} runs backwards; give {allowed}")
        if low is None or not (NUMBERS[0] <= low <= high <= NUMBERS[-1]):
            fail_user(
                f"--figures {shown(text)}: {shown(part.strip())} is not one of the paper's figures; "
                f"give {allowed}"
            )
        chosen += range(low, high + 1)
    return tuple(sorted(set(chosen)))


@click.command("gallery")
@out_option("groundres-out/gallery")
@FORMAT
@click.option(
    "--figures",
    "figures",
    metavar="LIST",
    default=None,
    help="Only these of the paper's figures, e.g. 3,4,8-10 [default: 3-13].",
)
def command(out, fmt, figures):
    """Reproduce the seed paper's Figures 3 to 13 and write them with one HTML page (index.html).

    Runs every shipped case that stands for one of the figures: Coleman
    diagrams in the paper's frame and the other one (Figures 3 to 10,
    eigen- and Floquet analysis), phasor diagrams below, inside and above the
    instability (Figures 11 to 13). index.html shows, per figure, the
    configuration, the paper's statement, what groundres computes and whether
    they agree, with the reason; it embeds every picture and opens offline.
    The pictures are also written as files in --format, and the numbers in
    gallery.json.
    """
    from pathlib import Path

    numbers = parse_figures(figures)
    console = make_console()
    out_dir = Path(out) if out is not None else Path("groundres-out") / "gallery"
    if out is not None and not out.strip():
        fail_user(f"--out {shown(out)}: empty; give a folder, e.g. --out gallery")
    check_out(out_dir, out)
    from ..pages.gallery import build, gallery_page
    from ..results import files, folders

    label = f"Figures ({len(numbers)})"
    with Steps(console, {"figures": label, "page": "Writing the page"}) as steps:
        steps("figures", 0, len(numbers))
        data, pictures = build(numbers, fmt, progress=lambda done, total: steps("figures", done, total))
        meta = invocation()
        with steps.step("page"), folders.output_folder(out_dir, out_name(out)) as folder:
            for name, content in pictures.items():
                files.write_bytes(folder / name, content)
            files.write_json(folder / "gallery.json", data["json"])
            files.write_text(
                folder / "index.html", gallery_page(data, shlex.join(["groundres", *meta["argv"]]))
            )
            folders.write_provenance(folder, _GalleryCase(), command="gallery", figures=list(numbers), **meta)
    for s in data["sections"]:
        console.print(f"Figure {s['figure'].number:2d} ({plain(s['figure'].case)}): {s['verdict'].word}")
    console.print(f"Wrote {plain(out_dir)}/index.html, gallery.json and {len(pictures)} pictures")


class _GalleryCase:
    """What provenance.json records as the 'case' of a gallery: the shipped cases, no single text."""

    title = "the seed paper's Figures 3 to 13"
    source = "shipped cases"
    text = ""
