"""The interface every optimiser of uavcov follows, and the callables it takes."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Protocol

import numpy as np

from ._settings import CAOSettings
from ._trace import OptimizerTrace

FeasibleFn = Callable[[np.ndarray, np.ndarray], np.ndarray]


StopRule = Callable[[np.ndarray], bool]
"""``stop(measured)``: called after each measurement with the values measured so far ``(k + 1,)``."""


class Optimizer(Protocol):
    """The interface every optimiser of uavcov follows (see :func:`cao` for the arguments)."""

    def __call__(
        self,
        measure: Callable[[np.ndarray], Any],
        x0: Any,
        *,
        feasible: FeasibleFn | None,
        iterations: int,
        settings: CAOSettings = ...,
        rng: Any = None,
    ) -> OptimizerTrace: ...
