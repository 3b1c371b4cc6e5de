"""Gaussian hills, the paper's 40 test terrains: a mixture of Gaussians on a square, sampled on an
elevation grid. :func:`gaussian_hills` draws one; ``GaussianMixture`` is the underlying
analytic height function (exact heights and gradients anywhere, for checks and priors).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validate import (
    MAX_HILLS,
    as_cell_count,
    as_count,
    as_float_array,
    as_generator,
    as_positive_float,
    as_range,
)
from ..engine import Terrain
from ..errors import InvalidInputError


@dataclass(frozen=True, eq=False)
class GaussianMixture:
    """A height field that is a sum of isotropic Gaussian bumps over flat ground at z = 0.

    ``z(x, y) = sum_k heights[k] * exp(-|(x, y) - centres[k]|^2 / (2 sigma^2))``

    Attributes
    ----------
    centres : ndarray, shape (k, 2)
        Bump centres (m).
    heights : ndarray, shape (k,)
        Peak height of each bump alone (m); overlapping bumps add up.
    sigma : float
        The common standard deviation (m).
    """

    centres: np.ndarray
    heights: np.ndarray
    sigma: float

    def __post_init__(self) -> None:
        centres = as_float_array(self.centres, "centres")
        heights = as_float_array(self.heights, "heights")
        if centres.size == 0 and heights.size == 0:  # no hills: flat ground
            centres, heights = np.zeros((0, 2)), np.zeros(0)
        if centres.ndim != 2 or centres.shape[1] != 2:
            raise InvalidInputError(f"centres must have shape (k, 2), got {centres.shape}")
        if heights.ndim != 1 or heights.shape[0] != centres.shape[0]:
            raise InvalidInputError(f"heights must have shape ({centres.shape[0]},), got {heights.shape}")
        sigma = as_positive_float(self.sigma, "sigma")
        if not 0.0 < sigma * sigma < math.inf:  # the bumps' exponent divides by sigma**2
            raise InvalidInputError(f"sigma must have a finite, non-zero square, got {sigma}")
        centres.setflags(write=False)
        heights.setflags(write=False)
        object.__setattr__(self, "centres", centres)
        object.__setattr__(self, "heights", heights)
        object.__setattr__(self, "sigma", sigma)

    def height(self, xy: Any) -> np.ndarray:
        """Heights ``(n,)`` (m) at points ``xy`` of shape ``(n, 2)`` (or ``(2,)``)."""
        points = as_float_array(xy, "xy")
        if points.ndim == 1 and points.shape[0] == 2:
            points = points.reshape(1, 2)
        if points.ndim != 2 or points.shape[1] != 2:
            raise InvalidInputError(f"xy must have shape (n, 2), got {points.shape}")
        return self._evaluate(points[:, 0], points[:, 1])

    def _evaluate(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        z = np.zeros(np.broadcast(x, y).shape)
        scale = -0.5 / self.sigma**2
        for (cx, cy), h in zip(self.centres, self.heights, strict=True):
            z += h * np.exp(scale * ((x - cx) ** 2 + (y - cy) ** 2))
        return z

    def grid(self, size: float, spacing: float) -> np.ndarray:
        """Heights ``(n, n)`` on the square ``[0, size]^2`` every ``spacing`` m.

        Entry ``[i, j]`` is the height at ``x = j * spacing``, ``y = i * spacing`` (the layout of
        :meth:`Terrain.from_grid`). ``size`` must be a multiple of ``spacing``.
        """
        size = as_positive_float(size, "size")
        spacing = as_positive_float(spacing, "spacing")
        cells = as_cell_count(size, spacing, "size")
        coords = np.arange(cells + 1) * spacing
        x, y = np.meshgrid(coords, coords)
        return self._evaluate(x, y)

    def terrain(self, size: float, spacing: float) -> Terrain:
        """The mixture sampled on ``[0, size]^2`` as a grid :class:`Terrain`."""
        spacing = as_positive_float(spacing, "spacing")
        return Terrain.from_grid(self.grid(size, spacing), spacing, origin=(0.0, 0.0))


def random_gaussian_mixture(
    size: float = 100.0,
    n_hills: int = 7,
    heights: Any = (5.0, 25.0),
    sigma: float = 10.0,
    rng: Any = None,
) -> GaussianMixture:
    """Draw the paper's terrain model: ``n_hills`` Gaussians with random centres and heights.

    Parameters
    ----------
    size : float
        Side of the square ``[0, size]^2`` the centres are drawn in, uniformly (m).
    n_hills : int
        Number of Gaussians (the paper: 7). 0 gives flat ground.
    heights : (float, float) or float
        Peak heights are uniform in this range (m). The paper says only "varying heights";
        [5, 25] m is the starting value of the calibration.
    sigma : float
        The common standard deviation (m); the paper's "fixed variance" is ``sigma**2``.
    rng : None, int or numpy.random.Generator
        Seed or generator. The centres are drawn first (``(n_hills, 2)`` uniforms), then the
        heights (``n_hills`` uniforms), so a seed gives the same hills at every grid spacing.
    """
    size = as_positive_float(size, "size")
    n_hills = as_count(n_hills, "n_hills", MAX_HILLS, minimum=0)
    low, high = as_range(heights, "heights")
    sigma = as_positive_float(sigma, "sigma")
    generator = as_generator(rng)
    centres = generator.uniform(0.0, size, size=(n_hills, 2))
    peak = generator.uniform(low, high, size=n_hills)
    return GaussianMixture(centres=centres, heights=peak, sigma=sigma)


def gaussian_hills(
    size: float = 100.0,
    spacing: float = 1.0,
    n_hills: int = 7,
    heights: Any = (5.0, 25.0),
    sigma: float = 10.0,
    rng: Any = None,
) -> Terrain:
    """The paper's test terrain: a mixture of Gaussians on ``[0, size]^2`` as a grid Terrain.

    Parameters
    ----------
    size : float
        Side of the square (m); default 100 m as in the paper.
    spacing : float
        Grid spacing (m); ``size`` must be a multiple of it. 1 m gives 101 x 101 vertices.
    n_hills, heights, sigma, rng
        See ``random_gaussian_mixture`` (defaults: 7 hills, heights uniform in [5, 25] m,
        sigma = 10 m). These are starting values to calibrate, not the paper's (unpublished) ones.

    Returns
    -------
    Terrain
        Vertex ``(i, j)`` at ``(j * spacing, i * spacing)``, height from the mixture. Use
        ``random_gaussian_mixture`` with the same ``rng`` for the analytic height function.

    Examples
    --------
    >>> import numpy as np, uavcov
    >>> hills = uavcov.gaussian_hills(rng=0)
    >>> hills
    Terrain(grid 101x101, 10201 vertices, 20000 faces, area 11341.0 m^2)
    >>> exact = uavcov.terrain._hills.random_gaussian_mixture(rng=0)  # the same hills, as a function
    >>> bool(np.isclose(exact.height([[50.0, 50.0]])[0], hills.ground_height([[50.0, 50.0]])[0]))
    True
    """
    mixture = random_gaussian_mixture(size=size, n_hills=n_hills, heights=heights, sigma=sigma, rng=rng)
    return mixture.terrain(size, spacing)
