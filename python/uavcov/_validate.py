"""Argument checks shared by every public function.

Each check returns the value converted to what the library computes with (a C-contiguous
float64 array, a Python float, ...) or raises an error from :mod:`uavcov.errors` that names the
argument. Converting here, once, is what lets the Rust core assume clean input.

Size limits
-----------
Every count a user chooses and that sizes an allocation is checked against one of the limits
below *before* anything is allocated, with an :class:`~uavcov.errors.InvalidInputError` (a
:class:`~uavcov.errors.ConfigError` for sweeps) naming the limit. They are generous (far beyond
the paper's experiments) and keep one run, or a sweep's bookkeeping, well inside a 24 GB
machine; this is the one place they are defined:

=============================  ==============  ===================================================
limit                          value           what it bounds
=============================  ==============  ===================================================
:data:`MAX_UAVS`               1 000           team size: ``MissionSettings.n_uavs``, a sweep's
                                               ``team_sizes``
:data:`MAX_GENERATORS`         10 000          generators of one :func:`~uavcov.placement.cvt`
:data:`MAX_SAMPLES`            10 000 000      CVT samples per iteration; prior points ``n_prior``;
                                               positions of :func:`~uavcov.placement.initial_positions`
:data:`MAX_ITERATIONS`         1 000 000       optimiser iterations of one mission
:data:`MAX_TRAJECTORY`         50 000 000      UAV positions a mission records,
                                               ``(iterations + 1) * n_uavs`` (1.2 GB)
:data:`MAX_PAIR_CHECKS`        25 000 000      d_safe distance checks per optimiser step,
                                               ``n_candidates * N (N - 1) / 2`` (about 2 GB)
:data:`MAX_SEEDS`              1 000 000       seeds of one sweep or reproduction
:data:`MAX_RUNS`               1 000 000       runs of one sweep (variants x seeds x team sizes x
                                               starts)
:data:`MAX_THREADS`            1 024           Rust threads of one call
:data:`MAX_GRID_CELLS`         10 000          cells along one side of a generated terrain
                                               (``size / spacing``, a wall's ``height /
                                               spacing``): 10^8 nodes
:data:`MAX_HILLS`              10 000          Gaussians of one hills terrain (``n_hills``)
:data:`MAX_SWEEP_FILE_BYTES`   1 MiB           one sweep file (TOML), checked before it is read
:data:`MAX_POLYGONS`           100 000 000     polygons of one figure's surface (``max_polygons``)
:data:`MAX_FILE_NAME_BYTES`    255             one file name uavcov writes (a run's ``<run_id>.npz``),
                                               checked before the run
=============================  ==============  ===================================================

Coordinates have a bound too, :data:`MAX_COORDINATE_M` (1e15 m): the engine refuses a surface
beyond it, and :func:`within_coordinate_bound` refuses points, frames and figures beyond it with
one message.
"""

from __future__ import annotations

import math
import numbers
import os
import stat
from pathlib import Path
from typing import Any

import numpy as np

from .errors import InvalidInputError, InvalidTypeError

__all__ = [
    "as_points",
    "as_float_array",
    "as_bool_array",
    "as_index_array",
    "as_finite_float",
    "as_positive_float",
    "as_non_negative_float",
    "as_positive_int",
    "as_non_negative_int",
    "as_n_threads",
    "as_generator",
    "as_count",
    "as_bool",
    "as_path",
    "as_tuple",
    "as_optional_str",
    "as_str",
    "as_bounds",
    "within_coordinate_bound",
    "MAX_COORDINATE_M",
    "MAX_UAVS",
    "MAX_GENERATORS",
    "MAX_SAMPLES",
    "MAX_ITERATIONS",
    "MAX_TRAJECTORY",
    "MAX_PAIR_CHECKS",
    "MAX_SEEDS",
    "MAX_RUNS",
    "MAX_THREADS",
    "MAX_GRID_CELLS",
    "MAX_HILLS",
    "MAX_SWEEP_FILE_BYTES",
    "MAX_POLYGONS",
]

