"""CAO's regressors: random 2nd- and 3rd-order monomials of normalised coordinates.

A nonlinear term is three indices into the coordinates augmented with a column of ones (index
``dim``), so u_i * u_j is (i, j, dim) and u_i * u_j * u_l is (i, j, l); every term is a
product of three gathered columns, which vectorises over candidates and robots alike. The draws
are made in Rust for numpy's ``PCG64`` (``uavcov.optim._draws.redraw_monomials``) and in numpy for
any other bit generator, with the same values.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from .._validate import read_only
from ..errors import InvalidInputError
from ._draws import redraw_monomials


def _n_distinct_monomials(dim: int) -> int:
    """Distinct monomials of degree 2 and 3 in ``dim`` variables."""
    return math.comb(dim + 1, 2) + math.comb(dim + 2, 3)


@functools.lru_cache(maxsize=64)
def _all_monomials(dim: int) -> np.ndarray:
    """Every distinct degree-2 and degree-3 monomial, as sorted index triples (read-only)."""
    rows = []
    for i in range(dim):
        for j in range(i, dim):
            rows.append((i, j, dim))
            rows.extend((i, j, k) for k in range(j, dim))
    return read_only(np.array(rows, dtype=np.int64).reshape(-1, 3))


def _draw_monomials(count: int, dim: int, existing: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Draw ``count`` random monomials distinct from each other and from ``existing`` rows.

    Degree 2 or 3 with equal probability, variables uniform with replacement (so squares and
    cubes occur). Falls back to sampling without replacement from the full list when rejection
    would be slow (few variables).
    """
    if count == 0:
        return np.empty((0, 3), dtype=np.int64)
    # a sorted index triple as one integer, so that membership is a set of ints
    base = dim + 1
    taken = {(a * base + b) * base + c for a, b, c in existing.tolist()}
    total = _n_distinct_monomials(dim)
    if total - len(taken) < count:  # guarded by regressors_for; kept as an internal check
        raise InvalidInputError(f"cannot draw {count} new monomials of {dim} variables")
    if 4 * (len(taken) + count) > total:
        every = _all_monomials(dim)
        pool = [row for row in every.tolist() if (row[0] * base + row[1]) * base + row[2] not in taken]
        chosen = rng.choice(len(pool), size=count, replace=False)
        return np.array([pool[c] for c in chosen], dtype=np.int64)
    out: list[int] = []
    while len(out) < count:
        need = count - len(out)
        # A few dozen triples a call: plain Python on lists beats numpy's per-call cost here
        # (the draws are numpy's, so the stream is the same).
        rows = rng.integers(0, dim, size=(2 * need + 4, 3)).tolist()
        quadratic = (rng.random(2 * need + 4) < 0.5).tolist()
        for row, square in zip(rows, quadratic, strict=True):
            if square:
                row[2] = dim
            a, b, c = sorted(row)
            key = (a * base + b) * base + c
            if key not in taken:
                taken.add(key)
                out.append(key)
                if len(out) == count:
                    break
    return np.array([(key // (base * base), key // base % base, key % base) for key in out], dtype=np.int64)


def _first_terms(count: int, dim: int, rng: np.random.Generator) -> np.ndarray:
    """``_draw_monomials(count, dim, none, rng)``, in Rust for numpy's ``PCG64`` (as :func:`_refresh_terms`)."""
    none = np.empty((0, 3), dtype=np.int64)
    drawn = redraw_monomials(none, np.empty(0), 0, count, dim, rng)
    return _draw_monomials(count, dim, none, rng) if drawn is None else drawn


def _refresh_terms(terms: np.ndarray, strength: np.ndarray, keep_fraction: float, dim: int, rng: np.random.Generator) -> np.ndarray:
    """Keep the strongest monomials (ties by position) and redraw the others.

    :func:`_refresh_terms_numpy`'s terms and draws, made in one Rust call when ``rng`` is
    numpy's ``PCG64`` (``uavcov.optim._draws.redraw_monomials``), else by that reference.
    """
    n_terms = terms.shape[0]
    n_keep = math.ceil(keep_fraction * n_terms)
    if n_keep >= n_terms:
        return terms
    drawn = redraw_monomials(terms, strength, n_keep, n_terms - n_keep, dim, rng)
    return _refresh_terms_numpy(terms, strength, keep_fraction, dim, rng) if drawn is None else drawn


def _refresh_terms_numpy(terms: np.ndarray, strength: np.ndarray, keep_fraction: float, dim: int, rng: np.random.Generator) -> np.ndarray:
    """:func:`_refresh_terms` with numpy's draws: the reference the kernel is held to."""
    n_terms = terms.shape[0]
    n_keep = math.ceil(keep_fraction * n_terms)
    if n_keep >= n_terms:
        return terms
    order = np.argsort(-strength, kind="stable")
    kept = terms[np.sort(order[:n_keep])]
    fresh = _draw_monomials(n_terms - n_keep, dim, kept, rng)
    return np.concatenate([kept, fresh], axis=0)


def _refresh_robot_terms(selected: np.ndarray, strength: np.ndarray, keep_fraction: float, rng: np.random.Generator) -> np.ndarray:
    """:func:`_refresh_terms` for every robot at once, on ``(N, 16)`` masks of active monomials.

    ``strength`` is ``(N, 16)`` (zero for inactive monomials).
    """
    n_terms = int(selected[0].sum())
    n_keep = math.ceil(keep_fraction * n_terms)
    if n_keep >= n_terms:
        return selected
    # strongest active first; inactive ones sort last whatever their (zero) strength
    rank_key = np.where(selected, -strength, np.inf)
    order = np.argsort(rank_key, axis=1, kind="stable")
    fresh = np.zeros_like(selected)
    np.put_along_axis(fresh, order[:, :n_keep], True, axis=1)
    keys = rng.random(selected.shape)
    keys[fresh] = np.inf  # never redraw a kept one
    redraw = np.argsort(keys, axis=1, kind="stable")[:, : n_terms - n_keep]
    np.put_along_axis(fresh, redraw, True, axis=1)
    return fresh
