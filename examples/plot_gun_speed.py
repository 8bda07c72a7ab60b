"""
Gun speed and joint limits of a raster program
==============================================

A raster whose passes are 50 mm apart, painted at a commanded gun speed of 500 mm/s. Where the
spray is on (shaded) the gun holds the commanded speed; the half-circle turns, with the spray
off, are timed as fast as the joint speed and acceleration limits allow (a time-optimal path
parameterisation), so the joints touch their acceleration limits there and nowhere exceed them.
The short ramps where the gun enters and leaves a turn lie in the 50 mm overspray margins.
"""

import matplotlib.pyplot as plt
import numpy as np

import ik7r
from ik7r.painting import paint_raster

robot = ik7r.load_robot()
res = paint_raster(robot, speed=500.0, size=(300.0, 50.0), spacing=50.0, margin=50.0, step=10.0)
tr = res.trajectory

fig, axes = plt.subplots(3, 1, figsize=(8, 8), sharex=True)
on = np.asarray(tr.spray, dtype=int)
edges = np.flatnonzero(np.diff(np.r_[0, on, 0]))
for ax in axes:
    for a, b in zip(edges[::2], edges[1::2]):
        ax.axvspan(tr.t[a], tr.t[b - 1], color="tab:green", alpha=0.12, lw=0)
axes[0].plot(tr.t, np.where(tr.spray, tr.commanded_speed, np.nan), "k--", lw=2, label="commanded")
axes[0].plot(tr.t, tr.gun_speed, lw=1.2, label="actual (FK of the joints)")
axes[0].set_ylabel("gun speed (mm/s)")
axes[0].legend(loc="lower right", fontsize=8)
for ax, x, lim, name in ((axes[1], tr.dq, robot.velocity, "speed / limit"),
                         (axes[2], tr.ddq, robot.acceleration, "acceleration / limit")):
    for j, label in enumerate(("q1", "q2", "q3", "q4", "q5", "q7")):
        ax.plot(tr.t, x[:, j] / lim[j], lw=1.0, label=label)
    ax.axhline(1.0, color="k", ls=":", lw=1)
    ax.axhline(-1.0, color="k", ls=":", lw=1)
    ax.set_ylabel(f"joint {name}")
axes[1].legend(ncol=6, fontsize=7, loc="upper right")
axes[2].set_xlabel("time (s)")
fig.suptitle(f"Raster at 500 mm/s: {tr.duration:.2f} s, peak acceleration "
             f"{np.max(tr.acceleration_ratio):.3f} of the limit")
fig.tight_layout()
plt.show()
