"""Argument checks shared by every public function.

Each check returns the value converted to what the library computes with (a C-contiguous
float64 array, a Python float, ...) or raises an error from :mod:`uavcov.errors` that names the
argument. Converting here, once, is what lets the Rust core assume clean input.
"""

from __future__ import annotations

import math
import numbers
from typing import Any

import numpy as np

from .errors import InvalidInputError, InvalidTypeError

__all__ = [
    "as_points",
    "as_float_array",
    "as_index_array",
    "as_finite_float",
    "as_positive_float",
    "as_non_negative_float",
    "as_positive_int",
    "as_non_negative_int",
    "as_n_threads",
    "as_generator",
]


def as_float_array(value: Any, name: str, *, ndim: int | None = None, allow_nan: bool = False) -> np.ndarray:
    """Return ``value`` as a C-contiguous float64 array, checking dimension and finiteness."""
    if isinstance(value, (str, bytes)):
        raise InvalidTypeError(f"{name} must be a numeric array, got {type(value).__name__}")
    try:
        array = np.asarray(value)
    except Exception as exc:  # ragged lists and the like
        raise InvalidInputError(f"{name} cannot be read as an array: {exc}") from exc
    if array.dtype == object or not (
        np.issubdtype(array.dtype, np.floating)
        or np.issubdtype(array.dtype, np.integer)
        or array.dtype == np.bool_
    ):
        raise InvalidTypeError(f"{name} must hold real numbers, got dtype {array.dtype}")
    if array.dtype == np.bool_:
        raise InvalidTypeError(f"{name} must hold real numbers, got booleans")
    array = np.ascontiguousarray(array, dtype=np.float64)
    if ndim is not None and array.ndim != ndim:
        raise InvalidInputError(f"{name} must be {ndim}-dimensional, got shape {array.shape}")
    if allow_nan:
        if np.isinf(array).any():
            raise InvalidInputError(f"{name} contains infinite values")
    elif not np.isfinite(array).all():
        raise InvalidInputError(f"{name} contains NaN or infinite values")
    return array


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


def as_index_array(value: Any, name: str, *, columns: int = 3) -> np.ndarray:
    """Return ``value`` as a ``(n, columns)`` int64 array; floats are refused, not rounded."""
    try:
        array = np.asarray(value)
    except Exception as exc:
        raise InvalidInputError(f"{name} cannot be read as an array: {exc}") from exc
    if array.size == 0 and array.dtype == np.float64:
        array = array.astype(np.int64)  # np.asarray([]) is float64; an empty list is not a float
    if not np.issubdtype(array.dtype, np.integer) or array.dtype == np.bool_:
        raise InvalidTypeError(f"{name} must hold integers, got dtype {array.dtype}")
    if array.ndim != 2 or array.shape[1] != columns:
        raise InvalidInputError(f"{name} must have shape (n, {columns}), got {array.shape}")
    return np.ascontiguousarray(array, dtype=np.int64)


def as_finite_float(value: Any, name: str) -> float:
    """Return ``value`` as a finite Python float."""
    if isinstance(value, bool) or not isinstance(value, (numbers.Real, np.floating, np.integer)):
        raise InvalidTypeError(f"{name} must be a real number, got {type(value).__name__}")
    result = float(value)
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
    if isinstance(value, bool) or not isinstance(value, (numbers.Integral, np.integer)):
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


MAX_THREADS = 1024
"""Most threads one call may ask for: more is a mistake, and each costs a stack."""


def as_n_threads(value: Any) -> int:
    """Return the thread count for a Rust call: 1..MAX_THREADS, or 0 for ``None``.

    ``None`` means rayon's default: ``RAYON_NUM_THREADS`` if set, else every core.
    """
    if value is None:
        return 0  # the Rust side reads 0 as "rayon's default" (rust/threads.rs)
    n = as_positive_int(value, "n_threads")
    if n > MAX_THREADS:
        raise InvalidInputError(f"n_threads must be at most {MAX_THREADS}, got {n}")
    return n


def as_generator(rng: Any) -> np.random.Generator:
    """``numpy.random.default_rng(rng)`` (SPEC 7: None, an int, a SeedSequence or a Generator),
    with a uavcov error for anything else."""
    try:
        return np.random.default_rng(rng)
    except (TypeError, ValueError) as exc:
        raise InvalidTypeError(f"rng must be None, an int, a SeedSequence or a numpy Generator, got {rng!r}") from exc


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


def as_cell_count(length: float, step: float, name: str) -> int:
    """Number of cells of size ``step`` in ``length``; the division must be (nearly) exact."""
    count = length / step
    cells = round(count)
    if cells < 1 or abs(count - cells) > 1e-9 * max(1.0, count):
        raise InvalidInputError(f"{name} ({length} m) must be a positive multiple of the spacing ({step} m)")
    return cells