MAX_UAVS = 1_000
"""Largest team (see the module's size limits)."""
MAX_GENERATORS = 10_000
"""Most generators of one CVT: its cost per iteration grows like generators x samples."""
MAX_SAMPLES = 10_000_000
"""Most CVT samples per iteration, and most prior points (``n_prior``)."""
MAX_ITERATIONS = 1_000_000
"""Most optimiser iterations of one mission."""
MAX_TRAJECTORY = 50_000_000
"""Most UAV positions one mission records: ``(iterations + 1) * n_uavs``."""
MAX_PAIR_CHECKS = 25_000_000
"""Most d_safe distance checks of one optimiser step: ``n_candidates * N * (N - 1) / 2``."""
MAX_SEEDS = 1_000_000
"""Most seeds of one sweep or reproduction."""
MAX_RUNS = 1_000_000
"""Most runs of one sweep."""
MAX_GRID_CELLS = 10_000
"""Most cells along one side of a generated terrain (10^8 nodes, checked before the grid is made)."""
MAX_HILLS = 10_000
"""Most Gaussians of one hills terrain: each costs a pass over every node."""
MAX_SWEEP_FILE_BYTES = 1 << 20
"""The largest sweep file read, bytes: a hand-written TOML of settings is a few kB; more is a wrong file."""
MAX_POLYGONS = 100_000_000
"""The most polygons a figure draws: far beyond what a picture shows (a count ``area / max_polygons`` divides)."""
MAX_WORKERS = 4096
"""Most local worker processes: far beyond any one machine; a larger count is a typo."""


def as_float_array(
    value: Any,
    name: str,
    *,
    ndim: int | None = None,
    allow_nan: bool = False,
    allow_bool: bool = False,
    nonfinite_error: type[InvalidInputError] = InvalidInputError,
) -> np.ndarray:
    """Return ``value`` as a C-contiguous float64 array, checking dimension and finiteness.

    Booleans are refused (a mask given for numbers) unless ``allow_bool``: then they read as 0 and 1.

    ``nonfinite_error`` is the class raised for NaN (unless ``allow_nan``) or infinite values:
    :class:`~uavcov.errors.MeshError` for the vertices of a mesh, for example.
    """
    if type(value) is np.ndarray and value.dtype == np.float64:
        # the common case (an optimiser's own arrays, hundreds of times a mission): no dtype probing
        array = np.ascontiguousarray(value)
    else:
        if isinstance(value, (str, bytes)):
            raise InvalidTypeError(f"{name} must be a numeric array, got {type(value).__name__}")
        array = _as_array(value, name, masked_as_nan=allow_nan)
        if array.dtype.kind not in "fiub":  # timedelta64 counts as an integer to numpy: not a number of metres
            raise InvalidTypeError(f"{name} must hold real numbers, got dtype {array.dtype}")
        if array.dtype == np.bool_ and not allow_bool:
            raise InvalidTypeError(f"{name} must hold real numbers, got booleans")
        with np.errstate(over="ignore"):  # a longdouble beyond float64 becomes inf, refused below
            array = np.ascontiguousarray(array, dtype=np.float64)
    if ndim is not None and array.ndim != ndim:
        raise InvalidInputError(f"{name} must be {ndim}-dimensional, got shape {array.shape}")
    if allow_nan:
        if np.isinf(array).any():
            raise nonfinite_error(f"{name} contains infinite values")
    elif not np.isfinite(array).all():
        raise nonfinite_error(f"{name} contains NaN or infinite values")
    return array


def _as_array(value: Any, name: str, *, masked_as_nan: bool = False) -> np.ndarray:
    """``np.asarray(value)`` with a uavcov error for what numpy cannot read (ragged lists and the like).

    A masked array's masked entries are not numbers: ``np.asarray`` would read whatever its
    data holds under the mask. They become NaN (no data) where ``masked_as_nan``, and are
    refused elsewhere.
    """
    if isinstance(value, np.ma.MaskedArray) and np.ma.getmaskarray(value).any():
        if not masked_as_nan or value.dtype.kind not in "fiu":
            raise InvalidInputError(f"{name} has masked entries: give the values themselves (np.ma.filled), not a mask over them")
        return np.ma.filled(value.astype(np.float64), np.nan)
    try:
        return np.asarray(value)
    except Exception as exc:  # ragged lists and the like
        raise InvalidInputError(f"{name} cannot be read as an array: {exc}") from exc


