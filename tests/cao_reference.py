"""numpy references of CAO's Rust surrogate kernels (``uavcov.optim._surrogate``): the same maths,
LAPACK's solve, which the tests hold the kernels to. Test code only: the library never calls it.
"""

from __future__ import annotations

import contextlib
import functools
from typing import Any

import numpy as np


def _every_monomial3(u: np.ndarray) -> np.ndarray:
    """All 16 monomials of degree 2 and 3 of ``u`` ``(..., 3)``, in ``_all_monomials(3)`` order."""
    x, y, z = u[..., 0], u[..., 1], u[..., 2]
    xx, yy, zz, xy, xz, yz = x * x, y * y, z * z, x * y, x * z, y * z
    cols = [xx, xx * x, xy * x, xz * x, xy, xy * y, xy * z, xz, xz * z,
            yy, yy * y, yz * y, yz, yz * z, zz, zz * z]  # fmt: skip
    return np.stack(cols, axis=-1)


def _design(u: np.ndarray, terms: np.ndarray) -> np.ndarray:
    """Regressor matrix ``(n, 1 + dim + n_terms)`` of points ``u`` of shape ``(n, dim)``."""
    ones = np.ones((*u.shape[:-1], 1))
    if terms.shape[0] == 0:
        return np.concatenate([ones, u], axis=-1)
    augmented = np.concatenate([u, ones], axis=-1)
    mono = augmented[..., terms[:, 0]] * augmented[..., terms[:, 1]] * augmented[..., terms[:, 2]]
    return np.concatenate([ones, u, mono], axis=-1)


def _robot_design(u: np.ndarray, selected: np.ndarray) -> np.ndarray:
    """Per-robot regressors ``(N, n, 20)`` of ``u`` ``(N, n, 3)``: constant, linear, 16 monomials.

    ``selected`` ``(N, 16)`` bool marks each robot's active monomials; the other columns are
    zero. A zero column changes nothing in a ridge fit (its coefficient is exactly 0), so this
    is the fit on the active columns only, without a per-robot gather.
    """
    ones = np.ones((*u.shape[:-1], 1))
    mono = _every_monomial3(u) * selected[:, None, :]
    return np.concatenate([ones, u, mono], axis=-1)


def _ridge(phi: np.ndarray, y: np.ndarray, ridge: float) -> np.ndarray:
    """Coefficients minimising ``mean((phi theta - y)^2) + ridge |theta[1:]|^2``.

    ``phi`` is ``(..., W, L)`` and ``y`` ``(..., W)``; column 0 is the constant, left unpenalised.
    ``y`` is centred first so the solve only carries the variations (better conditioned).
    """
    n_samples = phi.shape[-2]
    if n_samples == 0:  # nothing measured yet: a flat surrogate (every candidate ties)
        return np.zeros(phi.shape[:-2] + phi.shape[-1:])
    mean = y.mean(axis=-1, keepdims=True)
    yc = y - mean
    gram = np.swapaxes(phi, -1, -2) @ phi
    rhs = np.swapaxes(phi, -1, -2) @ yc[..., None]
    penalty = np.full(phi.shape[-1], ridge * n_samples)
    penalty[0] = 0.0
    gram = gram + np.diag(penalty)
    # The constant column is all ones and every other column is penalised, so the system is
    # positive definite; the pseudo-inverse only guards against round-off on extreme inputs.
    try:
        theta = np.linalg.solve(gram, rhs)[..., 0]
    except np.linalg.LinAlgError:
        theta = (np.linalg.pinv(gram) @ rhs)[..., 0]
    theta[..., 0] += mean[..., 0]
    return theta


def _strength(phi: np.ndarray, theta: np.ndarray, first: int) -> np.ndarray:
    """Contribution of nonlinear regressors ``first:``: ``|theta_j| * rms(phi[:, j])``."""
    rms = np.sqrt(np.mean(phi[..., first:] ** 2, axis=-2))
    strength: np.ndarray = np.abs(theta[..., first:]) * rms
    return strength


@functools.lru_cache(maxsize=1)
def _blas_controller() -> Any:
    try:
        from threadpoolctl import ThreadpoolController
    except ImportError:  # declared as a dependency; without it CAO is only slower
        return None
    return ThreadpoolController()


def _one_blas_thread() -> contextlib.AbstractContextManager[Any]:
    """Run CAO's small matrix products on one BLAS thread.

    The fit works on matrices of about 100 x 100: a multi-threaded BLAS spends longer waking
    its threads than computing, and far longer when the cores are busy with the coverage
    engine or other runs (measured: a 91 x 81 Gram matrix took 0.29 ms with 2 threads on a
    loaded 2-core machine, 0.05 ms with one). Only CAO's own work is limited, never ``measure``.
    """
    controller = _blas_controller()
    if controller is None:
        return contextlib.nullcontext()
    limited: contextlib.AbstractContextManager[Any] = controller.limit(limits=1, user_api="blas")
    return limited


def _fit_and_score_numpy(
    window: np.ndarray, values: np.ndarray, terms: np.ndarray, candidates: np.ndarray, ridge: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """numpy reference of :func:`_fit_and_score` (same maths, LAPACK's solve)."""
    dim = window.shape[-1]
    with _one_blas_thread():
        phi = _design(window, terms)
        theta = _ridge(phi, values, ridge)
        scores = _design(candidates, terms) @ theta
    strength = _strength(phi, theta, 1 + dim) if window.shape[0] else np.zeros(terms.shape[0])
    return theta, scores, strength


def _fit_and_score_robots_numpy(
    window: np.ndarray, values: np.ndarray, active: np.ndarray, candidates: np.ndarray, ridge: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """numpy reference of :func:`_fit_and_score_robots`."""
    with _one_blas_thread():
        phi = _robot_design(window, active)  # (N, W, 20)
        theta = _ridge(phi, values, ridge)  # (N, 20)
        scores = (  # theta . phi(candidates) without building phi for the M candidates
            theta[:, :1]
            + np.einsum("nmk,nk->nm", candidates, theta[:, 1:4])
            + np.einsum("nmj,nj->nm", _every_monomial3(candidates), theta[:, 4:] * active)
        )
    strength = _strength(phi, theta, 4) if window.shape[1] else np.zeros(active.shape)
    return theta, scores, strength
