"""The large synthetic map the large-map benchmarks share (imported by their child processes)."""

from __future__ import annotations

import numpy as np


def heights(size: float, spacing: float, seed: int = 0) -> np.ndarray:
    """Heights of a square map of side ``size`` m at ``spacing`` m: ``(n, n)``, n = size / spacing + 1.

    150 rolling hills (5-40 m tall, sigma 30-150 m) and 3000 small steep ones (1-6 m, sigma
    1-4 m). Gaussians are separable, so each adds an outer product to a block of rows, and no
    temporary is as large as the map.
    """
    rng = np.random.default_rng(seed)
    n = round(size / spacing) + 1
    hills = np.vstack(
        [
            np.column_stack([rng.uniform(0, size, 150), rng.uniform(0, size, 150), rng.uniform(5, 40, 150), rng.uniform(30, 150, 150)]),
            np.column_stack([rng.uniform(0, size, 3000), rng.uniform(0, size, 3000), rng.uniform(1, 6, 3000), rng.uniform(1, 4, 3000)]),
        ]
    )
    x = np.arange(n) * spacing
    z = np.zeros((n, n))
    for r0 in range(0, n, 256):
        y = x[r0 : r0 + 256]
        for cx, cy, h, s in hills:
            if cy + 5 * s < y[0] or cy - 5 * s > y[-1]:
                continue
            lo, hi = np.searchsorted(x, [cx - 5 * s, cx + 5 * s])
            gx = h * np.exp(-((x[lo:hi] - cx) ** 2) / (2 * s * s))
            gy = np.exp(-((y - cy) ** 2) / (2 * s * s))
            z[r0 : r0 + 256, lo:hi] += np.outer(gy, gx)
    return z
