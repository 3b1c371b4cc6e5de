"""Compare two folders written by ``scripts/runs_fingerprint.sh``: every number, to the last digit.

Timing columns (wall and CPU seconds), the versions and the command line (it names the output folder)
written into plans are skipped; a column
or key present on one side only is reported, not compared. Exit 1 on any difference.

Usage: ``python scripts/compare_fingerprints.py BEFORE AFTER``
"""

from __future__ import annotations

import csv
import json
import sys
from pathlib import Path

SKIP = ("time", "seconds", "elapsed", "version", "created", "wall", "cpu_s", "_s", "command")


def _timing(name: str) -> bool:
    return any(part in name.lower() for part in SKIP)


def _rows(path: Path) -> dict[str, dict[str, str]]:
    with path.open() as f:
        rows = list(csv.DictReader(f))
    key = "run_id" if rows and "run_id" in rows[0] else None
    return {(r[key] if key else str(i)): r for i, r in enumerate(rows)}


def _compare_csv(a: Path, b: Path, problems: list[str]) -> None:
    ra, rb = _rows(a), _rows(b)
    if set(ra) != set(rb):
        problems.append(f"{a.name}: rows differ ({len(ra)} against {len(rb)})")
        return
    cols_a, cols_b = set(next(iter(ra.values()), {})), set(next(iter(rb.values()), {}))
    for only in sorted(cols_a ^ cols_b):
        print(f"note: {a.parent.name}/{a.name} column {only!r} on one side only")
    columns = [c for c in sorted(cols_a & cols_b) if not _timing(c)]
    problems.extend(
        f"{a.parent.name}/{a.name} row {k} {col}: {ra[k][col]} != {rb[k][col]}" for k in ra for col in columns if ra[k][col] != rb[k][col]
    )


def _walk(x, y, where: str, problems: list[str]) -> None:
    if isinstance(x, dict) and isinstance(y, dict):
        for key in sorted(set(x) | set(y)):
            if _timing(str(key)):
                continue
            if key not in x or key not in y:
                print(f"note: {where}.{key} on one side only")
                continue
            _walk(x[key], y[key], f"{where}.{key}", problems)
    elif isinstance(x, list) and isinstance(y, list) and len(x) == len(y):
        for i, (u, v) in enumerate(zip(x, y, strict=True)):
            _walk(u, v, f"{where}[{i}]", problems)
    elif x != y:
        problems.append(f"{where}: {x!r} != {y!r}")


def main(before: str, after: str) -> int:
    a, b = Path(before), Path(after)
    problems: list[str] = []
    compared = 0
    for fa in sorted(a.rglob("*")):
        fb = b / fa.relative_to(a)
        if fa.suffix not in (".csv", ".json") or not fb.exists():
            continue
        compared += 1
        if fa.suffix == ".csv":
            _compare_csv(fa, fb, problems)
        else:
            _walk(json.loads(fa.read_text()), json.loads(fb.read_text()), str(fa.relative_to(a)), problems)
    print(f"{compared} files compared, {len(problems)} differences")
    for p in problems[:50]:
        print("  " + p)
    return 1 if problems or compared == 0 else 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:3]))
