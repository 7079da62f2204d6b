"""Write docs/images/gallery/: one picture per seed-paper figure, and the verdict table of docs/gallery.md.

Runs the gallery (`groundres gallery`, about 20 s) and keeps, per figure, the
picture in the paper's frame (Coleman figures) or inside the instability
(phasor figures), reduced to a palette PNG to keep the repository small. It
prints the "Figures" section of docs/gallery.md (the table of verdicts and
the pictures); paste it there. A test checks the table against a fresh
gallery.

Run: python3 docs/make_gallery_images.py
"""

from io import BytesIO
from pathlib import Path

from PIL import Image

from groundres.pages.gallery import build

OUT = Path(__file__).parent / "images" / "gallery"


def main():
    OUT.mkdir(parents=True, exist_ok=True)
    data, files = build()
    rows, blocks = [], []
    for s in data["sections"]:
        f, verdict = s["figure"], s["verdict"]
        picture = s["pictures"][1 if f.kind == "phasors" else 0]
        image = Image.open(BytesIO(files[picture["file"]])).convert("RGB")
        image.quantize(colors=128, method=Image.Quantize.MEDIANCUT).save(OUT / picture["file"], optimize=True)
        rows.append(f"| {f.number} | `{f.case}` | {verdict.computed} | {verdict.word} |")
        blocks += [
            f"### Figure {f.number}: {verdict.word}",
            "",
            f"*{f.caption}* The paper: {f.statement}",
            "",
            f"![Figure {f.number}: {picture['caption']}](images/gallery/{picture['file']})",
            "",
            f"groundres ({s['record']['method']}): {verdict.computed.rstrip('.')}. {verdict.reason}",
            "",
        ]
    print("## Figures\n")
    print(
        "What `groundres gallery` computes for each figure, with the verdict against the paper. "
        "The gallery page shows every picture (both frames, the Floquet diagrams, phasors below, "
        "inside and above); here is one per figure.\n"
    )
    print("| figure | case | groundres | verdict |")
    print("| --- | --- | --- | --- |")
    print("\n".join(rows) + "\n")
    print("\n".join(blocks).rstrip())


if __name__ == "__main__":
    main()
