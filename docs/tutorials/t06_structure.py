"""
A structure
===========

Beyond terrains, a surface may be a structure that is not a height field: a bridge whose deck
hides its underside from above. :mod:`uavcov.structures` builds five procedural scenes
(:data:`uavcov.structures.STRUCTURE_SCENES`); :func:`uavcov.placement.standoff_start` places a team
by a CVT on the surface, each UAV flown out along its generator's outward normal, its camera
facing back at the surface. Here a girder bridge, six cameras 8 m off the surface, and what they
see (see ``docs/structures.md`` for the scenes, the 3D prior and its reconstruction).
"""

# %%
import numpy as np

import uavcov
from uavcov import placement, plotting, structures

bridge = structures.girder_bridge(rng=0)
print(bridge.name, bridge.surface.n_faces, "faces, parts:", ", ".join(bridge.part_names))

start = placement.standoff_start(bridge.surface, 6, 8.0, rng=0)
sensor = uavcov.Sensor(20.0, camera=uavcov.Camera.from_fov(80.0, 60.0))
poses = np.column_stack([start.positions, start.attitudes])
vis = uavcov.Visibility(bridge.surface, d_max=20.0)
seen = vis.seen(poses, sensors=[sensor] * 6)
print(f"six cameras see {vis.coverage(poses, sensors=[sensor] * 6):.3f} of the bridge")

# %%
# The bridge coloured by seen, from several sides (one from below)
# ----------------------------------------------------------------
fig = plotting.plot_structure_seen(bridge.surface, seen, targets=vis.targets, positions=start.positions)
