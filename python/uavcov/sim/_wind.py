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

__all__ = ["DrydenGusts", "dryden_scales"]

_FEET = 3.281  # feet per metre: MIL-F-8785C states its scale lengths in feet
_AIRSPEED = 1.0  # m/s through the turbulence, RotorPy's choice for a hovering multirotor


def dryden_scales(altitude: float) -> np.ndarray:
    """``(3,)`` turbulence scale lengths (x, y, z), metres, at ``altitude`` metres (MIL-F-8785C
    below 1000 ft, RotorPy's formula): ``L_z = h``, ``L_x = L_y = h / (0.177 + 0.000823 h)^1.2`` (h in feet)."""
    h_ft = _FEET * max(float(altitude), 0.1)
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
    rng : numpy.random.Generator
        Draws the white noise; the gusts start from a draw of their stationary distribution.
    """

    def __init__(self, mean: Any, sigma: Any, dt: float, altitude: float, rng: np.random.Generator) -> None:
        self.mean = np.asarray(mean, dtype=np.float64)
        self.sigma = np.asarray(sigma, dtype=np.float64)
        self.decay = np.exp(-_AIRSPEED * dt / dryden_scales(altitude))
        self.innovation = self.sigma * np.sqrt(1.0 - self.decay**2)
        self.rng = rng
        self.gust = self.sigma * rng.standard_normal(3)

    def update(self, t: float, position: np.ndarray) -> np.ndarray:
        """The wind now, m/s (world frame); advances the gusts by one period."""
        wind = self.mean + self.gust
        self.gust = self.decay * self.gust + self.innovation * self.rng.standard_normal(3)
        return wind