def as_bool_array(value: Any, name: str, length: int) -> np.ndarray:
    """Return ``value`` as a ``(length,)`` bool array (a mask or flags); other dtypes are refused."""
    array = _as_array(value, name)
    if array.shape != (length,) or array.dtype != np.bool_:
        raise InvalidInputError(f"{name} must be a ({length},) bool array, got {array.dtype} {array.shape}")
    return array


def is_int(value: Any) -> bool:
    """An integer (Python or numpy), and not a bool (nor a numpy timedelta, an integer to numpy)."""
    return isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.timedelta64))


def as_points(value: Any, name: str, *, dim: int = 3, allow_empty: bool = False) -> np.ndarray:
    """Return ``value`` as a finite ``(n, dim)`` float64 array (a single point becomes ``(1, dim)``)."""
    array = as_float_array(value, name)
    if array.ndim == 1 and array.shape[0] == dim:
        array = array.reshape(1, dim)
    if array.ndim != 2 or array.shape[1] != dim:
        raise InvalidInputError(f"{name} must have shape (n, {dim}), got {array.shape}")
    if array.shape[0] == 0 and not allow_empty:
        raise InvalidInputError(f"{name} is empty: at least one point is needed")
    return array


def as_index_array(value: Any, name: str, *, columns: int | None = 3) -> np.ndarray:
    """Return ``value`` as a ``(n, columns)`` int64 array (any shape for ``columns=None``);
    floats are refused, not rounded."""
    array = _as_array(value, name)
    if array.size == 0 and array.dtype == np.float64:
        array = array.astype(np.int64)  # np.asarray([]) is float64; an empty list is not a float
    if array.dtype.kind not in "iu":  # not bool, nor timedelta64 (an integer to numpy)
        raise InvalidTypeError(f"{name} must hold integers, got dtype {array.dtype}")
    if array.dtype.kind == "u" and array.size and int(array.max()) > np.iinfo(np.int64).max:
        # int64 would wrap it to a negative index
        raise InvalidInputError(f"{name} holds an index beyond int64, {int(array.max())}")
    if columns is not None and (array.ndim != 2 or array.shape[1] != columns):
        raise InvalidInputError(f"{name} must have shape (n, {columns}), got {array.shape}")
    if array.ndim == 0:
        return array.astype(np.int64)  # ascontiguousarray would make it 1-d
    return np.ascontiguousarray(array, dtype=np.int64)


def as_finite_float(value: Any, name: str) -> float:
    """Return ``value`` as a finite Python float."""
    if isinstance(value, (bool, np.timedelta64)) or not isinstance(value, (numbers.Real, np.floating, np.integer)):
        raise InvalidTypeError(f"{name} must be a real number, got {type(value).__name__}")
    try:
        result = float(value)
    except OverflowError:  # an int or Fraction beyond the largest float
        raise InvalidInputError(f"{name} must be finite, got a number beyond the largest float ({str(value)[:20]}...)") from None
    if not math.isfinite(result):
        raise InvalidInputError(f"{name} must be finite, got {result}")
    return result


def as_positive_float(value: Any, name: str) -> float:
    """Return ``value`` as a finite float > 0."""
    result = as_finite_float(value, name)
    if result <= 0.0:
        raise InvalidInputError(f"{name} must be > 0, got {result}")
    return result


def as_non_negative_float(value: Any, name: str) -> float:
    """Return ``value`` as a finite float >= 0."""
    result = as_finite_float(value, name)
    if result < 0.0:
        raise InvalidInputError(f"{name} must be >= 0, got {result}")
    return result


def _as_int(value: Any, name: str) -> int:
    if isinstance(value, (bool, np.timedelta64)) or not isinstance(value, (numbers.Integral, np.integer)):
        raise InvalidTypeError(f"{name} must be an integer, got {type(value).__name__}")
    return int(value)


def _int_at_least(value: Any, name: str, minimum: int) -> int:
    result = _as_int(value, name)
    if result < minimum:
        raise InvalidInputError(f"{name} must be >= {minimum}, got {result}")
    return result


