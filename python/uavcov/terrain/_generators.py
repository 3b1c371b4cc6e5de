"""Scenario generators: the random surfaces an experiment draws, one per seed.

:class:`HillsGenerator` is the paper's random terrain (a mixture of Gaussians on a square) and
:class:`BuildingsGenerator` its realistic scene (boxes on flat ground) with the simplified,
erroneous map a team is given of it. Each is a frozen, picklable value: ``make(seed)`` draws the
true surface of scenario ``seed`` with ``rng=seed``, so the same seed gives the same surface for
every team size, start and experiment that shares the generator's settings.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from .._validate import as_cell_count, as_non_negative_float, as_non_negative_int, as_positive_float, as_positive_int, as_range
from ..engine import Terrain
from ..errors import InvalidInputError
from ._buildings import buildings_terrain, random_buildings
from ._hills import gaussian_hills, random_gaussian_mixture
from ._prior import buildings_prior


@dataclass(frozen=True)
class HillsGenerator:
    """The paper's random terrain: ``n_hills`` Gaussians on a ``size`` square (metres).

    ``heights`` is the range peak heights are drawn uniformly from, ``sigma`` the common
    standard deviation; ``spacing`` is the grid step, which is also the coverage discretisation
    (one target per grid node, weighted by the area it stands for).
    """

    size: float = 100.0
    spacing: float = 1.0
    n_hills: int = 7
    heights: tuple[float, float] = (5.0, 25.0)
    sigma: float = 10.0

    kind: ClassVar[str] = "HillsTerrain"
    """The family's name in a settings hash: fixed, so the run ids of published sweeps stay theirs."""

    def __post_init__(self) -> None:
        object.__setattr__(self, "size", as_positive_float(self.size, "size"))
        object.__setattr__(self, "spacing", as_positive_float(self.spacing, "spacing"))
        object.__setattr__(self, "n_hills", as_positive_int(self.n_hills, "n_hills"))
        low, high = as_range(self.heights, "heights")
        if low < 0.0:
            raise InvalidInputError(f"heights must be >= 0, got {self.heights}")
        object.__setattr__(self, "heights", (low, high))
        object.__setattr__(self, "sigma", as_positive_float(self.sigma, "sigma"))
        # Every check of make(), here: a sweep's bad setting is refused when it is read, not at its first run.
        as_cell_count(self.size, self.spacing, "size")
        random_gaussian_mixture(size=self.size, n_hills=self.n_hills, heights=self.heights, sigma=self.sigma, rng=0)

    def make(self, seed: int) -> Terrain:
        """The terrain of scenario ``seed`` (an integer >= 0, as every scenario's)."""
        seed = as_non_negative_int(seed, "seed")  # not any rng: None would draw a new terrain each call
        return gaussian_hills(size=self.size, spacing=self.spacing, n_hills=self.n_hills, heights=self.heights, sigma=self.sigma, rng=seed)


@dataclass(frozen=True)
class BuildingsGenerator:
    """The paper's realistic scene: ``n_buildings`` boxes on a ``size`` square of flat ground.

    The true scene is meshed every ``spacing`` metres; the simplified map the CVT runs on is
    ``uavcov.terrain._prior.buildings_prior`` (boxes with position, size and height errors, meshed
    every ``map_spacing`` metres).
    """

    size: float = 24.0
    spacing: float = 0.5
    n_buildings: int = 5
    footprint: tuple[float, float] = (3.0, 7.0)
    heights: tuple[float, float] = (3.0, 10.0)
    gap: float = 2.0
    map_spacing: float = 1.0
    position_error: float = 0.5
    size_error: float = 0.5
    height_error: float = 1.0

    kind: ClassVar[str] = "BuildingsTerrain"
    """The family's name in a settings hash: fixed, so the run ids of published sweeps stay theirs."""

    def __post_init__(self) -> None:
        # Checked, not converted: the values as given are what the settings hash (run ids) reads.
        size = as_positive_float(self.size, "size")
        as_cell_count(size, as_positive_float(self.spacing, "spacing"), "size")
        try:
            as_cell_count(size, as_positive_float(self.map_spacing, "map_spacing"), "size")
        except InvalidInputError as exc:
            raise InvalidInputError(f"map_spacing: {exc}") from exc
        as_non_negative_int(self.n_buildings, "n_buildings")
        as_range(self.footprint, "footprint", positive=True)
        as_range(self.heights, "heights", positive=True)
        for name in ("gap", "position_error", "size_error", "height_error"):
            as_non_negative_float(getattr(self, name), name)

    def boxes(self, seed: int) -> tuple[Any, ...]:
        """The buildings of scenario ``seed``."""
        return random_buildings(
            size=self.size,
            n_buildings=self.n_buildings,
            footprint=self.footprint,
            heights=self.heights,
            gap=self.gap,
            step=self.spacing,
            rng=seed,
        )

    def make(self, seed: int) -> Terrain:
        """The true scene of scenario ``seed``."""
        return buildings_terrain(self.boxes(seed), size=self.size, spacing=self.spacing)

    def simplified_map(self, seed: int) -> Terrain:
        """The coarse, erroneous map of scenario ``seed`` (the surface the CVT runs on)."""
        seed = as_non_negative_int(seed, "seed")  # it seeds the map's errors too: [seed, 1]
        return buildings_prior(
            self.boxes(seed),
            size=self.size,
            kind="boxes",
            spacing=self.map_spacing,
            position_error=self.position_error,
            size_error=self.size_error,
            height_error=self.height_error,
            rng=np.random.default_rng([seed, 1]),
        )


TerrainGenerator = HillsGenerator | BuildingsGenerator
"""A terrain generator: anything with ``make(seed) -> Terrain``."""
