"""A flown mission on disk: what ``uavcov view`` draws (the states flown, not only the waypoints).

:func:`save_flown` writes one ``.npz`` (the true surface, the waypoints, the reached
configurations and their coverage, every recorded state and when each measurement was taken);
:func:`load_flown` reads it back as a :class:`FlownRun`, which has the names the interactive view
reads from a mission result (``terrain``, ``trajectory``, ``coverage``, ``best_positions``, ...)
plus the flown states.
"""

from __future__ import annotations

import json
import os
import zipfile
import zlib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .._io import atomic_write_with, make_parent
from .._validate import as_path, open_regular_file, read_only
from ..engine import Terrain
from ..errors import InvalidTypeError, ResultsFormatError
from ..mission import MissionSettings
from ..records import check_shapes
from ._closed_loop import MEASUREMENTS, FlownMission

__all__ = ["FlownRun", "save_flown", "load_flown", "FLOWN_FORMAT"]

FLOWN_FORMAT = "uavcov-flown-1"
"""The ``format`` of a flown run's header."""

_ARRAYS = ("start", "commanded", "reached", "exact", "sensed", "clock", "states", "states_time", "leg_ends_s")


@dataclass(frozen=True)
class FlownRun:
    """A flown mission as saved: the surface it flew over and what it flew. Metres, seconds.

    Attributes
    ----------
    terrain : Terrain
    settings : MissionSettings
    seed : int or None
    measurement : str
        What CAO maximised (``"exact"`` or ``"sensed"``).
    failure : str or None
    start_positions : (N, 3) ndarray
    commanded, trajectory : (K + 1, N, 3) ndarray
        The waypoints CAO chose, and the configurations reached there (where it measured).
    coverage, sensed : (K + 1,) ndarray
        Exact and sensed coverage at each reached configuration.
    measured_at_s : (K + 1,) ndarray
        Mission time of each measurement (the clock of :attr:`flown_time`).
    flown_states : (M, N, 3) ndarray
        Every recorded position.
    flown_time : (M,) ndarray
        Mission time of each recorded state.
    """

    terrain: Terrain
    settings: MissionSettings
    seed: int | None
    measurement: str
    failure: str | None
    start_positions: np.ndarray
    commanded: np.ndarray
    trajectory: np.ndarray
    coverage: np.ndarray
    sensed: np.ndarray
    measured_at_s: np.ndarray
    flown_states: np.ndarray
    flown_time: np.ndarray

    @property
    def best_iteration(self) -> int:
        """The measurement of the highest exact coverage (the first on ties)."""
        return int(np.argmax(self.coverage))

    @property
    def best_coverage(self) -> float:
        return float(self.coverage[self.best_iteration])

    @property
    def best_positions(self) -> np.ndarray:
        """``(N, 3)`` the reached configuration of :attr:`best_iteration`."""
        return np.asarray(self.trajectory[self.best_iteration])

    @property
    def prior_points(self) -> np.ndarray:
        return np.empty((0, 3))


def save_flown(flown: FlownMission, path: str | os.PathLike[str], terrain: Terrain) -> Path:
    """Write ``flown`` and the surface it flew over (``terrain``) to ``path`` (``.npz``, atomically)."""
    if not isinstance(flown, FlownMission):
        raise InvalidTypeError(f"flown must be a FlownMission, got {type(flown).__name__}")
    if not isinstance(terrain, Terrain):
        raise InvalidTypeError(f"terrain must be a Terrain, got {type(terrain).__name__}")
    header = {
        "format": FLOWN_FORMAT,
        "spec": flown.settings.as_dict(),
        "seed": flown.seed,
        "measurement": flown.sim.measurement,
        "failure": flown.failure,
    }
    arrays = {
        "header": np.array(json.dumps(header)),
        "terrain_vertices": np.asarray(terrain.vertices),
        "terrain_faces": np.asarray(terrain.faces),
        **{name: np.asarray(getattr(flown, name)) for name in _ARRAYS},
    }
    out = make_parent(as_path(path, "path"))
    atomic_write_with(out, lambda handle: np.savez_compressed(handle, **arrays))  # type: ignore[arg-type]
    return out


def is_flown_file(path: str | os.PathLike[str]) -> bool:
    """Whether ``path`` is an ``.npz`` written by :func:`save_flown` (False for any other file).

    Raises
    ------
    InvalidTypeError
        ``path`` is not a path (a string or ``os.PathLike``).
    """
    file = as_path(path, "path")  # a number or None is a mistake, not "some other file"
    if not file.is_file():  # a FIFO would block np.load forever; a folder is no flown run either
        return False
    try:  # checked again on the opened file: one swapped for a FIFO since would block np.load
        with open_regular_file(file, "flown run", ResultsFormatError) as handle, np.load(handle, allow_pickle=False) as data:
            return "header" in data.files and json.loads(str(data["header"])).get("format") == FLOWN_FORMAT
    except Exception:  # noqa: BLE001 - any unreadable file is simply not a flown run
        return False


