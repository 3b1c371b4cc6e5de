"""What a row of the structures experiment says of its run's settings (``rows.jsonl``)."""

from __future__ import annotations

from typing import Any

DEFAULT_CAO_STEP = 1.5
"""``CAOSettings().alpha0``: the step of the rows written before the experiment chose it."""


def setting_of(row: dict[str, Any]) -> tuple[float, float, float, float]:
    """A row's (offset, spacing, normal weight, CAO step); rows written before a setting was
    chosen have its value of then (spacing and normal weight 0, CAO's default step)."""
    return (
        float(row["offset"]),
        float(row.get("spacing", 0.0)),
        float(row.get("normal_weight", 0.0)),
        float(row.get("cao_step", DEFAULT_CAO_STEP)),
    )
