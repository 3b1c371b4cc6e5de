# Hand-written stub of the Rust extension uavcov._core; tests/test_stubs.py checks it against
# the compiled module with mypy.stubtest, so it fails on drift.
from typing import final

import numpy as np
import numpy.typing as npt

__all__ = [
    "Surface",
    "Visibility",
    "CoverageTracker",
    "CVT",
    "SeenMatrix",
    "Surrogate",
    "available_threads",
    "pcg64_standard_normal",
    "pcg64_random",
    "pcg64_integers",
    "pcg64_monomials",
    "__version__",
]

__version__: str

def available_threads() -> int: ...
def pcg64_standard_normal(state: int, inc: int, n: int) -> tuple[npt.NDArray[np.float64], int]: ...
def pcg64_random(state: int, inc: int, n: int) -> tuple[npt.NDArray[np.float64], int]: ...
def pcg64_integers(
    state: int, inc: int, has_uint32: int, uinteger: int, low: int, high: int, n: int
) -> tuple[npt.NDArray[np.int64], int, int, int]: ...
def pcg64_monomials(
    terms: npt.NDArray[np.int64],
    strength: npt.NDArray[np.float64],
    keep: int,
    count: int,
    dim: int,
    state: int,
    inc: int,
    has_uint32: int,
    uinteger: int,
) -> tuple[npt.NDArray[np.int64] | None, int, int, int]: ...

@final
class Surface:
    def __new__(cls, vertices: npt.NDArray[np.float64], faces: npt.NDArray[np.int64]) -> Surface: ...
    @staticmethod
    def from_grid(z: npt.NDArray[np.float64], dx: float, dy: float, x0: float, y0: float) -> Surface: ...
    @property
    def n_vertices(self) -> int: ...
    @property
    def n_faces(self) -> int: ...
    @property
    def area(self) -> float: ...
    def vertices(self) -> npt.NDArray[np.float64]: ...
    def faces(self) -> npt.NDArray[np.int64]: ...
    def face_areas(self) -> npt.NDArray[np.float64]: ...
    def face_normals(self) -> npt.NDArray[np.float64]: ...
    def bounds(self) -> npt.NDArray[np.float64]: ...
    def vertex_targets(self) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...
    def area_targets(self, density: float) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...
    def vertex_normals(self) -> npt.NDArray[np.float64]: ...
    def ground_height(self, xy: npt.NDArray[np.float64], n_threads: int = 0) -> npt.NDArray[np.float64]: ...
    def clearance(self, points: npt.NDArray[np.float64], n_threads: int = 0) -> npt.NDArray[np.float64]: ...
    def closest_point(self, points: npt.NDArray[np.float64], n_threads: int = 0) -> npt.NDArray[np.float64]: ...
    def closest_face(
        self, points: npt.NDArray[np.float64], n_threads: int = 0
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.int64]]: ...
    def faces_at_closest(
        self, points: npt.NDArray[np.float64], n_threads: int = 0
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.int64], npt.NDArray[np.int64]]: ...
    def segments_clear(self, a: npt.NDArray[np.float64], b: npt.NDArray[np.float64], n_threads: int = 0) -> npt.NDArray[np.bool_]: ...
    def first_hits(
        self, origins: npt.NDArray[np.float64], directions: npt.NDArray[np.float64], t_max: float, n_threads: int = 0
    ) -> npt.NDArray[np.float64]: ...
    def distance(self, points: npt.NDArray[np.float64], n_threads: int = 0) -> npt.NDArray[np.float64]: ...
    def inside(self, points: npt.NDArray[np.float64], n_threads: int = 0) -> npt.NDArray[np.bool_]: ...
    def admissible_mask(
        self,
        current: npt.NDArray[np.float64],
        candidates: npt.NDArray[np.float64],
        bounds: tuple[float, float, float, float],
        h_min: float,
        h_max: float | None,
        z_max: float,
        d_safe: float,
        check_moves: bool,
        n_threads: int = 0,
        clearance: str = "vertical",
    ) -> npt.NDArray[np.bool_]: ...

