"""Named presets of CAO's constants: the paper's Table 1, and a plateau of large steps.

Each preset is stated for the paper's sensing range of 25 m; :func:`cao_preset` scales the
first step ``alpha0`` (metres) with the range, so a team with a 100 m sensor takes steps four
times as long. The values were chosen on development seeds (``docs/calibration.md``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import replace
from types import MappingProxyType

from .._validate import as_positive_float
from ..errors import InvalidInputError
from ._settings import CAOSettings

PRESET_RANGE = 25.0
"""The sensing range (metres) the presets' ``alpha0`` is stated for."""

_PAPER = CAOSettings(
    n_regressors=None,
    history=10,
    n_candidates=200,
    alpha0=8.0,
    stability=0.0,
    decay=1.0,
    ridge=1e-3,
    measurement_noise=0.0,
)

CAO_PRESETS: Mapping[str, CAOSettings] = MappingProxyType(
    {
        # The paper's constants (paper-setup.md) without simulated measurement noise, and the
        # step alpha_k = alpha0 / (k + 1): the fastest decay the paper's conditions allow, with
        # the largest alpha0 whose runs converge by 500 iterations.
        "paper": _PAPER,
        # A plateau of large steps, alpha_k = 30 m / (k + 6): slower to settle, more robust to a
        # start far from the optimum (the default of flight plans on real sites).
        "plateau": replace(_PAPER, alpha0=5.0, stability=5.0),
    }
)
"""CAO's constants by name, for a sensing range of ``PRESET_RANGE``."""


def cao_preset(name: str, d_max: float = PRESET_RANGE) -> CAOSettings:
    """The preset ``name`` with its first step scaled to the sensing range ``d_max`` (metres).

    Examples
    --------
    >>> cao_preset("plateau", d_max=100.0).alpha0
    20.0
    """
    if not isinstance(name, str) or name not in CAO_PRESETS:
        raise InvalidInputError(f"CAO preset must be one of {sorted(CAO_PRESETS)}, got {name!r}")
    preset = CAO_PRESETS[name]
    d_max = as_positive_float(d_max, "d_max")
    alpha0 = preset.alpha0 * d_max / PRESET_RANGE
    if not 0.0 < alpha0 < math.inf:  # a subnormal range rounds its first step to 0 m; one near 1.8e308 overflows it
        raise InvalidInputError(f"d_max = {d_max} m gives CAO no first step ({preset.alpha0 / PRESET_RANGE:g} d_max = {alpha0} m)")
    return replace(preset, alpha0=alpha0)
