"""
How many solutions, where
=========================

The number of solutions of a pose over a slice of the workspace: tool positions in the
base's x-z plane (y = 0), the gun pointing down, every pose solved at once by
``robot.ik_all_batch``. On this slice a pose has 8 solutions, or 4 where only one shoulder
branch reaches it; on the line x = 0 the wrist centre lies on axis 1 (the shoulder
singularity), where q1 is free and one member of each family is returned. Other
orientations have poses with 12 or 16 solutions (one arm branch holding several fixed points
of the paper's iteration), which the paper's "at most eight" misses.
"""

import matplotlib.pyplot as plt
import numpy as np

import ik7r

robot = ik7r.load_robot()
x = np.linspace(-2100, 2100, 211)
z = np.linspace(-1700, 2300, 201)
X, Z = np.meshgrid(x, z)
T = np.zeros(X.shape + (4, 4))
T[..., :3, :3] = np.diag([1.0, -1.0, -1.0])    # the gun points down (the paper's painting pose)
T[..., 0, 3] = X
T[..., 2, 3] = Z
T[..., 3, 3] = 1.0

q, valid = robot.ik_all_batch(T.reshape(-1, 4, 4))
count = valid.sum(axis=1).reshape(X.shape)
values, poses = np.unique(count, return_counts=True)
print(dict(zip(values.tolist(), poses.tolist())))

# %%
# Every solution is exact (the batch returns only verified ones):
Tq = robot.fk(q[valid])
target = np.repeat(T.reshape(-1, 4, 4), valid.sum(axis=1), axis=0)
print("largest position error (mm):", np.abs(Tq[:, :3, 3] - target[:, :3, 3]).max())

# %%
fig, ax = plt.subplots(figsize=(7.5, 6.5))
top = max(16, int(count.max()))
cmap = plt.get_cmap("viridis", top // 4 + 1)               # one colour per multiple of 4
im = ax.pcolormesh(X, Z, count, cmap=cmap, shading="auto", vmin=-2, vmax=top + 2)
fig.colorbar(im, ax=ax, label="number of solutions", ticks=range(0, top + 1, 4))
ax.set_xlabel("x (mm)")
ax.set_ylabel("z (mm)")
ax.set_aspect("equal")
ax.set_title("Solutions per pose, y = 0, gun pointing down")
plt.show()
