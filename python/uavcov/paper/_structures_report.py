"""The structures experiment's report: its table (Markdown) and figure, from its rows."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from ._structures_rows import setting_of


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


THREE_D = ("cvt3d", "cvt3d_paper", "greedy3d", "cvt_true", "greedy_true")
"""The 3D starts (the 3D prior's two, and both on the true surface), each paired with the
height-field prior's (``cvt_hf``)."""
NAMES = {
    "cvt3d": "CVT on S'",
    "cvt3d_paper": "CVT on S' without normal weight",
    "greedy3d": "greedy on S'",
    "cvt_true": "CVT on the true surface",
    "greedy_true": "greedy on the true surface",
    "cvt_hf": "height-field CVT",
}


def _triples(rows: list[dict[str, Any]], families: list[str], start: str) -> list[tuple[dict[str, Any], dict[str, Any], dict[str, Any]]]:
    """(``start``, cvt_hf, greedy) rows of each seed of ``families`` where all three finished."""
    out = []
    for family in families:
        three, flat, greedy = (_by_seed(rows, family, s) for s in (start, "cvt_hf", "greedy"))
        out += [(three[s], flat[s], greedy[s]) for s in sorted(set(three) & set(flat) & set(greedy))]
    return out


def family_summary(rows: list[dict[str, Any]], family: str | list[str], start: str = "cvt3d") -> dict[str, Any]:
    """The numbers of one 3D start's line on one family (or on several families' pairs pooled):
    paired with the height-field prior's start over the seeds where both and the reference finished."""
    families = [family] if isinstance(family, str) else list(family)
    triples = _triples(rows, families, start)
    seeds = triples
    three = [t for t, _, _ in triples]
    best3 = np.array([t["best"] for t, _, _ in triples])
    best_hf = np.array([f["best"] for _, f, _ in triples])
    reference = np.array([g["coverage"] for _, _, g in triples])
    bound = np.array([g["bound"] for _, _, g in triples])
    mean, low, high = paired_interval(best3, best_hf)
    return {
        "seeds": len(seeds),
        "initial_3d": float(np.mean([t["initial"] for t in three])) if seeds else math.nan,
        "initial_hf": float(np.mean([f["initial"] for _, f, _ in triples])) if seeds else math.nan,
        "best_3d": float(best3.mean()) if seeds else math.nan,
        "best_hf": float(best_hf.mean()) if seeds else math.nan,
        "gain": mean,
        "low": low,
        "high": high,
        "of_greedy_3d": float(np.mean(best3 / reference)) if seeds else math.nan,
        "of_greedy_3d_min": float(np.min(best3 / reference)) if seeds else math.nan,
        "of_bound_3d": float(np.mean(best3 / bound)) if seeds else math.nan,
        "of_greedy_hf": float(np.mean(best_hf / reference)) if seeds else math.nan,
        "greedy": float(reference.mean()) if seeds else math.nan,
        "bound": float(bound.mean()) if seeds else math.nan,
        "inside_3d": sum(r["inside_before"] for r in _all(rows, families, start)),
        "inside_hf": sum(r["inside_before"] for r in _all(rows, families, "cvt_hf")),
        "inward_mean": float(np.mean([r.get("inward_share", math.nan) for r in three])) if three else math.nan,
        "inward_max": float(np.max([r.get("inward_share", math.nan) for r in three])) if three else math.nan,
        "errors": sum(1 for r in rows if r["family"] in families and r["start"] in (start, "cvt_hf", "greedy") and r["error"]),
    }


def start_against_start(
    rows: list[dict[str, Any]], family: str | list[str], key: str, first: str = "greedy3d", second: str = "cvt3d"
) -> tuple[float, float, float]:
    """``first`` minus ``second`` (greedy on S' minus CVT on S' by default) in ``key``
    (``"initial"`` or ``"best"``), paired over the seeds."""
    families = [family] if isinstance(family, str) else list(family)
    pairs = [
        (g[s][key], c[s][key])
        for f in families
        for g, c in [(_by_seed(rows, f, first), _by_seed(rows, f, second))]
        for s in sorted(set(g) & set(c))
    ]
    return paired_interval([a for a, _ in pairs], [b for _, b in pairs])


def _all(rows: list[dict[str, Any]], families: list[str], start: str) -> list[dict[str, Any]]:
    return [r for r in rows if r["family"] in families and r["start"] == start and not r["error"]]


def shortfall(rows: list[dict[str, Any]], family: str, start: str = "cvt3d") -> dict[str, Any]:
    """Why a 3D start falls short of the full-knowledge greedy on one family (measured).

    The initial coverage of both starts and its paired interval, what CAO added to each, and
    the part whose coverage falls most short of greedy's, weighted by its share of the
    structure's targets (the part's contribution to the gap), with the 3D start's and greedy's
    coverage of it.
    """
    triples = _triples(rows, [family], start)
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


def write_report(path: Path, experiment: Any, chosen: dict[str, Any], rows: list[dict[str, Any]], dev_rows: list[dict[str, Any]]) -> None:
    """``structures.md`` (and ``figures/structures.png`` with matplotlib) beside ``rows.jsonl``."""
    path.write_text(report_markdown(experiment, chosen, rows, dev_rows), encoding="utf-8")
    _figure(path.parent / "figures" / "structures.png", experiment, rows)
    _flight_figure(path.parent / "figures" / "structures_flight.png", experiment, rows)


def _percent(share: float) -> str:
    return "-" if math.isnan(share) else f"{100 * share:.2f} %"


def _chosen_words(chosen: dict[str, Any]) -> str:
    words = []
    for start, (offset, spacing, weight, step) in chosen.items():
        words.append(
            f"{NAMES.get(start, start)} {offset:g} m"
            + (f", points of S' {spacing:g} m apart" if spacing else "")
            + (f", normal weight {weight:g} m" if weight else "")
            + f", CAO step {step:g} m"
        )
    return "; ".join(words)


def report_markdown(experiment: Any, chosen: dict[str, Any], rows: list[dict[str, Any]], dev_rows: list[dict[str, Any]]) -> str:
    """The report's Markdown: one line per family and 3D start, paired over the report seeds."""
    lines = [
        "### Structures no one tuned on: the 3D prior's starts against the height-field prior's",
        "",
        (
            f"Families {', '.join(experiment.families)}; report seeds {list(experiment.report_seeds)}, development seeds "
            f"{list(experiment.dev_seeds)} (settings chosen there: {_chosen_words(chosen)}). {experiment.n_uavs} UAVs, "
            f"d_max {experiment.d_max:g} m, {experiment.n_prior} known points, standoff {experiment.h_min:g} m, separation "
            f"{experiment.d_safe:g} m, every move checked, {experiment.iterations} iterations. Full knowledge: greedy on viewpoints "
            f"{list(experiment.reference_distances)} m out along the true normals, with its certified bound. Two starts on the 3D "
            "prior's S': the CVT's generators, and greedy's picks by the coverage each adds on S' (the reference's greedy on what "
            "the start knows); and, to tell the prior from each start's objective, both on the true structure's surface (a perfect "
            "prior) with the settings chosen for them on S'. Each against the height-field prior's CVT start (HF) on the same seeds."
        ),
        "",
        (
            "| family | 3D start | seeds | initial 3D / HF | best 3D / HF | 3D - HF best [95 % CI] | 3D / greedy (min) | 3D / bound "
            "| HF / greedy | greedy | bound | starts inside the structure (3D / HF) | S' facing inward (mean / max) | failed runs |"
        ),
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for family in [*experiment.families, list(experiment.families)]:
        for start in THREE_D:
            s = family_summary(rows, family, start)
            lines.append(
                f"| {'all' if isinstance(family, list) else family} | {NAMES[start]} | {s['seeds']} "
                f"| {s['initial_3d']:.3f} / {s['initial_hf']:.3f} | {s['best_3d']:.3f} / {s['best_hf']:.3f} "
                f"| {s['gain']:+.3f} [{s['low']:+.3f}, {s['high']:+.3f}] "
                f"| {s['of_greedy_3d']:.3f} ({s['of_greedy_3d_min']:.3f}) | {s['of_bound_3d']:.3f} | {s['of_greedy_hf']:.3f} "
                f"| {s['greedy']:.3f} | {s['bound']:.3f} | {s['inside_3d']} / {s['inside_hf']} "
                f"| {_percent(s['inward_mean'])} / {_percent(s['inward_max'])} | {s['errors']} |"
            )
    lines += [
        "",
        "Greedy on S' against the CVT on S', paired over the report seeds (the same S', the same known points):",
        "",
        "| family | initial: greedy - CVT [95 % CI] | best: greedy - CVT [95 % CI] |",
        "|---|---|---|",
    ]
    for family in [*experiment.families, list(experiment.families)]:
        first, best = (start_against_start(rows, family, key) for key in ("initial", "best"))
        lines.append(
            f"| {'all' if isinstance(family, list) else family} | {first[0]:+.3f} [{first[1]:+.3f}, {first[2]:+.3f}] "
            f"| {best[0]:+.3f} [{best[1]:+.3f}, {best[2]:+.3f}] |"
        )
    lines += [
        "",
        "The normal weight: the CVT on S' as chosen against the paper's CVT on S' (no normal weight, its own offset), paired:",
        "",
        "| family | initial: chosen - paper's [95 % CI] | best: chosen - paper's [95 % CI] |",
        "|---|---|---|",
    ]
    for family in [*experiment.families, list(experiment.families)]:
        first, best = (start_against_start(rows, family, key, "cvt3d", "cvt3d_paper") for key in ("initial", "best"))
        lines.append(
            f"| {'all' if isinstance(family, list) else family} | {first[0]:+.3f} [{first[1]:+.3f}, {first[2]:+.3f}] "
            f"| {best[0]:+.3f} [{best[1]:+.3f}, {best[2]:+.3f}] |"
        )
    lines += [
        "",
        (
            "Where each 3D start stays short of greedy (means over the report seeds): each start's initial coverage and the "
            "paired interval of 3D - HF on it, what CAO added to each, the gap to greedy, and the part contributing most to it "
            "(its share of the targets times greedy's coverage of it minus the 3D start's best; the two coverages beside it)."
        ),
        "",
        (
            "| family | 3D start | initial 3D | initial HF | initial 3D - HF [95 % CI] | CAO added 3D | CAO added HF | greedy - 3D "
            "| part most missed: gap (3D / greedy) |"
        ),
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for family in experiment.families:
        for start in THREE_D:
            w = shortfall(rows, family, start)
            lines.append(
                f"| {family} | {NAMES[start]} | {w['initial_3d']:.3f} | {w['initial_hf']:.3f} | {w['initial_gain']:+.3f} "
                f"[{w['initial_low']:+.3f}, {w['initial_high']:+.3f}] | {w['cao_3d']:+.3f} | {w['cao_hf']:+.3f} | {w['gap']:+.3f} "
                f"| {w['worst_part'] or '-'}: {w['worst_gap']:+.3f} ({w['worst_3d']:.3f} / {w['worst_greedy']:.3f}) |"
            )
    lines += _budget_lines(experiment, rows)
    lines += _dev_choice_lines(experiment, dev_rows)
    errors = [r for r in rows + dev_rows if r["error"]]
    if errors:
        lines += ["", "Failed runs:", ""] + [f"- {r['family']} {r['start']} seed {r['seed']}: {r['error']}" for r in errors]
    lines.append("")
    return "\n".join(lines)


def after_iterations(rows: list[dict[str, Any]], family: str | list[str], iterations: int, start: str = "cvt3d") -> dict[str, Any]:
    """The best coverage after ``iterations`` of CAO (a row's ``best_at``) of ``start`` and of the
    height-field prior's start, as shares of the full-knowledge greedy's, paired over the seeds
    where both reached it."""
    families = [family] if isinstance(family, str) else list(family)
    key = str(iterations)
    triples = [(t, f, g) for t, f, g in _triples(rows, families, start) if key in t.get("best_at", {}) and key in f.get("best_at", {})]
    three = np.array([t["best_at"][key] for t, _, _ in triples])
    flat = np.array([f["best_at"][key] for _, f, _ in triples])
    greedy = np.array([g["coverage"] for _, _, g in triples])
    mean, low, high = paired_interval(three, flat)
    return {
        "seeds": len(triples),
        "of_greedy_3d": float(np.mean(three / greedy)) if triples else math.nan,
        "of_greedy_hf": float(np.mean(flat / greedy)) if triples else math.nan,
        "reached_3d": int(np.sum(three >= 0.95 * greedy)),
        "reached_hf": int(np.sum(flat >= 0.95 * greedy)),
        "gain": mean,
        "low": low,
        "high": high,
    }


def _budget_lines(experiment: Any, rows: list[dict[str, Any]]) -> list[str]:
    """Both 3D-prior starts and the height-field prior's as shares of greedy, and 3D - HF, after
    more and more iterations (the report missions fly on to ``trace_iterations``)."""
    reached = sorted({int(k) for r in rows for k in r.get("best_at", {}) if int(k) > 0})
    if not reached:
        return []
    lines = [
        "",
        (
            f"More flight time: the report missions fly on to {experiment.trace_iterations} iterations (the tables above are "
            f"after {experiment.iterations}); the best after each number of iterations as a share of the full-knowledge "
            "greedy's coverage (mean), the runs at 0.95 of it or more, and each 3D-prior start minus the height-field "
            "prior's (HF), paired over the seeds."
        ),
        "",
        (
            "| family | iterations | CVT on S' / greedy | greedy on S' / greedy | HF / greedy "
            "| runs at >= 0.95 of greedy (CVT on S' / greedy on S' / HF) | CVT on S' - HF [95 % CI] | greedy on S' - HF [95 % CI] |"
        ),
        "|---|---|---|---|---|---|---|---|",
    ]
    for family in [*experiment.families, list(experiment.families)]:
        for k in reached:
            c, g = after_iterations(rows, family, k, "cvt3d"), after_iterations(rows, family, k, "greedy3d")
            if not c["seeds"]:
                continue
            lines.append(
                f"| {'all' if isinstance(family, list) else family} | {k} | {c['of_greedy_3d']:.3f} | {g['of_greedy_3d']:.3f} "
                f"| {c['of_greedy_hf']:.3f} | {c['reached_3d']} / {g['reached_3d']} / {c['reached_hf']} of {c['seeds']} "
                f"| {c['gain']:+.3f} [{c['low']:+.3f}, {c['high']:+.3f}] | {g['gain']:+.3f} [{g['low']:+.3f}, {g['high']:+.3f}] |"
            )
    return lines


def dev_scores(dev_rows: list[dict[str, Any]], families: list[str], start: str) -> dict[tuple[float, ...], float]:
    """Each setting's score on the development seeds: the mean over ``families`` of the mean
    best coverage (what ``choose_offsets`` picks by); a setting without a finished run on some
    family has none."""
    by_setting: dict[tuple[float, ...], dict[str, list[float]]] = {}
    for r in dev_rows:
        if r["start"] == start and not r["error"]:
            key = setting_of(r)
            by_setting.setdefault(key, {}).setdefault(r["family"], []).append(r["best"])
    return {key: float(np.mean([np.mean(per[f]) for f in families])) for key, per in by_setting.items() if all(f in per for f in families)}


def _dev_choice_lines(experiment: Any, dev_rows: list[dict[str, Any]]) -> list[str]:
    """Per start and per open setting, the best development score with that setting's value (the
    others at their best): how much each choice matters."""
    lines = [
        "",
        (
            f"The choice on the development seeds {list(experiment.dev_seeds)}: per start and per value of each open setting, the "
            "best mean best coverage (mean over the families) with that value, the other settings at their best."
        ),
        "",
        "| start | offset from S' (m) | normal weight (m) | CAO step (m) |",
        "|---|---|---|---|",
    ]
    for start in ("cvt3d", "cvt_hf", "greedy3d"):
        scores = dev_scores(dev_rows, list(experiment.families), start)
        if not scores:
            continue
        cells = []
        for index in (0, 2, 3):
            values = sorted({key[index] for key in scores})
            best = {v: max(score for key, score in scores.items() if key[index] == v) for v in values}
            cells.append(", ".join(f"{v:g}: {best[v]:.3f}" for v in values))
        lines.append(f"| {NAMES.get(start, start)} | {' | '.join(cells)} |")
    return lines


def _pyplot() -> Any:
    """matplotlib's pyplot on the Agg backend, or None without the ``plot`` extra (no figure then)."""
    try:
        import matplotlib as mpl

        mpl.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return None
    return plt


def _figure(path: Path, experiment: Any, rows: list[dict[str, Any]]) -> None:
    plt = _pyplot()
    if plt is None:
        return
    path.parent.mkdir(parents=True, exist_ok=True)
    families = list(experiment.families)
    cvt = [family_summary(rows, f, "cvt3d") for f in families]
    greedy = [family_summary(rows, f, "greedy3d") for f in families]
    x = np.arange(len(families))
    fig, ax = plt.subplots(figsize=(8, 4))
    for shift, values, label in (
        (-0.32, [s["best_3d"] for s in cvt], "CVT on S' (3D prior)"),
        (-0.16, [s["best_3d"] for s in greedy], "greedy on S' (3D prior)"),
        (0.0, [s["best_hf"] for s in cvt], "height-field prior's CVT"),
        (0.16, [s["greedy"] for s in cvt], "full-knowledge greedy"),
        (0.32, [s["bound"] for s in cvt], "certified bound"),
    ):
        ax.bar(x + shift, values, width=0.16, label=label)
    ax.set_xticks(x, families)
    ax.set_ylabel("mean best coverage")
    ax.set_ylim(0.0, 1.0)
    ax.legend(loc="lower right", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def _flight_figure(path: Path, experiment: Any, rows: list[dict[str, Any]]) -> None:
    """Per family, each start's mean best as a share of the full-knowledge greedy's against the
    iterations flown (the report missions' ``best_at``)."""
    reached = sorted({int(k) for r in rows for k in r.get("best_at", {}) if int(k) > 0})
    plt = _pyplot()
    if plt is None or not reached:
        return
    path.parent.mkdir(parents=True, exist_ok=True)
    panels = [*experiment.families, list(experiment.families)]
    fig, axes = plt.subplots(1, len(panels), figsize=(2.6 * len(panels), 3.2), sharey=True)
    for ax, family in zip(np.atleast_1d(axes), panels, strict=True):
        for start, style in (("cvt3d", "-o"), ("greedy3d", "-s"), ("cvt3d_paper", ":^")):
            shares = [after_iterations(rows, family, k, start) for k in reached]
            ax.plot(reached, [a["of_greedy_3d"] for a in shares], style, markersize=3, label=NAMES[start])
        flat = [after_iterations(rows, family, k, "cvt3d") for k in reached]
        ax.plot(reached, [a["of_greedy_hf"] for a in flat], "--x", markersize=3, label=NAMES["cvt_hf"])
        ax.axhline(0.95, color="grey", linewidth=0.8)
        ax.set_xscale("log")
        ax.set_title("all" if isinstance(family, list) else family, fontsize=9)
        ax.set_xlabel("CAO iterations")
    np.atleast_1d(axes)[0].set_ylabel("mean best / full-knowledge greedy")
    np.atleast_1d(axes)[0].legend(loc="lower right", fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