def as_positive_int(value: Any, name: str) -> int:
    """Return ``value`` as an int > 0."""
    return _int_at_least(value, name, 1)


def as_non_negative_int(value: Any, name: str) -> int:
    """Return ``value`` as an int >= 0."""
    return _int_at_least(value, name, 0)


def as_count(value: Any, name: str, maximum: int, *, minimum: int = 1) -> int:
    """Return ``value`` as an int in ``[minimum, maximum]`` (``maximum`` one of the size limits)."""
    result = _int_at_least(value, name, minimum)
    if result > maximum:
        raise InvalidInputError(f"{name} must be at most {maximum:,}, got {result:,} (uavcov's size limit)")
    return result


MAX_THREADS = 1024
"""Most threads one call may ask for: more is a mistake, and each costs a stack."""


def as_n_threads(value: Any) -> int:
    """Return the thread count for a Rust call: 1..MAX_THREADS, or 0 for ``None``.

    ``None`` means rayon's default: ``RAYON_NUM_THREADS`` if set, else every core; a
    ``RAYON_NUM_THREADS`` beyond MAX_THREADS is refused as an ``n_threads`` beyond it is (the
    core would start that many threads, minutes of thread starts for a typo).
    """
    if value is None:
        _check_rayon_num_threads()
        return 0  # the Rust side reads 0 as "rayon's default" (rust/threads.rs)
    n = as_positive_int(value, "n_threads")
    if n > MAX_THREADS:
        raise InvalidInputError(f"n_threads must be at most {MAX_THREADS}, got {n}")
    return n


def _check_rayon_num_threads() -> None:
    """Refuse a ``RAYON_NUM_THREADS`` the core would read as more than MAX_THREADS threads.

    The core reads it as rayon does (a whole number, blanks around it ignored; anything else is
    ignored, and every core used): the same reading here, so that only a count it would use is refused.
    """
    text = os.environ.get("RAYON_NUM_THREADS", "").strip().removeprefix("+")
    digits = text.lstrip("0")  # int() of thousands of digits raises: the length says it first
    if text.isascii() and text.isdigit() and (len(digits) > len(str(MAX_THREADS)) or int(digits or "0") > MAX_THREADS):
        raise InvalidInputError(
            f"the environment variable RAYON_NUM_THREADS asks for {digits[:20]}{'...' if len(digits) > 20 else ''} threads, "
            f"more than {MAX_THREADS} (uavcov's limit); unset it or give a count of threads"
        )


_RNG_KINDS = "None, an int, a SeedSequence or a numpy Generator"


def as_generator(rng: Any) -> np.random.Generator:
    """``numpy.random.default_rng(rng)`` (SPEC 7: None, an int, a SeedSequence or a Generator),
    with a uavcov error for anything else (True and False too: numpy would seed with 1 and 0).

    A legacy ``RandomState`` (or a generator over a legacy-seeded bit generator) is refused too:
    numpy wraps it without a SeedSequence, and uavcov splits one generator into independent
    streams (``spawn``), which such a generator cannot do.
    """
    if isinstance(rng, (bool, np.bool_)):
        raise InvalidTypeError(f"rng must be {_RNG_KINDS}, got {rng!r}")
    if isinstance(rng, np.random.RandomState):
        raise InvalidTypeError(
            f"rng must be {_RNG_KINDS}, got a legacy RandomState: give its seed, or np.random.default_rng(seed), instead"
        )
    try:
        generator = np.random.default_rng(rng)
    except (TypeError, ValueError) as exc:
        raise InvalidTypeError(f"rng must be {_RNG_KINDS}, got {rng!r}") from exc
    if not isinstance(generator.bit_generator.seed_seq, np.random.SeedSequence):
        raise InvalidTypeError(
            f"rng must be {_RNG_KINDS} seeded by a SeedSequence, got one over a legacy-seeded bit generator "
            "(it cannot be split into independent streams): give np.random.default_rng(seed) instead"
        )
    return generator


def as_bool(value: Any, name: str) -> bool:
    """``value`` as a bool: only True or False (Python's or numpy's), never an array's truth."""
    if not isinstance(value, (bool, np.bool_)):
        raise InvalidTypeError(f"{name} must be True or False, got {type(value).__name__}")
    return bool(value)


