"""The structures experiment's report: its table (Markdown) and figure, from its rows."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np


def paired_interval(a: Any, b: Any) -> tuple[float, float, float]:
    """Mean of ``a - b`` over the pairs with its two-sided 95 % t interval ``(mean, low, high)``."""
    from scipy import stats

    d = np.asarray(a, dtype=float) - np.asarray(b, dtype=float)
    mean = float(d.mean()) if d.size else math.nan
    if d.size < 2:
        return mean, math.nan, math.nan
    half = float(stats.t.ppf(0.975, d.size - 1) * d.std(ddof=1) / math.sqrt(d.size))
    return mean, mean - half, mean + half


def _by_seed(rows: list[dict[str, Any]], family: str, start: str) -> dict[int, dict[str, Any]]:
    return {r["seed"]: r for r in rows if r["family"] == family and r["start"] == start and not r["error"]}


def _triples(rows: list[dict[str, Any]], families: list[str]) -> list[tuple[dict[str, Any], dict[str, Any], dict[str, Any]]]:
    """(cvt3d, cvt_hf, greedy) rows of each seed of ``families`` where all three finished."""
    out = []
    for family in families:
        three, flat, greedy = (_by_seed(rows, family, s) for s in ("cvt3d", "cvt_hf", "greedy"))
        out += [(three[s], flat[s], greedy[s]) for s in sorted(set(three) & set(flat) & set(greedy))]
    return out


def family_summary(rows: list[dict[str, Any]], family: str | list[str]) -> dict[str, Any]:
    """The numbers of one family's line (or of several families' pairs pooled): paired over the
    seeds where all three runs finished."""
    families = [family] if isinstance(family, str) else list(family)
    triples = _triples(rows, families)
    seeds = triples
    three = [t for t, _, _ in triples]
    best3 = np.array([t["best"] for t, _, _ in triples])
    best_hf = np.array([f["best"] for _, f, _ in triples])
    reference = np.array([g["coverage"] for _, _, g in triples])
    bound = np.array([g["bound"] for _, _, g in triples])
    mean, low, high = paired_interval(best3, best_hf)
    return {
        "seeds": len(seeds),
        "cvt3d": float(best3.mean()) if seeds else math.nan,
        "cvt_hf": float(best_hf.mean()) if seeds else math.nan,
        "gain": mean,
        "low": low,
        "high": high,
        "of_greedy_3d": float(np.mean(best3 / reference)) if seeds else math.nan,
        "of_bound_3d": float(np.mean(best3 / bound)) if seeds else math.nan,
        "of_greedy_hf": float(np.mean(best_hf / reference)) if seeds else math.nan,
        "greedy": float(reference.mean()) if seeds else math.nan,
        "bound": float(bound.mean()) if seeds else math.nan,
        "inside_3d": sum(r["inside_before"] for r in _all(rows, families, "cvt3d")),
        "inside_hf": sum(r["inside_before"] for r in _all(rows, families, "cvt_hf")),
        "inward_mean": float(np.mean([r["inward_share"] for r in three])) if three else math.nan,
        "inward_max": float(np.max([r["inward_share"] for r in three])) if three else math.nan,
        "errors": sum(1 for r in rows if r["family"] in families and r["error"]),
    }


def _all(rows: list[dict[str, Any]], families: list[str], start: str) -> list[dict[str, Any]]:
    return [r for r in rows if r["family"] in families and r["start"] == start and not r["error"]]


def shortfall(rows: list[dict[str, Any]], family: str) -> dict[str, Any]:
    """Why the 3D start falls short of the full-knowledge greedy on one family (measured).

    The initial coverage of both starts and its paired interval, what CAO added to each, and
    the part whose coverage falls most short of greedy's, weighted by its share of the
    structure's targets (the part's contribution to the gap), with the 3D start's and greedy's
    coverage of it.
    """
    triples = _triples(rows, [family])
    initial3 = np.array([t["initial"] for t, _, _ in triples])
    initial_hf = np.array([f["initial"] for _, f, _ in triples])
    mean, low, high = paired_interval(initial3, initial_hf)
    gaps: dict[str, list[float]] = {}
    cover3: dict[str, list[float]] = {}
    cover_g: dict[str, list[float]] = {}
    for t, _, g in triples:
        weights = g.get("part_weights", {})
        for part, weight in weights.items():
            if part in t.get("parts", {}) and part in g.get("parts", {}):
                gaps.setdefault(part, []).append(weight * (g["parts"][part] - t["parts"][part]))
                cover3.setdefault(part, []).append(t["parts"][part])
                cover_g.setdefault(part, []).append(g["parts"][part])
    worst = max(gaps, key=lambda p: float(np.mean(gaps[p]))) if gaps else ""
    return {
        "initial_3d": float(initial3.mean()) if triples else math.nan,
        "initial_hf": float(initial_hf.mean()) if triples else math.nan,
        "initial_gain": mean,
        "initial_low": low,
        "initial_high": high,
        "cao_3d": float(np.mean([t["best"] - t["initial"] for t, _, _ in triples])) if triples else math.nan,
        "cao_hf": float(np.mean([f["best"] - f["initial"] for _, f, _ in triples])) if triples else math.nan,
        "gap": float(np.mean([g["coverage"] - t["best"] for t, _, g in triples])) if triples else math.nan,
        "worst_part": worst,
        "worst_gap": float(np.mean(gaps[worst])) if worst else math.nan,
        "worst_3d": float(np.mean(cover3[worst])) if worst else math.nan,
        "worst_greedy": float(np.mean(cover_g[worst])) if worst else math.nan,
    }


def write_report(path: Path, experiment: Any, chosen: dict[str, float], rows: list[dict[str, Any]], dev_rows: list[dict[str, Any]]) -> None:
    """``structures.md`` (and ``figures/structures.png`` with matplotlib) beside ``rows.jsonl``."""
    path.write_text(report_markdown(experiment, chosen, rows, dev_rows), encoding="utf-8")
    _figure(path.parent / "figures" / "structures.png", experiment, rows)


def report_markdown(experiment: Any, chosen: dict[str, float], rows: list[dict[str, Any]], dev_rows: list[dict[str, Any]]) -> str:
    """The report's Markdown: one line per family, paired over the report seeds."""
    lines = [
        "### Structures no one tuned on: the 3D prior's start against the height-field prior's",
        "",
        (
            f"Families {', '.join(experiment.families)}; report seeds {list(experiment.report_seeds)}, development seeds "
            f"{list(experiment.dev_seeds)} (offsets chosen there: {chosen}). {experiment.n_uavs} UAVs, d_max {experiment.d_max:g} m, "
            f"{experiment.n_prior} known points, standoff {experiment.h_min:g} m, separation {experiment.d_safe:g} m, every move "
            f"checked, {experiment.iterations} iterations. Full knowledge: greedy on viewpoints {list(experiment.reference_distances)} "
            "m out along the true normals, with its certified bound."
        ),
        "",
        (
            "| family | seeds | 3D prior, mean best | height-field prior, mean best | 3D - HF [95 % CI] | 3D / greedy | 3D / bound "
            "| HF / greedy | greedy | bound | starts inside the structure (3D / HF) | S' facing inward (mean / max) | failed runs |"
        ),
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for family in [*experiment.families, list(experiment.families)]:
        s = family_summary(rows, family)
        lines.append(
            f"| {'all' if isinstance(family, list) else family} | {s['seeds']} | {s['cvt3d']:.3f} | {s['cvt_hf']:.3f} "
            f"| {s['gain']:+.3f} [{s['low']:+.3f}, {s['high']:+.3f}] "
            f"| {s['of_greedy_3d']:.3f} | {s['of_bound_3d']:.3f} | {s['of_greedy_hf']:.3f} | {s['greedy']:.3f} | {s['bound']:.3f} "
            f"| {s['inside_3d']} / {s['inside_hf']} | {100 * s['inward_mean']:.2f} % / {100 * s['inward_max']:.2f} % | {s['errors']} |"
        )
    lines += [
        "",
        (
            "Where the 3D start stays short of greedy (means over the report seeds): each start's initial coverage and the paired "
            "interval of 3D - HF on it, what CAO added to each, the gap to greedy, and the part contributing most to it (its share "
            "of the targets times greedy's coverage of it minus the 3D start's best; the two coverages beside it)."
        ),
        "",
        (
            "| family | initial 3D | initial HF | initial 3D - HF [95 % CI] | CAO added 3D | CAO added HF | greedy - 3D "
            "| part most missed: gap (3D / greedy) |"
        ),
        "|---|---|---|---|---|---|---|---|",
    ]
    for family in experiment.families:
        w = shortfall(rows, family)
        lines.append(
            f"| {family} | {w['initial_3d']:.3f} | {w['initial_hf']:.3f} | {w['initial_gain']:+.3f} [{w['initial_low']:+.3f}, "
            f"{w['initial_high']:+.3f}] | {w['cao_3d']:+.3f} | {w['cao_hf']:+.3f} | {w['gap']:+.3f} | {w['worst_part'] or '-'}: "
            f"{w['worst_gap']:+.3f} ({w['worst_3d']:.3f} / {w['worst_greedy']:.3f}) |"
        )
    errors = [r for r in rows + dev_rows if r["error"]]
    if errors:
        lines += ["", "Failed runs:", ""] + [f"- {r['family']} {r['start']} seed {r['seed']}: {r['error']}" for r in errors]
    lines.append("")
    return "\n".join(lines)


def _figure(path: Path, experiment: Any, rows: list[dict[str, Any]]) -> None:
    try:
        import matplotlib as mpl

        mpl.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    path.parent.mkdir(parents=True, exist_ok=True)
    families = list(experiment.families)
    summaries = [family_summary(rows, f) for f in families]
    x = np.arange(len(families))
    fig, ax = plt.subplots(figsize=(8, 4))
    for shift, key, label in (
        (-0.3, "cvt3d", "3D prior start"),
        (-0.1, "cvt_hf", "height-field prior start"),
        (0.1, "greedy", "full-knowledge greedy"),
        (0.3, "bound", "certified bound"),
    ):
        ax.bar(x + shift, [s[key] for s in summaries], width=0.2, label=label)
    ax.set_xticks(x, families)
    ax.set_ylabel("mean best coverage")
    ax.set_ylim(0.0, 1.0)
    ax.legend(loc="lower right", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
