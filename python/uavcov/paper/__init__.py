"""The paper as data, its reproduction, its reports and claims (Renzaglia et al., section V)."""

from __future__ import annotations

from ._claims import PUBLISHED_GAIN, speed
from ._data import (
    ABLATIONS_BY_NAME,
    BUILDINGS,
    COMPARISON,
    DEV_SEEDS,
    EXAMPLE,
    EXPERIMENTS,
    HELD_OUT_SEEDS,
    PUBLISHED_FIG6_MAX,
    PUBLISHED_PYRAMID,
    PUBLISHED_TABLE1,
    PYRAMID,
    TABLE1,
    PublishedValue,
)
from ._jobs import ablate, reproduce, reproduce_all
from ._oracle import OracleRow, oracle

__all__ = [
    "PUBLISHED_GAIN",
    "speed",
    "ablate",
    "reproduce",
    "reproduce_all",
    "OracleRow",
    "oracle",
    "ABLATIONS_BY_NAME",
    "BUILDINGS",
    "COMPARISON",
    "DEV_SEEDS",
    "EXAMPLE",
    "EXPERIMENTS",
    "HELD_OUT_SEEDS",
    "PUBLISHED_FIG6_MAX",
    "PUBLISHED_PYRAMID",
    "PUBLISHED_TABLE1",
    "PYRAMID",
    "TABLE1",
    "PublishedValue",
]
