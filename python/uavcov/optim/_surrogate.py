"""CAO's surrogate: the fitting window (eq. 4), its normalisation, and the Rust fit-and-score kernels.

``tests/cao_reference.py`` holds the same maths in numpy, the reference the tests hold these
kernels to.
"""

from __future__ import annotations

import numpy as np

from .. import _core
from ._monomials import _all_monomials


def _window_start(k: int, n_window: int) -> int:
    """``l_k = max(0, k - L - T_h)`` of the paper's eq. 4: iteration ``k`` fits ``l_k ... k - 1``.

    The window holds the ``L + T_h`` measurements before ``x_k``'s own (``n_window = L + T_h``),
    so the move from ``x_k`` is chosen on what was measured before reaching it; at ``k = 0`` it
    is empty and the surrogate is flat.
    """
    return max(0, k - n_window)


def _scale(window: np.ndarray, centre: np.ndarray, alpha: float) -> np.ndarray:
    """Normalisation scale(s) ``max(alpha, rms distance per coordinate)`` over the window.

    ``window`` is ``(W, ..., d)`` and ``centre`` ``(..., d)``; one scale per leading estimator.
    """
    if window.shape[0] == 0:
        return np.broadcast_to(np.float64(alpha), centre.shape[:-1]).copy()
    if window.ndim == 2:  # one estimator: np.mean's own reduction, without its dispatch (same bits)
        squares = window - centre
        squares *= squares
        spread = np.sqrt(np.add.reduce(squares, axis=None) / squares.size)
    else:
        spread = np.sqrt(np.mean((window - centre) ** 2, axis=(0, -1)))
    scale: np.ndarray = np.maximum(alpha, spread)
    return scale


def _fit_and_score(
    window: np.ndarray, values: np.ndarray, terms: np.ndarray, candidates: np.ndarray, ridge: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Fit the centralised surrogate and score the candidates: ``(theta, scores, strength)``.

    ``window`` ``(W, d)`` and ``candidates`` ``(M, d)`` are normalised coordinates, ``values``
    ``(W,)`` what was measured at the window's points, ``terms`` ``(T, 3)`` the monomials.
    ``strength`` ``(T,)`` is :func:`_strength` of the monomials. The Rust kernel
    (``uavcov._core.Surrogate.fit``, nalgebra); :func:`_fit_and_score_numpy` is its reference.
    """
    return _core.Surrogate.fit(window, values, terms, candidates, ridge)


def _fit_and_score_robots(
    window: np.ndarray, values: np.ndarray, active: np.ndarray, candidates: np.ndarray, ridge: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Every robot's surrogate at once: ``window`` ``(N, W, 3)``, ``values`` ``(N, W)``,
    ``active`` ``(N, 16)`` bool (each robot's monomials), ``candidates`` ``(N, M, 3)`` ->
    ``theta`` ``(N, 20)``, ``scores`` ``(N, M)``, ``strength`` ``(N, 16)``. Rust kernel;
    :func:`_fit_and_score_robots_numpy` is its reference.
    """
    return _core.Surrogate.fit_robots(window, values, _all_monomials(3), active, candidates, ridge)