def as_path(value: Any, name: str) -> Path:
    """``value`` as a :class:`~pathlib.Path`: a string or an ``os.PathLike``, nothing else."""
    if not isinstance(value, (str, os.PathLike)):
        raise InvalidTypeError(f"{name} must be a path string or os.PathLike, got {type(value).__name__}")
    return Path(checked_path_text(os.fspath(value), name))


def checked_path_text(text: str, name: str) -> str:
    """``text`` (a path's string, ``os.fspath`` of it) unless it is empty or holds a NUL character.

    ``Path("")`` is the working directory: an empty path (an unset variable, ``--out ""``) would
    write there, or read it, instead of being the mistake it is; no file name holds a NUL.
    """
    if not isinstance(text, str):
        raise InvalidTypeError(f"{name} must be a path string or os.PathLike of one, got {type(text).__name__}")
    if not text:
        raise InvalidInputError(f"{name} is an empty path: give a file or folder name ('.' for the working directory)")
    if "\0" in text:
        raise InvalidInputError(f"{name} holds a NUL character, which no path may hold")
    return text


def as_optional_str(value: Any, name: str) -> str | None:
    """``value`` when it is None or a string (a title, a label, a command line)."""
    if value is not None and not isinstance(value, str):
        raise InvalidTypeError(f"{name} must be None or a string, got {type(value).__name__}")
    return value


def not_a_terrain(value: Any, name: str) -> InvalidTypeError:
    """The error for ``name`` given something else than a uavcov Terrain, saying what to give instead.

    A :class:`~uavcov.structures.Structure` (it has a ``surface`` and ``targets``) is the usual
    mix-up: its mesh is ``.surface`` and its targets ``.targets(spacing=...)``.
    """
    hint = ""
    if hasattr(value, "surface") and hasattr(value, "targets"):
        hint = " (a structure's mesh is its .surface, and Visibility takes its .targets(spacing=...) as targets)"
    return InvalidTypeError(f"{name} must be a uavcov Terrain, got {type(value).__name__}{hint}")


def as_str(value: Any, name: str) -> str:
    """``value`` when it is a non-empty string (a name, a label, a word of a choice)."""
    if not isinstance(value, str):
        raise InvalidTypeError(f"{name} must be a string, got {type(value).__name__}")
    if not value.strip():
        raise InvalidInputError(f"{name} must be a non-empty string, got {value!r}")
    return value


MAX_COORDINATE_M = 1e15
"""The largest coordinate magnitude, metres: the engine's bound on a surface's vertices (a
coordinate there still resolves 0.125 m; beyond it areas and sight lines lose their meaning)."""


def within_coordinate_bound(points: np.ndarray, name: str) -> np.ndarray:
    """``points`` (a float array of coordinates, metres) when none is beyond :data:`MAX_COORDINATE_M`.

    NaN passes (finiteness is the caller's check); an infinite coordinate does not.
    """
    if points.size:
        largest = float(np.nanmax(np.abs(points), initial=0.0))
        if largest > MAX_COORDINATE_M:
            raise InvalidInputError(f"{name} must lie within 1e15 m of the origin, got a coordinate of {largest:g} m")
    return points


def as_bounds(value: Any, name: str = "bounds") -> tuple[float, float, float, float]:
    """An x-y rectangle ``(xmin, ymin, xmax, ymax)`` of finite floats with ``xmin < xmax``, ``ymin < ymax``
    (also read from ``[[xmin, ymin, ...], [xmax, ymax, ...]]``, a surface's ``bounds``)."""
    if isinstance(value, (str, bytes)):
        raise InvalidTypeError(f"{name} must be (xmin, ymin, xmax, ymax), got a string")
    array = as_float_array(value, name)
    if array.ndim == 2 and array.shape[0] == 2 and array.shape[1] >= 2:
        array = np.array([array[0, 0], array[0, 1], array[1, 0], array[1, 1]])
    if array.shape != (4,):
        raise InvalidInputError(
            f"{name} must be (xmin, ymin, xmax, ymax) or [[xmin, ymin, ...], [xmax, ymax, ...]], got shape {array.shape}"
        )
    xmin, ymin, xmax, ymax = (float(v) for v in array)
    if not (xmin < xmax and ymin < ymax):
        raise InvalidInputError(f"{name} need xmin < xmax and ymin < ymax, got {(xmin, ymin, xmax, ymax)}")
    return xmin, ymin, xmax, ymax


