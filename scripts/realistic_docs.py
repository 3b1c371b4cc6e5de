#!/usr/bin/env python
"""Regenerate docs/realistic.md's results from the rows of the flown experiments, finished or not.

    uavcov reproduce realistic --out out/realistic --resume
    uavcov reproduce realistic --standoff 1 --out out/standoff --resume
    uavcov reproduce flown-table1 --out out/table1 --resume
    python scripts/realistic_docs.py --realistic out/realistic --standoff out/standoff --table1 out/table1

Each folder's report is rebuilt from its ``rows.jsonl`` (:func:`uavcov.paper.write_realistic_report`),
then put into the page between its markers (``<!-- generated: realistic -->`` ...
``<!-- end: realistic -->``, the same for ``standoff`` and ``table1``), its title dropped and its figures copied
under ``docs/figures/realistic/`` (prefixed with the experiment's name) with their links rewritten.
"""

from __future__ import annotations

import argparse
import re
import shutil
from pathlib import Path

from uavcov.paper import write_realistic_report

ROOT = Path(__file__).resolve().parent.parent
PAGE = ROOT / "docs" / "realistic.md"
FIGURES = ROOT / "docs" / "figures" / "realistic"
IMAGE = re.compile(r"!\[(?P<alt>[^\]]*)\]\((?P<file>[A-Za-z0-9_.-]+\.png)\)")


def _section(name: str, folder: Path) -> str:
    report = write_realistic_report(folder).read_text(encoding="utf-8")
    body = report.split("\n", 1)[1].strip()  # without its "# title" line
    FIGURES.mkdir(parents=True, exist_ok=True)

    def copy(match: re.Match[str]) -> str:
        target = f"{name}_{match['file']}"
        shutil.copyfile(folder / match["file"], FIGURES / target)
        return f"![{match['alt']}](figures/realistic/{target})"

    return f"(`{folder}`, rebuilt by `scripts/realistic_docs.py`)\n\n" + IMAGE.sub(copy, body)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--realistic", type=Path, help="the realistic scenario's results folder")
    parser.add_argument("--standoff", type=Path, help="the realistic scenario flown under a 3D standoff: its results folder")
    parser.add_argument("--table1", type=Path, help="Table 1 flown's results folder")
    args = parser.parse_args()
    page = PAGE.read_text(encoding="utf-8")
    for name, folder in (("realistic", args.realistic), ("standoff", args.standoff), ("table1", args.table1)):
        if folder is None:
            continue
        begin, end = f"<!-- generated: {name} -->", f"<!-- end: {name} -->"
        if begin not in page or end not in page:
            raise SystemExit(f"{PAGE} has no markers {begin} ... {end}")
        head, rest = page.split(begin, 1)
        _, tail = rest.split(end, 1)
        page = f"{head}{begin}\n{_section(name, folder)}\n{end}{tail}"
    PAGE.write_text(page, encoding="utf-8")
    print(f"wrote {PAGE}")


if __name__ == "__main__":
    main()
