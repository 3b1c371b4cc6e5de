"""Random draws that numpy makes, made faster and bit for bit the same.

CAO draws a few thousand standard normal perturbations per iteration; numpy spends about
9 ns a value on them, a tenth of a mission's time. :func:`standard_normal` draws the same
values, and leaves the generator in the same state, with a compiled loop (``uavcov._core``),
so a seeded run gives the same mission either way.

CAO also redraws some of its monomials every iteration, a dozen small numpy calls (about 20 us);
``redraw_monomials`` makes them in one call, with numpy's ``Generator.integers`` and
``Generator.random`` reproduced in Rust (``_core.pcg64_integers`` and ``_core.pcg64_random``
expose those two for the tests).
"""

from __future__ import annotations

import operator

import numpy as np

from .. import _core
from ..errors import InvalidInputError, InvalidTypeError


def standard_normal(rng: np.random.Generator, shape: int | tuple[int, ...]) -> np.ndarray:
    """Standard normal values of ``shape``, exactly as ``rng.standard_normal(shape)`` draws them.

    Parameters
    ----------
    rng : numpy.random.Generator
        The generator to draw from; it advances exactly as numpy's own draw would advance it.
    shape : int or tuple of int
        The shape of the result; every dimension non-negative.

    Returns
    -------
    numpy.ndarray
        float64 values of ``shape``, C-contiguous, equal bit for bit to numpy's.

    Raises
    ------
    InvalidTypeError
        ``rng`` not a Generator, ``shape`` not integers.
    InvalidInputError
        If a dimension is negative.
    SurfaceTooLargeError
        If more values are asked for than one call draws (2^34) or than memory holds.

    Notes
    -----
    A generator on numpy's ``PCG64`` bit generator (what ``np.random.default_rng`` makes) is
    drawn from in Rust, under the bit generator's lock: its state is read, advanced past the
    draws and written back, with the increment and numpy's buffered 32-bit half unchanged (64-bit
    draws do not touch it). Any other bit generator, a subclass of ``PCG64`` included (it may
    draw differently), is left to numpy.

    Examples
    --------
    >>> import numpy as np
    >>> from uavcov.optim import standard_normal
    >>> a, b = np.random.default_rng(7), np.random.default_rng(7)
    >>> np.array_equal(standard_normal(a, (2, 3)), b.standard_normal((2, 3)))
    True
    >>> a.bit_generator.state == b.bit_generator.state
    True
    """
    if not isinstance(rng, np.random.Generator):
        raise InvalidTypeError(f"rng must be a numpy Generator, got {type(rng).__name__}")
    try:
        if isinstance(shape, (str, bytes, dict)):  # iterable, but never a shape
            raise TypeError(shape)
        dims = (shape,) if isinstance(shape, (int, np.integer)) else tuple(shape)
        if any(isinstance(d, (bool, np.bool_)) for d in dims):  # numpy would read True as 1
            raise TypeError(shape)
        dims = tuple(operator.index(d) for d in dims)
    except TypeError:
        raise InvalidTypeError(f"shape must be an int or a tuple of ints, got {shape!r}") from None
    if any(d < 0 for d in dims):
        raise InvalidInputError(f"shape must have non-negative dimensions, got {shape!r}")
    bit_generator = rng.bit_generator
    if type(bit_generator) is not np.random.PCG64:
        return rng.standard_normal(dims)
    n = 1
    for d in dims:  # Python ints: no overflow before the kernel checks the size
        n *= d
    with bit_generator.lock:  # another thread's draw between our read and write would be lost
        state = bit_generator.state
        words = state["state"]
        values, words["state"] = _core.pcg64_standard_normal(words["state"], words["inc"], n)
        bit_generator.state = state
    return values.reshape(dims)


def redraw_monomials(
    terms: np.ndarray, strength: np.ndarray, keep: int, count: int, dim: int, rng: np.random.Generator
) -> np.ndarray | None:
    """CAO's monomial refresh, as ``uavcov.optim._monomials._refresh_terms_numpy`` makes it, or ``None``.

    Parameters
    ----------
    terms : numpy.ndarray, shape (T, 3), int64
        Monomials as index triples into ``dim`` coordinates and a constant (index ``dim``).
    strength : numpy.ndarray, shape (T,), float64
        What each monomial contributes to the fit; the strongest are kept.
    keep : int
        How many of ``terms`` are kept: the ``keep`` strongest (ties by position), in index order.
    count : int
        How many new monomials are drawn, distinct from those kept and from each other.
    dim : int
        Variables of the monomials, at most 2^32.
    rng : numpy.random.Generator
        The generator to draw from; it advances exactly as numpy's own draws would advance it.

    Returns
    -------
    numpy.ndarray or None
        ``(keep + count, 3)`` int64 rows, the kept ones first, then the new ones in the order
        drawn. ``None``, with ``rng`` untouched, when numpy must draw: a bit generator other than
        ``PCG64`` (a subclass included), or so few free monomials that ``_draw_monomials``
        samples without replacement (``4 * (kept + count)`` above the number of monomials).

    Raises
    ------
    InvalidInputError
        Inconsistent sizes, an index outside ``[0, dim]``, or fewer than ``count`` monomials left.

    Notes
    -----
    numpy draws each round of the rejection loop as ``integers(0, dim, (2 need + 4, 3))`` then
    ``random(2 need + 4)``; here the same words are drawn in the same order, so the generator's
    state afterwards, 32-bit buffer included, is numpy's. It is read and written under the bit
    generator's lock, as in :func:`standard_normal`.
    """
    bit_generator = rng.bit_generator
    if type(bit_generator) is not np.random.PCG64:
        return None
    with bit_generator.lock:
        state = bit_generator.state
        words = state["state"]
        rows, words["state"], state["has_uint32"], state["uinteger"] = _core.pcg64_monomials(
            terms, strength, keep, count, dim, words["state"], words["inc"], state["has_uint32"], state["uinteger"]
        )
        if rows is not None:
            bit_generator.state = state
    return rows
