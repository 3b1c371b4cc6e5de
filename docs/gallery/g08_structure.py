"""
A structure from several sides
==============================

A girder bridge is not a height field: its deck hides its underside from above.
:func:`uavcov.placement.standoff_start` places six cameras by a CVT on the surface, each flown
8 m out along its generator's outward normal and facing back; the figure shows the bridge
coloured by what they see, from three sides above and one from below
(:func:`uavcov.plotting.plot_structure_seen`).
"""

import numpy as np

import uavcov
from uavcov import placement, plotting, structures

bridge = structures.girder_bridge(rng=0)
start = placement.standoff_start(bridge.surface, 6, 8.0, rng=0)
sensor = uavcov.Sensor(20.0, camera=uavcov.Camera.from_fov(80.0, 60.0))
poses = np.column_stack([start.positions, start.attitudes])
vis = uavcov.Visibility(bridge.surface, d_max=20.0)
seen = vis.seen(poses, sensors=[sensor] * 6)
fig = plotting.plot_structure_seen(bridge.surface, seen, targets=vis.targets, positions=start.positions)
