"""What made a structure's plan, for its ``plan.json`` and ``report.md``: the command, the seed, every
setting, the versions, the coverage of the whole and of each part."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from ._provenance import json_safe, versions, versions_line

if TYPE_CHECKING:  # _structure_plan writes with these: no import cycle at run time
    from ._structure_plan import StructurePlan


def structure_record(plan: StructurePlan, command: str | None, runtime_s: float | None) -> dict[str, Any]:
    """The keys a structure's ``plan.json`` adds to its plan's geometry (all strict JSON)."""
    result = plan.result
    return {
        "command": command,
        "runtime_s": runtime_s,
        "seed": result.seed,
        "settings": json_safe(result.settings.as_dict()),
        "results": {
            "coverage": result.best_coverage,
            "initial_coverage": result.initial_coverage,
            "coverage_by_part": dict(result.coverage_by_part or {}),
            "best_iteration": result.best_iteration,
            "targets": len(plan.targets),
            "seen_targets": int((plan.seen_count > 0).sum()),
        },
        "versions": versions(),
    }


def structure_report_md(plan: StructurePlan, document: dict[str, Any]) -> bytes:
    """One page: the command, the numbers, each part's coverage, the positions, the settings."""
    results, settings = document["results"], document["settings"]
    flight = plan.flight
    anchor = document["anchor"]
    lines = [
        "# uavcov plan round a structure",
        "",
        f"Command: `{document['command']}`" if document["command"] else "Made by `uavcov.field.write_structure_plan`.",
        "",
        "## Numbers",
        "",
        "| | |",
        "|---|---|",
        f"| coverage of the structure (weighted share of its targets seen) | {results['coverage']:.3f} |",
        f"| at the start | {results['initial_coverage']:.3f} |",
        f"| targets | {results['targets']} ({results['seen_targets']} seen) |",
        f"| best configuration at iteration | {results['best_iteration']} of {settings['iterations']} |",
    ]
    if document["runtime_s"] is not None:
        lines.append(f"| runtime (planning; files not included) | {document['runtime_s']:.1f} s |")
    lines += ["", "| part | share seen |", "|---|---|"]
    lines += [f"| {part} | {share:.3f} |" for part, share in results["coverage_by_part"].items()]
    lines += ["", "| UAV | longitude | latitude | height above ellipsoid (m) | east, north, up (m) |", "|---|---|---|---|---|"]
    for k in range(flight.n_uavs):
        lon, lat, h = flight.positions_wgs84[k]
        east, north, up = flight.positions_local[k]
        lines.append(f"| {k + 1} | {lon:.7f} | {lat:.7f} | {h:.1f} | {east:.1f}, {north:.1f}, {up:.1f} |")
    lines += [
        "",
        "## Frames and settings",
        "",
        f"- anchor (local origin): {anchor['longitude']}, {anchor['latitude']}, {anchor['height_ellipsoid_m']} m above the WGS84 ellipsoid",
        f"- {document['local_frame']}; heights {document['heights']}",
        (
            f"- team: {settings['n_uavs']} UAVs, range d_max = {settings['d_max']:g} m, {settings['iterations']} iterations, "
            f"seed {document['seed']}"
        ),
        f"- versions: {versions_line(document['versions'])}; every setting in `plan.json` (`settings`)",
        "",
    ]
    return "\n".join(lines).encode("utf-8")
