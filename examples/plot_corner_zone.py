"""
A sharp corner: stop, or blend within a zone
============================================

A stroke with a right-angle corner, loaded as samples. Without a zone the robot stops at the
corner (the gun speed drops to zero there); with a 20 mm zone (RAPID's zone data) the corner is
replaced by a tangent arc that passes 0.41 x 20 mm from it, and the gun slows only as much as
the joint acceleration limits require. Neither has an acceleration spike.
"""

import matplotlib.pyplot as plt
import numpy as np

import ik7r
from ik7r.geometry.rotations import transform
from ik7r.painting import GUN_DOWN, paint_path, path_from_poses

robot = ik7r.load_robot()
pts = np.array([[950.0, 0.0, 300.0], [1250.0, 0.0, 300.0], [1250.0, 200.0, 300.0]])
fine = np.vstack([np.linspace(pts[0], pts[1], 31), np.linspace(pts[1], pts[2], 21)[1:]])
path = path_from_poses(transform(GUN_DOWN, fine))

fig, (ax0, ax1) = plt.subplots(1, 2, figsize=(10, 4))
for zone, style in ((None, "-"), (20.0, "--")):
    res = paint_path(robot, path, speed=300.0, zone=zone, slow_down=True)
    tr = res.trajectory
    name = "stop at the corner" if zone is None else f"zone {zone:g} mm"
    ax0.plot(tr.positions[:, 0], tr.positions[:, 1], style, label=name)
    ax1.plot(tr.t, tr.gun_speed, style, label=f"{name}: {tr.duration:.2f} s, "
             f"peak accel. {np.max(tr.acceleration_ratio):.2f} of limit")
ax0.set_xlim(1180, 1270)
ax0.set_ylim(-20, 70)
ax0.set_aspect("equal")
ax0.set_xlabel("x (mm)")
ax0.set_ylabel("y (mm)")
ax0.set_title("near the corner")
ax0.legend(fontsize=8)
ax1.set_xlabel("time (s)")
ax1.set_ylabel("gun speed (mm/s)")
ax1.legend(fontsize=8)
fig.tight_layout()
plt.show()
