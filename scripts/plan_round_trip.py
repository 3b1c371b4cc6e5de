#!/usr/bin/env python
"""Round-trip errors of the plan frames: local -> WGS84 -> local on a UTM DEM and on the Jacksboro sample (docs/plan.md)."""

import numpy as np

from uavcov import sample_dem as sample_geo_dem
from uavcov.terrain import dem_from_array

z = np.full((20, 24), 400.0)
utm = dem_from_array(z, (30.0, 0.0, 500000.0, 0.0, -30.0, 5000600.0), "EPSG:32633")
geo = sample_geo_dem((0, 30, 0, 30))
for name, dem in (("UTM 33N", utm), ("Jacksboro (WGS 84)", geo)):
    high = dem.terrain.bounds[1]
    local = np.random.default_rng(3).uniform([0, 0, 0], high + [0, 0, 100.0], size=(200, 3))
    print(name, f"local -> WGS84 -> local max error {np.abs(dem.from_wgs84(dem.to_wgs84(local)) - local).max():.2e} m")