@final
class Visibility:
    def __new__(
        cls,
        surface: Surface,
        targets: npt.NDArray[np.float64] | None,
        weights: npt.NDArray[np.float64] | None,
        d_max: float,
        method: str = "auto",
        normals: npt.NDArray[np.float64] | None = None,
    ) -> Visibility: ...
    @property
    def path(self) -> str: ...
    @property
    def n_targets(self) -> int: ...
    @property
    def d_max(self) -> float: ...
    def seen(
        self, uavs: npt.NDArray[np.float64], n_threads: int = 0, sensors: npt.NDArray[np.float64] | None = None
    ) -> npt.NDArray[np.bool_]: ...
    def coverage(self, uavs: npt.NDArray[np.float64], n_threads: int = 0, sensors: npt.NDArray[np.float64] | None = None) -> float: ...
    def quality(
        self, uavs: npt.NDArray[np.float64], n_threads: int = 0, sensors: npt.NDArray[np.float64] | None = None
    ) -> npt.NDArray[np.float64]: ...
    def quality_coverage(
        self, uavs: npt.NDArray[np.float64], n_threads: int = 0, sensors: npt.NDArray[np.float64] | None = None
    ) -> float: ...
    def per_uav(
        self, uavs: npt.NDArray[np.float64], n_threads: int = 0, sensors: npt.NDArray[np.float64] | None = None
    ) -> tuple[
        npt.NDArray[np.uint64],
        npt.NDArray[np.uint64],
        npt.NDArray[np.float64],
        npt.NDArray[np.float64],
        float,
        float,
    ]: ...

@final
class SeenMatrix:
    def __new__(
        cls,
        visibility: Visibility,
        candidates: npt.NDArray[np.float64],
        sensors: npt.NDArray[np.float64] | None = None,
        n_threads: int = 0,
    ) -> SeenMatrix: ...
    @property
    def n_candidates(self) -> int: ...
    @property
    def n_targets(self) -> int: ...
    @property
    def nbytes(self) -> int: ...
    def ceiling(self) -> float: ...
    def column(self, c: int) -> npt.NDArray[np.bool_]: ...
    def greedy(self, k: int, d_safe: float, n_threads: int = 0) -> tuple[npt.NDArray[np.int64], npt.NDArray[np.float64], float, float]: ...
    def bound(self, seen: npt.NDArray[np.bool_], k: int, n_threads: int = 0) -> tuple[float, float]: ...

@final
class CoverageTracker:
    def __new__(cls, visibility: Visibility, margin: float | None = None) -> CoverageTracker: ...
    @property
    def margin(self) -> float | None: ...
    @property
    def certifies(self) -> bool: ...
    @property
    def settled(self) -> int: ...
    def seen(self, uavs: npt.NDArray[np.float64], n_threads: int = 0) -> npt.NDArray[np.bool_]: ...
    def coverage(self, uavs: npt.NDArray[np.float64], n_threads: int = 0) -> float: ...

@final
class CVT:
    @staticmethod
    def run(
        surface: Surface,
        n: int,
        samples_per_iteration: int,
        alpha: tuple[float, float],
        beta: tuple[float, float],
        tolerance: float,
        window: int,
        max_iterations: int,
        seed: int,
        density: npt.NDArray[np.float64] | None = None,
        initial: npt.NDArray[np.float64] | None = None,
        n_threads: int = 0,
        normal_weight: float = 0.0,
    ) -> tuple[
        npt.NDArray[np.float64],
        npt.NDArray[np.float64],
        npt.NDArray[np.float64],
        npt.NDArray[np.float64],
        npt.NDArray[np.float64],
        int,
        bool,
    ]: ...
    @staticmethod
    def regions(generators: npt.NDArray[np.float64], points: npt.NDArray[np.float64], n_threads: int = 0) -> npt.NDArray[np.int64]: ...

@final
class Surrogate:
    @staticmethod
    def fit(
        window: npt.NDArray[np.float64],
        values: npt.NDArray[np.float64],
        terms: npt.NDArray[np.int64],
        candidates: npt.NDArray[np.float64],
        ridge: float,
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...
    @staticmethod
    def fit_robots(
        window: npt.NDArray[np.float64],
        values: npt.NDArray[np.float64],
        terms: npt.NDArray[np.int64],
        active: npt.NDArray[np.bool_],
        candidates: npt.NDArray[np.float64],
        ridge: float,
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...
