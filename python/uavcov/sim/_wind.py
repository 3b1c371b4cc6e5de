"""Dryden gusts on top of a mean wind, drawn from the mission's generator (``rng=``).

RotorPy's wind models are called once per control period through ``update(t, position)``; its
Dryden model (``rotorpy.wind.dryden_winds.DrydenGust``) cannot serve a reproducible mission: its
module imports torch unconditionally (a multi-gigabyte install the ``sim`` extra does not need)
and it draws its white noise from numpy's global generator, which no ``rng=`` can seed. This
class keeps RotorPy's interface and its choice of turbulence scales (MIL-F-8785C low-altitude
lengths from the operating altitude, airspeed through the turbulence 1 m/s) and samples the
Dryden longitudinal spectrum ``Phi(w) = sigma^2 (2 L / pi V) / (1 + (L w / V)^2)`` exactly on
every axis: a first-order Gauss-Markov process with correlation time ``L / V``, whose exact
discretisation keeps the stationary standard deviation at ``sigma`` for any period.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .._validate import as_finite_float, as_float_array, as_generator, as_non_negative_float, as_positive_float
from ..errors import InvalidInputError

__all__ = ["DrydenGusts", "dryden_scales"]

_FEET = 3.281  # feet per metre: MIL-F-8785C states its scale lengths in feet
_AIRSPEED = 1.0  # m/s through the turbulence, RotorPy's choice for a hovering multirotor
# MIL-F-8785C's low-altitude model holds below 1000 ft; far above it the formula overflows.
_MAX_ALTITUDE = 1e5  # metres
_MAX_WIND = 1e3  # m/s: beyond any vehicle's thrust by far; what a typo in units looks like


def dryden_scales(altitude: float) -> np.ndarray:
    """``(3,)`` turbulence scale lengths (x, y, z), metres, at ``altitude`` metres (MIL-F-8785C
    below 1000 ft, RotorPy's formula): ``L_z = h``, ``L_x = L_y = h / (0.177 + 0.000823 h)^1.2`` (h in feet)."""
    altitude = as_finite_float(altitude, "altitude")
    if not altitude <= _MAX_ALTITUDE:
        raise InvalidInputError(f"altitude must be at most {_MAX_ALTITUDE:g} m, got {altitude:g}")
    h_ft = _FEET * max(altitude, 0.1)
    horizontal = h_ft / (0.177 + 0.000823 * h_ft) ** 1.2
    return np.array([horizontal, horizontal, h_ft]) / _FEET


class DrydenGusts:
    """One vehicle's wind: a constant mean plus Dryden gusts, RotorPy's wind interface.

    Parameters
    ----------
    mean : (3,) array_like
        Mean wind, m/s, world frame.
    sigma : (3,) array_like
        Gusts' standard deviation on each axis, m/s.
    dt : float
        Seconds between calls of :meth:`update` (the control period).
    altitude : float
        Operating altitude, metres (sets the scale lengths, :func:`dryden_scales`).
    rng : None, int or numpy.random.Generator
        Draws the white noise; the gusts start from a draw of their stationary distribution.

    Raises
    ------
    InvalidInputError
        A wind or deviation not three finite numbers within 1000 m/s, a negative deviation, a
        period not positive, an altitude beyond 1e5 m.
    """

    def __init__(self, mean: Any, sigma: Any, dt: float, altitude: float, rng: Any) -> None:
        self.mean = _wind_vector(mean, "mean")
        self.sigma = _wind_vector(sigma, "sigma")
        if (self.sigma < 0.0).any():
            raise InvalidInputError(f"sigma must be non-negative, got {self.sigma.tolist()}")
        dt = as_positive_float(dt, "dt")
        generator = as_generator(rng)
        self.decay = np.exp(-_AIRSPEED * dt / dryden_scales(altitude))
        self.innovation = self.sigma * np.sqrt(1.0 - self.decay**2)
        self.rng = generator
        self.gust = self.sigma * generator.standard_normal(3)
        # A clock past this cannot tell one period from the next in float64: such a time is a
        # unit mistake, not a flight.
        self._latest_time = dt / np.finfo(np.float64).eps

    def update(self, t: float, position: np.ndarray) -> np.ndarray:
        """The wind now, m/s (world frame); advances the gusts by one period.

        Raises
        ------
        InvalidInputError
            ``t`` negative, not finite or too large for the period to advance it (s);
            ``position`` not three finite numbers.
        """
        t = as_non_negative_float(t, "t")
        if t > self._latest_time:
            raise InvalidInputError(
                f"t must be at most {self._latest_time:g} s (beyond it one period does not advance the clock), got {t:g}"
            )
        point = as_float_array(position, "position", ndim=1)
        if point.shape != (3,):
            raise InvalidInputError(f"position must have 3 components (m), got shape {point.shape}")
        wind: np.ndarray = self.mean + self.gust
        self.gust = self.decay * self.gust + self.innovation * self.rng.standard_normal(3)
        return wind


def _wind_vector(value: Any, name: str) -> np.ndarray:
    vector = as_float_array(value, name, ndim=1)
    if vector.shape != (3,):
        raise InvalidInputError(f"{name} must have 3 components (m/s), got shape {vector.shape}")
    if not (np.abs(vector) <= _MAX_WIND).all():
        raise InvalidInputError(f"{name} must be within {_MAX_WIND:g} m/s on each axis, got {vector.tolist()}")
    return vector
