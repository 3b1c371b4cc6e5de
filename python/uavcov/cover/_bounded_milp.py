"""scipy's HiGHS run in a child process that is killed at a hard deadline.

HiGHS checks its clock between steps, not inside every one: on Table 1's terrains (1,323
candidates, 10,092 target rows, 1.5 million non-zeros) its presolve took 21.8 s of a 6.2 s limit
and a round of cut separation ran 6 s past a 20 s limit; before this fix two 60 s solves took
about 504 s. A time limit that must hold therefore cannot be left to the solver: the program goes
to a child interpreter (``python -c``, fed by a pipe: no copy of the caller's Rust and BLAS
threads, and no re-import of the caller's script as ``multiprocessing``'s spawn would do), HiGHS
gets a share of the time that remains, and the caller waits until the deadline plus a grace
period, then kills the child and goes on without the solver's answer (the caller's incumbent and
bounds stand, each certified on its own).
"""

from __future__ import annotations

import pickle
import subprocess
import sys
import time
from dataclasses import dataclass
from typing import Any

import numpy as np

# HiGHS gets this share of the time left (its own overshoot, when it checks its clock, is then
# mostly absorbed before the deadline); the child is killed this many seconds past the deadline.
_SOLVER_SHARE = 0.85
_GRACE_S = 1.0

# The child: scipy's milp on the pickled keyword arguments from stdin, the answer pickled to stdout.
_CHILD = """
import pickle, sys
import numpy as np
from scipy.optimize import milp
result = milp(**pickle.load(sys.stdin.buffer))
bound = getattr(result, "mip_dual_bound", None)
answer = (
    None if result.x is None else np.asarray(result.x, dtype=np.float64),
    float("nan") if bound is None else float(bound),
    int(result.status),
    int(getattr(result, "mip_node_count", 0) or 0),
)
sys.stdout.buffer.write(pickle.dumps(answer, protocol=pickle.HIGHEST_PROTOCOL))
"""


@dataclass(frozen=True)
class MilpOutcome:
    """What the solver reported, or that it was killed.

    Attributes
    ----------
    x : ndarray or None
        The solver's incumbent (``None`` when it found none or was killed).
    dual_bound : float
        The solver's proven bound on its (minimised) objective, ``nan`` when it gave none.
    status : int
        scipy's ``milp`` status (0 optimal, 1 time or node limit, ...); -1 when the child was
        killed at the deadline or died without an answer.
    n_nodes : int
        Branch-and-bound nodes explored (0 when killed).
    wall_s : float
        Wall time from starting the child to its answer or its kill, seconds.
    """

    x: np.ndarray | None
    dual_bound: float
    status: int
    n_nodes: int
    wall_s: float

    @property
    def killed(self) -> bool:
        """The child was killed at the deadline (or died) without an answer."""
        return self.status == -1


def bounded_milp(arguments: dict[str, Any], deadline: float) -> MilpOutcome:
    """scipy's ``milp(**arguments)`` in a child process that cannot outlive ``deadline`` by more than a grace period.

    Parameters
    ----------
    arguments : dict
        ``milp``'s keyword arguments (picklable); ``options["time_limit"]`` is replaced by a
        share of the time left before ``deadline``.
    deadline : float
        ``time.perf_counter()`` value by which the answer is due; the child is killed
        ``_GRACE_S`` seconds after it.

    Returns
    -------
    MilpOutcome
    """
    started = time.perf_counter()
    left = deadline - started
    if left <= 0.0:
        return MilpOutcome(None, float("nan"), -1, 0, 0.0)
    options = dict(arguments.get("options") or {})
    options["time_limit"] = max(_SOLVER_SHARE * left, 1e-3)
    payload = pickle.dumps({**arguments, "options": options}, protocol=pickle.HIGHEST_PROTOCOL)
    child = subprocess.Popen([sys.executable, "-c", _CHILD], stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)
    output = b""
    try:
        output, _ = child.communicate(payload, timeout=max(deadline + _GRACE_S - time.perf_counter(), 1e-3))
    except subprocess.TimeoutExpired:
        pass
    finally:  # past the deadline, or the caller interrupted: the child never outlives this call
        if child.poll() is None:
            child.kill()
            child.communicate()
    wall = time.perf_counter() - started
    if child.returncode != 0 or not output:  # killed, or died (out of memory, a crash): no solver result
        return MilpOutcome(None, float("nan"), -1, 0, wall)
    x, bound, status, nodes = pickle.loads(output)
    return MilpOutcome(x, bound, status, nodes, wall)