def as_tuple(value: Any, name: str) -> tuple[Any, ...]:
    """``value`` (a list, tuple, array or other iterable, not a string or a mapping) as a tuple.

    A 0-d array is refused: it has ``__iter__`` but no items (numpy raises on iterating it).
    """
    if isinstance(value, (str, bytes, dict)) or not hasattr(value, "__iter__") or is_0d_array(value):
        raise InvalidTypeError(f"{name} must be a sequence, got {_kind_of(value)}")
    return tuple(value)


def is_0d_array(value: Any) -> bool:
    """A numpy array of no dimension (``np.array(3)``): iterable to Python's eyes, not to numpy's."""
    return isinstance(value, np.ndarray) and value.ndim == 0


def _kind_of(value: Any) -> str:
    return f"a 0-d array of {value.dtype}" if is_0d_array(value) else type(value).__name__


def as_range(value: Any, name: str, *, positive: bool = False) -> tuple[float, float]:
    """A ``(low, high)`` pair of finite floats with ``low <= high`` (a single number means both)."""
    if isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool):
        low = high = as_finite_float(value, name)
    else:
        pair = as_float_array(value, name, ndim=1)
        if pair.shape != (2,):
            raise InvalidInputError(f"{name} must be a number or a (low, high) pair, got shape {pair.shape}")
        low, high = float(pair[0]), float(pair[1])
    if low > high:
        raise InvalidInputError(f"{name} must have low <= high, got ({low}, {high})")
    if positive and low <= 0.0:
        raise InvalidInputError(f"{name} must be > 0, got ({low}, {high})")
    return low, high


def as_spacing(spacing: Any, name: str = "spacing") -> tuple[float, float]:
    """``spacing`` as ``(dx, dy)``, both finite and > 0."""
    if isinstance(spacing, (int, float, np.integer, np.floating)) and not isinstance(spacing, bool):
        value = as_positive_float(spacing, name)
        return value, value
    pair = as_float_array(spacing, name, ndim=1)
    if pair.shape != (2,):
        raise InvalidInputError(f"{name} must be a number or a (dx, dy) pair, got shape {pair.shape}")
    if not (pair > 0.0).all():
        raise InvalidInputError(f"{name} must be > 0, got {tuple(pair)}")
    return float(pair[0]), float(pair[1])


def cells_along(length: float, step: float, name: str) -> float:
    """``length / step``, the cells of side ``step`` along ``length``, refused beyond :data:`MAX_GRID_CELLS`
    before the caller rounds it (a subnormal ``step`` makes it inf, which no ``int`` holds)."""
    count = length / step
    if not count <= MAX_GRID_CELLS + 0.5:
        raise InvalidInputError(
            f"{name} ({length:g} m) in cells of {step:g} m is {count:,.0f} cells, more than {MAX_GRID_CELLS:,} (uavcov's size limit)"
        )
    return count


def as_cell_count(length: float, step: float, name: str) -> int:
    """Number of cells of size ``step`` in ``length``; the division must be (nearly) exact."""
    count = length / step
    if count > MAX_GRID_CELLS + 0.5:  # checked first: round() of an infinite ratio would overflow
        raise InvalidInputError(
            f"{name} ({length} m) is {count:,.0f} spacings ({step} m) long, more than {MAX_GRID_CELLS:,} (uavcov's size limit)"
        )
    cells = round(count)
    if cells < 1 or abs(count - cells) > 1e-9 * max(1.0, count):
        raise InvalidInputError(f"{name} ({length} m) must be a positive multiple of the spacing ({step} m)")
    return cells


MAX_FILE_NAME_BYTES = 255
"""The longest file name, bytes, on Linux, macOS and Windows file systems."""


