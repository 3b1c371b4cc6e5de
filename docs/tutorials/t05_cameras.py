"""
Cameras
=======

A :class:`uavcov.Camera` (pinhole: sensor, focal length, image size; or a field of view)
turns the paper's omnidirectional sensor into a frustum: a point is seen when it is in range,
in the camera's view and in line of sight. Poses are ``(x, y, z, yaw, pitch)`` (metres,
degrees). A mission takes the camera in ``sensor=`` and the fixed angles in ``attitude=``; with
a :class:`uavcov.Gimbal` CAO also turns each camera.
"""

# %%
import numpy as np

import uavcov
from uavcov import plotting

terrain = uavcov.gaussian_hills(size=80.0, spacing=1.0, rng=0)
camera = uavcov.Camera.from_fov(70.0, 50.0)  # horizontal, vertical field of view (degrees)
sensor = uavcov.Sensor(40.0, camera=camera)
vis = uavcov.Visibility(terrain, d_max=40.0)
poses = np.array([[20.0, 20.0, 30.0, 0.0, -90.0], [60.0, 50.0, 30.0, 45.0, -60.0]])
print(f"two cameras see {vis.coverage(poses, sensors=[sensor, sensor]):.3f} of the surface")

# %%
# A mission with cameras whose heading CAO turns
# ----------------------------------------------
settings = uavcov.MissionSettings(
    n_uavs=4, d_max=40.0, iterations=40, sensor=sensor, attitude=(0.0, -70.0), gimbal=uavcov.Gimbal(free_yaw=True)
)
result = uavcov.run_mission(terrain, settings, rng=2)
print(f"coverage {result.initial_coverage:.3f} -> {result.best_coverage:.3f}; headings {np.round(result.best_attitudes[:, 0])}")

# %%
# Footprints and view quality, from above
# ---------------------------------------
best_poses = np.column_stack([result.best_positions, result.best_attitudes])
views = plotting.plot_camera_views(terrain, best_poses, [sensor] * 4)
