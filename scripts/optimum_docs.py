#!/usr/bin/env python
"""Write the exact placement's sweep into docs/reproduction.md and benches/README.md.

    OPENBLAS_NUM_THREADS=1 nice python benches/exact_placement.py --sweep --seeds 0-39 --threads 1 --rows ROWS
    uavcov reproduce table1 --out TABLE1 --seeds 0-39 --workers 1 --threads 1 --no-plots --no-save-runs
    python scripts/optimum_docs.py ROWS --runs TABLE1/runs.csv

The sweep's rows (one JSON line per terrain and team size, :class:`uavcov.paper.OracleRow` with
the optimum's columns) give, in docs/reproduction.md, the section "Table 1 against the lattice
optimum" (each start's max coverage as a share of its terrain's optimum, from Table 1's
``runs.csv``: the runs are deterministic, so the ``reproduce`` command above rebuilds the page's
runs); in benches/README.md, the table between the ``exact-sweep`` markers (proved, gaps, wall
times, the overshoot past the limit). Both are replaced in place; rows still missing are counted.
"""

from __future__ import annotations

import argparse
import csv
import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PAGE = ROOT / "docs" / "reproduction.md"
BENCHES = ROOT / "benches" / "README.md"
HEADING = "## Table 1 against the lattice optimum"
BEFORE = "## The paper's claims on Table 1, measured"  # the section goes right before this one
BEGIN, END = "<!-- exact-sweep:begin -->", "<!-- exact-sweep:end -->"


def _replace_section(text: str, section: str) -> str:
    """``text`` with its optimum section replaced by ``section`` (inserted before BEFORE when absent)."""
    if HEADING in text:
        start = text.index(HEADING)
        end = text.find("\n## ", start + len(HEADING))
        return text[:start] + section + ("\n" + text[end + 1 :] if end >= 0 else "")
    if BEFORE not in text:
        raise SystemExit(f"error: {PAGE} has neither {HEADING!r} nor {BEFORE!r}")
    start = text.index(BEFORE)
    return text[:start] + section + "\n" + text[start:]


def main(argv: list[str] | None = None) -> int:
    from uavcov.experiments import finished_rows
    from uavcov.paper import OracleRow
    from uavcov.paper._bounds import optimum_markdown, optimum_sweep_markdown

    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("rows", type=Path, help="the sweep's JSON lines (benches/exact_placement.py --rows)")
    parser.add_argument("--runs", type=Path, help="Table 1's runs.csv on the same terrains")
    parser.add_argument("--time-limit", type=float, default=60.0, help="the sweep's limit, seconds (default 60)")
    parser.add_argument("--expected", type=int, default=160, help="instances of the whole sweep (default 40 x 4)")
    args = parser.parse_args(argv)
    if not args.rows.is_file():
        print(f"error: {args.rows} does not exist", file=sys.stderr)
        return 2
    rows = [OracleRow(**json.loads(line)) for line in args.rows.read_text().splitlines() if line.strip()]
    runs = []
    if args.runs is not None:
        with args.runs.open() as handle:
            runs = finished_rows(list(csv.DictReader(handle)))
    done = f"{len(rows)} of the sweep's {args.expected} instances (terrains {min(r.seed for r in rows)}-{max(r.seed for r in rows)})"
    command = (
        "```\nOPENBLAS_NUM_THREADS=1 nice python benches/exact_placement.py --sweep --seeds 0-39 --threads 1 --rows ROWS\n"
        "uavcov reproduce table1 --out TABLE1 --seeds 0-39 --workers 1 --threads 1 --no-plots --no-save-runs\n"
        "python scripts/optimum_docs.py ROWS --runs TABLE1/runs.csv\n```\n\n"
        "The rows shown are in `docs/exact_sweep/rows.jsonl` (`ROWS` above).\n"
    )
    section = optimum_markdown(runs, rows).rstrip("\n") + f"\n\n{done}, {args.time_limit:g} s each, made by\n\n{command}"
    PAGE.write_text(_replace_section(PAGE.read_text(encoding="utf-8"), section), encoding="utf-8")
    text = BENCHES.read_text(encoding="utf-8")
    if BEGIN not in text or END not in text:
        print(f"error: {BENCHES} has no {BEGIN} ... {END} block", file=sys.stderr)
        return 2
    table = f"{BEGIN}\n{done}, {args.time_limit:g} s each:\n\n{optimum_sweep_markdown(rows, args.time_limit)}{END}"
    BENCHES.write_text(text[: text.index(BEGIN)] + table + text[text.index(END) + len(END) :], encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
