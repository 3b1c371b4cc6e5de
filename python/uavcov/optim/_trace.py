"""What one optimiser run did: :class:`OptimizerTrace`, and how a run's arrays become one."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .._validate import read_only
from ._settings import CAOSettings


@dataclass(frozen=True, eq=False)
class OptimizerTrace:
    """What one optimiser run did, iteration by iteration. Picklable.

    ``K`` is the number of iterations (moves); the run measured ``K + 1`` configurations.

    Attributes
    ----------
    kind : str
        ``"cao"``, ``"per_robot"`` or ``"escape"``.
    trajectory : ndarray, shape (K + 1, N, d)
        The decision variables at every iteration, positions in metres first (``d = 3`` unless
        :func:`cao` was given more per UAV); ``trajectory[0]`` is the start.
    values : ndarray, shape (K + 1,)
        Objective at each configuration, noise-free (what ``measure`` returned).
    measured : ndarray, shape (K + 1,)
        What the optimiser saw: ``values`` plus the simulated measurement noise.
    step_sizes : ndarray, shape (K,)
        ``alpha_k`` used at each iteration, metres.
    n_checked : ndarray, shape (K,), int64
        Candidates checked for feasibility at each iteration (all of them when
        ``settings.check_batch`` is None; see there).
    n_feasible : ndarray, shape (K,), int64
        Feasible candidates among those checked (0 means the team stayed: none was feasible).
    best_positions : ndarray, shape (N, d)
        The configuration with the highest noise-free value (the first one on ties).
    best_value : float
    best_iteration : int
    evaluations : int
        Calls of ``measure`` (``K + 1``).
    settings : CAOSettings
        The settings used, with ``None`` resolved.
    time_measure_s, time_feasibility_s, time_optimizer_s : float
        Seconds spent in ``measure``, in ``feasible``, and in the optimiser's own work (the
        names of :class:`~uavcov.MissionResult`).
    relocations : ndarray, shape (R, 3), int64
        The escapes of the ``"escape"`` optimiser (:class:`~uavcov.EscapeSettings`), one row ``(uav, first, last)`` each: the
        UAV flew from its position at iteration ``first`` to the one at ``last`` through the
        configurations in between (every other UAV holding still); empty for other optimisers.
    """

    kind: str
    trajectory: np.ndarray = field(repr=False)
    values: np.ndarray = field(repr=False)
    measured: np.ndarray = field(repr=False)
    step_sizes: np.ndarray = field(repr=False)
    n_checked: np.ndarray = field(repr=False)
    n_feasible: np.ndarray = field(repr=False)
    best_positions: np.ndarray
    best_value: float
    best_iteration: int
    evaluations: int
    settings: CAOSettings
    time_measure_s: float = field(default=0.0)
    time_feasibility_s: float = field(default=0.0)
    time_optimizer_s: float = field(default=0.0)
    relocations: np.ndarray = field(default_factory=lambda: read_only(np.empty((0, 3), dtype=np.int64)))

    @property
    def n_iterations(self) -> int:
        """``K``, the number of moves."""
        return int(self.trajectory.shape[0] - 1)

    @property
    def final_positions(self) -> np.ndarray:
        """``(N, 3)`` positions after the last iteration."""
        last: np.ndarray = self.trajectory[-1]
        return last

    def best_so_far(self) -> np.ndarray:
        """``(K + 1,)`` running maximum of :attr:`values`."""
        best: np.ndarray = np.maximum.accumulate(self.values)
        return best


def _finish(
    kind: str,
    traj: np.ndarray,
    values: np.ndarray,
    measured: np.ndarray,
    steps: np.ndarray,
    n_checked: np.ndarray,
    n_feasible: np.ndarray,
    settings: CAOSettings,
    t_measure: float,
    t_feasible: float,
    t_total: float,
) -> OptimizerTrace:
    best = int(np.argmax(values))
    return OptimizerTrace(
        kind=kind,
        trajectory=read_only(traj),
        values=read_only(values),
        measured=read_only(measured),
        step_sizes=read_only(steps),
        n_checked=read_only(n_checked),
        n_feasible=read_only(n_feasible),
        best_positions=read_only(traj[best].copy()),
        best_value=float(values[best]),
        best_iteration=best,
        evaluations=int(values.shape[0]),
        settings=settings,
        time_measure_s=t_measure,
        time_feasibility_s=t_feasible,
        time_optimizer_s=max(0.0, t_total - t_measure - t_feasible),
    )
