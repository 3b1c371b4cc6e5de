"""A plan's CSV tables: one row per UAV (``positions.csv``), one per ``.plan`` item (``waypoints.csv``)."""

from __future__ import annotations

import csv
import io
import math
import os
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..errors import InvalidInputError
from ._plan import FlightPlan
from ._qgc import MAV_CMD_NAV_LOITER_TIME, _items

_POSITION_COLUMNS = (
    "uav",
    "x_local_m",
    "y_local_m",
    "z_local_m",
    "x_crs",
    "y_crs",
    "longitude",
    "latitude",
    "altitude_amsl_m",
    "altitude_agl_m",
    "altitude_home_m",
    "ground_amsl_m",
    "transit_amsl_m",
    "heading_deg",
    "pitch_deg",
)
"""``heading_deg`` (clockwise from true north) and ``pitch_deg`` are the camera's: a plan without a
camera writes neither column, and a mixed team leaves them empty for its omnidirectional UAVs."""
_CAMERA_COLUMNS = ("heading_deg", "pitch_deg")


def _csv(rows: Sequence[Sequence[Any]], header: Sequence[str]) -> bytes:
    """CSV text whose every number is finite: NaN means "not applicable", written as an empty cell,
    and a column of nothing but NaN is left out; an infinity is an error.

    Raises
    ------
    InvalidInputError
        A value is infinite.
    """
    if any(isinstance(v, float) and math.isinf(v) for row in rows for v in row):
        raise InvalidInputError(f"a table with columns {tuple(header)} would hold an infinite number; nothing was written")
    keep = [c for c in range(len(header)) if not rows or not all(isinstance(row[c], float) and math.isnan(row[c]) for row in rows)]
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow([header[c] for c in keep])
    writer.writerows([[_cell(row[c]) for c in keep] for row in rows])
    return buffer.getvalue().encode("utf-8")


def _cell(value: Any) -> Any:
    if isinstance(value, float):
        return "" if math.isnan(value) else repr(value)
    return value


def _positions_csv(fp: FlightPlan) -> bytes:
    rows = [
        [
            k + 1,
            *(float(v) for v in fp.positions_local[k]),
            *(float(v) for v in fp.positions_crs[k, :2]),
            *(float(v) for v in fp.positions_wgs84[k]),
            float(fp.altitude_amsl[k]),
            float(fp.altitude_agl[k]),
            float(fp.altitude_home[k]),
            float(fp.ground_amsl[k]),
            float(fp.transit_amsl[k]),
            *((math.nan, math.nan) if fp.attitudes is None else (float(v) for v in fp.attitudes[k])),
        ]
        for k in range(fp.n_uavs)
    ]
    return _csv(rows, _POSITION_COLUMNS)


def _waypoints_csv(fp: FlightPlan) -> bytes:
    home = float(fp.takeoff_wgs84[2])
    rows = []
    for k in range(fp.n_uavs):
        for seq, (command, name, lat, lon, alt) in enumerate(_items(fp, k), start=1):
            hold = fp.settings.hold_s if command == MAV_CMD_NAV_LOITER_TIME else 0.0
            rows.append([k + 1, seq, command, name, lon, lat, alt, alt + home, hold])
    header = ("uav", "seq", "command", "name", "longitude", "latitude", "altitude_home_m", "altitude_amsl_m", "hold_s")
    return _csv(rows, header)


def read_positions_csv(path: Any) -> dict[str, np.ndarray]:
    """``positions.csv`` -> one float array per column (``uav`` as int; NaN for an empty cell or
    the camera's columns of a plan without a camera)."""
    try:
        with open(os.fspath(path), encoding="utf-8", newline="") as handle:
            rows = list(csv.DictReader(handle))
    except OSError as exc:
        raise InvalidInputError(f"cannot read {path}: {exc}") from None
    if not rows or set(_POSITION_COLUMNS) - set(_CAMERA_COLUMNS) - set(rows[0]):
        raise InvalidInputError(f"{path}: not a positions.csv (columns {_POSITION_COLUMNS})")
    try:
        out = {name: np.array([float(r.get(name) or "nan") for r in rows]) for name in _POSITION_COLUMNS}
    except (TypeError, ValueError) as exc:
        raise InvalidInputError(f"{path}: a cell is not a number: {exc}") from None
    out["uav"] = out["uav"].astype(np.int64)
    return out
