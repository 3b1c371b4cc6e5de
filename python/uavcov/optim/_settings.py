"""CAO's constants: :class:`CAOSettings`, and the rules a setting can take."""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from .._validate import as_finite_float, as_float_array, as_non_negative_float, as_non_negative_int, as_positive_float, as_positive_int
from ..errors import InvalidInputError, InvalidTypeError
from ._monomials import _n_distinct_monomials

_PERTURBATIONS = ("gaussian", "uniform")


INFEASIBLE_RULES = ("drop", "hold")
"""How centralised CAO treats a candidate in which some UAVs' perturbed positions are inadmissible."""


@dataclass(frozen=True)
class CAOSettings:
    """Constants of CAO. The paper publishes none; the defaults follow ``paper-setup.md``.

    Parameters
    ----------
    n_regressors : int or None, default None
        ``L``, regressors of the centralised surrogate: 1 constant + ``dN`` linear terms (``d = 3``
        coordinates per UAV, more when camera angles are optimised) + the rest random 2nd/3rd-order
        monomials. ``None`` means ``1 + dN + max(10, N)``. Must be at least ``1 + dN``.
    history : int, default 10
        ``T_h``: iteration ``k`` fits the ``L + T_h`` measurements ``l_k ... k - 1`` (eq. 4).
    n_candidates : int, default 200
        ``M``: candidate configurations per iteration, the unperturbed state included.
    alpha0 : float, default 1.5
        Initial perturbation size ``alpha_0`` in metres (standard deviation per coordinate).
    stability : float, default 50.0
        ``A`` in ``alpha_k = alpha_0 ((1 + A) / (k + 1 + A)) ** decay``; larger keeps steps large
        for longer.
    decay : float, default 0.602
        Exponent of the step decay. ``0.5 < decay <= 1`` satisfies the paper's conditions; 0 gives
        a constant step.
    ridge : float, default 1e-3
        Ridge penalty on every coefficient but the constant, relative to the mean squared
        residual: the fit minimises ``mean(residual^2) + ridge * |theta[1:]|^2``.
    measurement_noise : float, default 0.0
        Standard deviation of Gaussian noise added to each measurement (coverage units), to
        exercise CAO's filtering. The trace keeps the noise-free values too.
    keep_fraction : float, default 0.5
        Share of the nonlinear monomials kept (the strongest) when the others are redrawn, in
        ``[0, 1]``.
    perturbation : {"gaussian", "uniform"}, default "gaussian"
        Law of ``zeta``: standard normal, or uniform on ``[-sqrt(3), sqrt(3)]`` (also unit
        variance, bounded steps).
    robot_regressors : int or None, default None
        Regressors of each per-robot estimator (:func:`per_robot_cao`), on 3 coordinates:
        ``None`` means ``1 + 3 + 6 = 10``; at most ``1 + 3 + 16 = 20`` (every distinct 2nd- and
        3rd-order monomial of three variables).
    check_batch : int or None, default 16
        Candidates are checked for feasibility best-rated first, ``check_batch`` at a time (the
        batch doubling each round), until the best feasible one is known; usually the first
        batch settles it, which spares the clearance queries of the other ``M - 16``. ``None``
        checks all ``M`` at once. The choice is the same either way (feasibility is judged per
        candidate); only ``OptimizerTrace.n_feasible`` counts fewer.
    infeasible : {"drop", "hold"}, default "drop"
        What centralised CAO does with a candidate in which some UAV's perturbed position is
        inadmissible on its own (out of the flight band or the region, in the ground, a move
        through it). ``"drop"``, the paper's eq. 6 as written: the whole candidate configuration
        is neglected. ``"hold"``: those UAVs keep their current positions within it (their
        perturbation is zeroed before the surrogate rates the candidate) and the others still
        move; the repaired candidate must then pass the team check (separation). ``feasible``
        is called once per UAV on one-UAV slices ``(1, d)`` and ``(M, 1, d)`` to judge the
        positions alone.
    """

    n_regressors: int | None = None
    history: int = 10
    n_candidates: int = 200
    alpha0: float = 1.5
    stability: float = 50.0
    decay: float = 0.602
    ridge: float = 1e-3
    measurement_noise: float = 0.0
    keep_fraction: float = 0.5
    perturbation: str = "gaussian"
    robot_regressors: int | None = None
    check_batch: int | None = 16
    infeasible: str = "drop"

    def __post_init__(self) -> None:
        def put(name: str, value: Any) -> None:
            object.__setattr__(self, name, value)

        if self.n_regressors is not None:
            put("n_regressors", as_positive_int(self.n_regressors, "n_regressors"))
        if self.robot_regressors is not None:
            value = as_positive_int(self.robot_regressors, "robot_regressors")
            if not 4 <= value <= 4 + _n_distinct_monomials(3):
                raise InvalidInputError(
                    f"robot_regressors must be in [4, {4 + _n_distinct_monomials(3)}] "
                    f"(constant, 3 linear terms, up to 16 distinct monomials), got {value}"
                )
            put("robot_regressors", value)
        if self.check_batch is not None:
            put("check_batch", as_positive_int(self.check_batch, "check_batch"))
        put("history", as_non_negative_int(self.history, "history"))
        put("n_candidates", as_positive_int(self.n_candidates, "n_candidates"))
        put("alpha0", as_positive_float(self.alpha0, "alpha0"))
        put("stability", as_non_negative_float(self.stability, "stability"))
        put("decay", as_non_negative_float(self.decay, "decay"))
        put("ridge", as_positive_float(self.ridge, "ridge"))
        put("measurement_noise", as_non_negative_float(self.measurement_noise, "measurement_noise"))
        keep = as_non_negative_float(self.keep_fraction, "keep_fraction")
        if keep > 1.0:
            raise InvalidInputError(f"keep_fraction must be in [0, 1], got {keep}")
        put("keep_fraction", keep)
        if not isinstance(self.perturbation, str):
            raise InvalidTypeError(f"perturbation must be a string, got {type(self.perturbation).__name__}")
        if self.perturbation not in _PERTURBATIONS:
            raise InvalidInputError(f"perturbation must be one of {_PERTURBATIONS}, got {self.perturbation!r}")
        if not isinstance(self.infeasible, str) or self.infeasible not in INFEASIBLE_RULES:
            raise InvalidInputError(f"infeasible must be one of {INFEASIBLE_RULES}, got {self.infeasible!r}")

    def regressors_for(self, n_uavs: int, n_coordinates: int = 3) -> int:
        """Return ``L`` for a team of ``n_uavs``, checking it against ``1 + dN`` and the monomial count.

        ``n_coordinates`` is ``d``, the decision variables per UAV: 3 for a position, more when
        a camera's heading or pitch is optimised too (:class:`uavcov.engine.Gimbal`).
        """
        n_uavs = as_positive_int(n_uavs, "number of UAVs")
        d = as_positive_int(n_coordinates, "coordinates per UAV")
        dim = d * n_uavs
        value = 1 + dim + max(10, n_uavs) if self.n_regressors is None else self.n_regressors
        if value < 1 + dim:
            raise InvalidInputError(
                f"n_regressors must be at least 1 + {d}N = {1 + dim} for N = {n_uavs} (the constant and every linear term), got {value}"
            )
        if value - 1 - dim > _n_distinct_monomials(dim):
            raise InvalidInputError(
                f"n_regressors = {value} asks for more distinct 2nd/3rd-order monomials than "
                f"{dim} coordinates have ({_n_distinct_monomials(dim)})"
            )
        return value

    def robot_regressors_value(self) -> int:
        """Return the regressor count of each per-robot estimator."""
        return 10 if self.robot_regressors is None else self.robot_regressors

    def step_size(self, k: int | np.ndarray) -> float | np.ndarray:
        """``alpha_k`` in metres for iteration ``k`` (0-based; ``alpha_0`` at ``k = 0``).

        Examples
        --------
        >>> s = CAOSettings()
        >>> s.step_size(0), round(s.step_size(100), 3)
        (1.5, 0.78)
        """
        iteration: np.ndarray
        if isinstance(k, (np.ndarray, list, tuple)):
            iteration = as_float_array(k, "k").reshape(np.shape(k))  # a 0-d array stays 0-d
        else:
            iteration = np.asarray(as_finite_float(k, "k"))
        if (iteration < 0.0).any():
            raise InvalidInputError(f"k must be >= 0 (0-based iterations), got {np.min(iteration)}")
        ratio = (1.0 + self.stability) / (iteration + 1.0 + self.stability)
        result = self.alpha0 * ratio**self.decay
        return float(result) if np.ndim(result) == 0 else result

    def resolved(self, n_uavs: int, n_coordinates: int = 3) -> CAOSettings:
        """These settings with every ``None`` replaced by the value used for ``n_uavs`` UAVs."""
        return replace(
            self,
            n_regressors=self.regressors_for(n_uavs, n_coordinates),
            robot_regressors=self.robot_regressors_value(),
        )
