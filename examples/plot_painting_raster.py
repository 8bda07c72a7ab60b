"""
A painting raster (the paper's Figure 12)
=========================================

The paper's Simulation 3: the gun sweeps a 600 x 800 mm raster in configuration 1 in 20 s.
``paint_raster`` solves every sample on one continuous solution branch, interpolates a
quintic spline through them, checks the tool's deviation from the path and the joint
limits, and reports anything that would surprise on the shop floor (nothing, here).
"""

import matplotlib.pyplot as plt
import numpy as np

import ik7r
from ik7r.painting import paint_raster

robot = ik7r.load_robot()
result = paint_raster(robot, duration=20.0, config=1)
trajectory = result.trajectory
print(result.report())

# %%
# The path in the base frame, with the passes joined by half circles:
P = result.path.positions
fig, ax = plt.subplots(figsize=(6, 5))
ax.plot(P[:, 0], P[:, 1], lw=1)
ax.set_xlabel("x (mm)")
ax.set_ylabel("y (mm)")
ax.set_aspect("equal")
ax.set_title(f"raster: {len(P)} samples, {result.path.length:.0f} mm")

# %%
# Joint positions, velocities and accelerations against time (Figure 12). The
# accelerations jump where a straight pass meets a half-circle turn (the curvature jumps).
labels = ["q1", "q2", "q3", "q4", "q5", "q7"]
fig, axes = plt.subplots(3, 1, figsize=(8, 8.5), sharex=True)
for ax, x, name in zip(axes, (trajectory.q, trajectory.dq, trajectory.ddq),
                       ("position (deg)", "velocity (deg/s)", "acceleration (deg/s²)")):
    for j in range(6):
        ax.plot(trajectory.t, np.degrees(x[:, j]), label=labels[j], lw=1.1)
    ax.set_ylabel(name)
    ax.grid(True, alpha=0.3)
axes[0].legend(ncol=6, fontsize=8, loc="upper center", bbox_to_anchor=(0.5, 1.3))
axes[-1].set_xlabel("time (s)")
fig.tight_layout()
plt.show()