def within_file_name_limit(name: str, what: str) -> str:
    """``name`` (a file name uavcov will write) when a file system can hold it: checked before the
    work whose result it names, not when that result is saved."""
    if len(name.encode()) > MAX_FILE_NAME_BYTES:
        raise InvalidInputError(
            f"{what} would be named with {len(name.encode())} bytes, past the {MAX_FILE_NAME_BYTES} bytes a file name may have; "
            "use a shorter name"
        )
    return name


def read_only(array: np.ndarray) -> np.ndarray:
    """``array`` itself, made read-only: a result hands out arrays nobody can change under it.

    Copy first (``read_only(np.array(x))``) when the caller keeps a writable alias.
    """
    array.setflags(write=False)
    return array


def existing_path(path: Any, what: str, error: type[Exception]) -> str:
    """``path`` as a string, checked to name an existing file; ``error`` (naming ``what``) when it does not.

    Raises ``InvalidTypeError`` when ``path`` is neither a string nor ``os.PathLike``.
    """
    if not isinstance(path, (str, os.PathLike)):
        raise InvalidTypeError(f"path must be a string or os.PathLike, got {type(path).__name__}")
    text = checked_path_text(os.fspath(path), "path")
    if not os.path.exists(text):
        raise error(f"{what} file {text!r} does not exist")
    if os.path.isdir(text):
        raise error(f"{what} path {text!r} is a directory, not a file")
    if not os.path.isfile(text):
        raise error(f"{what} path {text!r} is not a regular file (a FIFO, socket or device): reading it could block or never end")
    return text


def open_regular_file(path: Path, what: str, error: type[Exception]) -> Any:
    """``path`` opened for reading in binary, when the opened file is a regular file; ``error`` else.

    The check is made on the opened file (``fstat``), not on its name: a file swapped for a FIFO
    after a check by name would block the read forever (the open itself does not: ``O_NONBLOCK``,
    which a regular file ignores).
    """
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except (OSError, ValueError) as exc:
        raise error(f"cannot read the {what} {path}: {getattr(exc, 'strerror', None) or exc}") from exc
    handle = os.fdopen(fd, "rb")
    if not stat.S_ISREG(os.fstat(fd).st_mode):
        handle.close()
        raise error(f"the {what} {path} is not a regular file (it changed since it was checked): reading it could block or never end")
    return handle


def read_regular_file(path: Path, what: str, error: type[Exception], max_bytes: int) -> bytes:
    """The bytes of ``path`` when it is a regular file of at most ``max_bytes``; ``error`` when not.

    :func:`regular_file`'s checks, made on the opened file itself (``fstat``), then at most
    ``max_bytes + 1`` bytes read: a file replaced by a FIFO, or grown past the limit, between a
    check by name and the read is refused too (the open does not block on a FIFO: ``O_NONBLOCK``).
    """
    regular_file(path, what, error, max_bytes)  # the messages of a missing file, a folder, ...
    with open_regular_file(path, what, error) as handle:
        try:
            data: bytes = handle.read(max_bytes + 1)
        except OSError as exc:
            raise error(f"cannot read the {what} {path}: {exc.strerror or exc}") from exc
    if len(data) > max_bytes:
        raise error(f"the {what} {path} is more than the {max_bytes:,} bytes it may have (it grew since it was checked)")
    return data


def regular_file(path: Path, what: str, error: type[Exception], max_bytes: int) -> Path:
    """``path`` when it names a regular file of at most ``max_bytes``; ``error`` (naming ``what``) when not.

    Checked before a file is read whole: a FIFO would block the read forever, ``/dev/zero``
    would never end it, and a huge file would fill the memory.
    """
    try:
        info = path.stat()
    except (OSError, ValueError) as exc:
        raise error(f"cannot read the {what} {path}: {getattr(exc, 'strerror', None) or exc}") from exc
    if stat.S_ISDIR(info.st_mode):
        raise error(f"the {what} {path} is a directory, not a file")
    if not stat.S_ISREG(info.st_mode):
        raise error(f"the {what} {path} is not a regular file (a FIFO, socket or device): reading it could block or never end")
    if info.st_size > max_bytes:
        raise error(f"the {what} {path} is {info.st_size:,} bytes, more than the {max_bytes:,} it may have")
    return path