def _check_flown(arrays: dict[str, Any], header: dict[str, Any], n: int, file: Path) -> None:
    """A flown run's arrays agree in shape with each other and the team, and its header's records are what they say."""
    measured = arrays["reached"].shape[0] if arrays["reached"].ndim == 3 else None  # configurations measured
    flown = arrays["states"].shape[0] if arrays["states"].ndim == 3 else None  # states recorded
    shapes = {"start": (n, 3), "commanded": (measured, n, 3), "reached": (measured, n, 3), "exact": (measured,), "sensed": (measured,)}
    shapes |= {"clock": (measured,), "states": (flown, n, 3), "states_time": (flown,), "leg_ends_s": (None,)}
    check_shapes(arrays, shapes, file)
    nonfinite = next((name for name in shapes if name not in ("sensed", "states") and not np.isfinite(arrays[name]).all()), None)
    if nonfinite is not None:  # sensed is NaN where the cameras did not render
        raise ResultsFormatError(f"{file}: {nonfinite} holds NaN or infinite values")
    seed, measurement, failure = header.get("seed"), header.get("measurement"), header.get("failure")
    if seed is not None and (isinstance(seed, bool) or not isinstance(seed, int) or seed < 0):
        raise ResultsFormatError(f"{file}: seed = {seed!r} is not an integer >= 0")
    if measurement not in MEASUREMENTS:
        raise ResultsFormatError(f"{file}: measurement = {measurement!r} is not one of {MEASUREMENTS}")
    if failure is not None and not isinstance(failure, str):
        raise ResultsFormatError(f"{file}: failure = {failure!r} is not a message")


def load_flown(path: str | os.PathLike[str]) -> FlownRun:
    """Read a run written by :func:`save_flown`.

    Raises
    ------
    ResultsFormatError
        Not a readable flown run (missing, corrupt, another format, arrays of the wrong shapes).
    """
    file = as_path(path, "path")
    if not file.is_file():
        raise ResultsFormatError(f"no flown run at {file}")
    try:
        with open_regular_file(file, "flown run", ResultsFormatError) as handle, np.load(handle, allow_pickle=False) as data:
            arrays: dict[str, Any] = {name: data[name] for name in data.files}
        header = json.loads(str(arrays["header"]))
        if not isinstance(header, dict) or header.get("format") != FLOWN_FORMAT:
            raise ValueError(f"format {header.get('format') if isinstance(header, dict) else header!r}, not {FLOWN_FORMAT!r}")
        terrain = Terrain(arrays["terrain_vertices"], arrays["terrain_faces"])
        settings = MissionSettings.from_dict(header["spec"])
        _check_flown(arrays, header, settings.n_uavs, file)
        reached, states = np.asarray(arrays["reached"], dtype=np.float64), np.asarray(arrays["states"], dtype=np.float64)
        first_end = float(arrays["leg_ends_s"][0]) if arrays["leg_ends_s"].size else 0.0
    except ResultsFormatError:
        raise
    except (OSError, ValueError, KeyError, TypeError, EOFError, zipfile.BadZipFile, zlib.error, RecursionError) as exc:
        raise ResultsFormatError(f"{file} is not a readable flown run: {type(exc).__name__}: {exc}") from exc
    except MemoryError:  # a member whose header claims terabytes (a corrupt or hostile file), as load_mission says
        raise ResultsFormatError(f"{file} is not a flown run: an array of it claims more memory than there is") from None
    return FlownRun(
        terrain=terrain,
        settings=settings,
        seed=header.get("seed"),
        measurement=str(header.get("measurement")),
        failure=header.get("failure"),
        start_positions=read_only(np.asarray(arrays["start"], dtype=np.float64)),
        commanded=read_only(np.asarray(arrays["commanded"], dtype=np.float64)),
        trajectory=read_only(reached),
        coverage=read_only(np.asarray(arrays["exact"], dtype=np.float64)),
        sensed=read_only(np.asarray(arrays["sensed"], dtype=np.float64)),
        measured_at_s=read_only(np.asarray(arrays["clock"], dtype=np.float64) + first_end),
        flown_states=read_only(states),
        flown_time=read_only(np.asarray(arrays["states_time"], dtype=np.float64)),
    )
