"""
Every solution of one pose
==========================

The paper's Simulation 1: the joints ``[60, 60, 0, -30, 60, 30]`` deg give a pose, and
``robot.ik_all`` returns every joint vector that reaches it: eight here, one per
configuration (Appendix 3), each checked by forward kinematics.
"""

import matplotlib.pyplot as plt
import numpy as np

import ik7r

robot = ik7r.load_robot()                      # the paper's robot, mm
q = np.radians([60, 60, 0, -30, 60, 30])       # [q1, q2, q3, q4, q5, q7]
T = robot.fk(q)
solutions = robot.ik_all(T)
configs = robot.config_of(solutions)
print(f"{len(solutions)} solutions, configurations {configs.tolist()}")

# %%
# Each solution reaches the pose to machine precision:
errors = np.abs(robot.fk(solutions)[:, :3, 3] - T[:3, 3]).max(axis=1)
print("largest position error (mm):", errors.max())
assert errors.max() < robot.position_tolerance

# %%
# The eight postures: the links (through the origins of the DH frames) and the tool's
# approach axis. Postures that share most links differ in the wrist.
frames = robot.frames(solutions)               # (8, 9, 4, 4): base, frames 1..7, tool
points = frames[:, :, :3, 3].reshape(-1, 3)
centre = 0.5 * (points.min(axis=0) + points.max(axis=0))
half = 0.55 * (points.max(axis=0) - points.min(axis=0)).max()
fig = plt.figure(figsize=(12, 6.2))
for k in range(len(solutions)):
    ax = fig.add_subplot(2, (len(solutions) + 1) // 2, k + 1, projection="3d")
    P = frames[k, :, :3, 3]
    ax.plot(P[:, 0], P[:, 1], P[:, 2], "-o", color="tab:blue", ms=3, lw=2)
    z = frames[k, -1, :3, 2] * 0.25 * half
    ax.quiver(*P[-1], *z, color="tab:red", lw=2)
    ax.scatter(*T[:3, 3], color="k", s=25)
    ax.scatter(0, 0, 0, color="0.4", marker="s", s=30)
    ax.set_title(f"configuration {configs[k]}", fontsize=10)
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_zlim(centre[2] - half, centre[2] + half)
    ax.view_init(elev=18, azim=-50)
    ax.set_xticks([])
    ax.set_yticks([])
    ax.set_zticks([])
fig.suptitle("Simulation 1: the eight solutions of one pose (target in black, tool axis in red)")
fig.tight_layout()
plt.show()
