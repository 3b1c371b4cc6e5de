#!/usr/bin/env python
"""Regenerate docs/reproduction.md and docs/figures/reproduction/ from a ``uavcov reproduce all`` folder.

    uavcov reproduce all --out out/all --workers 2 --threads 1
    python scripts/docs_from_report.py out/all

The page is the folder's ``report.md`` under a short preamble (what it is, the commands); each
experiment's summary figures (Table 1 bars, coverage curves) are copied under
``docs/figures/reproduction/<experiment>/`` (stored with a 256-colour palette to stay small) and
their links rewritten; the pictures of single runs stay in the folder. Figures of an earlier report are
removed first, so the docs hold exactly what this report shows.
"""

from __future__ import annotations

import argparse
import re
import shutil
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PAGE = ROOT / "docs" / "reproduction.md"
FIGURES = ROOT / "docs" / "figures" / "reproduction"
LINK = re.compile(r"\]\((?P<name>[A-Za-z0-9_.-]+)/figures/(?P<file>[A-Za-z0-9_.-]+\.png)\)")
IMAGE_LINE = re.compile(r"^!\[[^\]]*\]\((?P<name>[A-Za-z0-9_.-]+)/figures/(?P<file>[A-Za-z0-9_.-]+\.png)\)$")
# What the page shows: each experiment's bars and curves; the pictures of single runs (a run id
# followed by what is drawn) stay in the folder, and docs/figures.md shows such pictures.
SUMMARY_FIGURE = re.compile(r"^[A-Za-z0-9]+_(max_coverage|initial_coverage|coverage_distance|coverage_N\d+_d[0-9.]+)\.png$")

PREAMBLE = """\
# The paper's experiments, reproduced

Renzaglia et al., "Multi-UAV Visual Coverage of Partially Known 3D Surfaces: Voronoi-based
Initialization to Improve Local Optimizers" (arXiv:1901.10272), section V. No code of the
authors is public: this is our implementation, and the reproduction is statistical, on terrains
drawn the way the paper describes. Every parameter the paper leaves open was chosen on the
development seeds 1000-1039 ([calibration.md](calibration.md)); the scenarios below (0-39) were
run once with those settings. The model is the paper's: minimum and maximum height of flight,
robot-robot and robot-ground avoidance on every move, no simulated measurement noise, one
altitude rule for every start; what a mechanism the paper lacks would change is in the
ablation table at the end. Beyond the paper, Table 1 has a fourth start, greedy on S' (what the
paper dismissed as too costly), and every start is set against a certified bound on the best
placement of each terrain ("Table 1 against the certified bound"); the paper's claims are
checked on its own three starts.

This page is generated, numbers and figures alike:

```
uavcov reproduce all --out out/all --workers 2 --threads 1
python scripts/docs_from_report.py out/all
python scripts/optimum_docs.py ROWS --runs out/all/table1/runs.csv  # the lattice optimum (benches/README.md)
```

"""


def _small(source: Path, target: Path) -> None:
    try:
        from PIL import Image
    except ImportError:  # without Pillow (it comes with matplotlib) the PNG is copied as is
        shutil.copyfile(source, target)
        return
    with Image.open(source) as image:
        image.convert("RGB").quantize(colors=256, method=Image.Quantize.MEDIANCUT).save(target, optimize=True)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("folder", type=Path, help="the --out folder of `uavcov reproduce all`")
    args = parser.parse_args(argv)
    report = args.folder / "report.md"
    if not report.is_file():
        print(f"error: {report} does not exist (run `uavcov reproduce all --out {args.folder}` first)", file=sys.stderr)
        return 2
    text = report.read_text(encoding="utf-8")
    lines = text.splitlines()
    if lines and lines[0].startswith("# "):
        text = "\n".join(lines[1:]).lstrip("\n")  # the preamble carries the title
    if FIGURES.exists():
        shutil.rmtree(FIGURES)
    copied = 0

    def relink(match: re.Match[str]) -> str:
        nonlocal copied
        source = args.folder / match["name"] / "figures" / match["file"]
        target = FIGURES / match["name"] / match["file"]
        target.parent.mkdir(parents=True, exist_ok=True)
        _small(source, target)
        copied += 1
        return f"](figures/reproduction/{match['name']}/{match['file']})"

    kept = []
    for line in text.splitlines():
        image = IMAGE_LINE.match(line)
        if image and not SUMMARY_FIGURE.match(image["file"]):
            continue
        kept.append(line)
    text = LINK.sub(relink, "\n".join(kept))
    PAGE.write_text(PREAMBLE + text.rstrip() + "\n", encoding="utf-8")
    print(f"wrote {PAGE.relative_to(ROOT)} and {copied} figure(s) under {FIGURES.relative_to(ROOT)}/")
    return 0


if __name__ == "__main__":
    sys.exit(main())
