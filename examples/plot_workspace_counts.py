"""
How many solutions, where
=========================

The number of solutions of a pose over a slice of the workspace: tool positions in the
base's x-z plane (y = 0), the gun pointing down, every pose solved at once by
``robot.ik_all_batch``. The paper's "at most eight" holds almost everywhere; near the
boundaries the count drops (4) or, in thin regions, rises to 12 or 16, where one arm branch
holds several fixed points of the paper's iteration.
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
levels = np.arange(-0.5, count.max() + 1.5, 1)
im = ax.pcolormesh(X, Z, count, cmap="viridis", shading="auto", vmin=0, vmax=max(16, count.max()))
fig.colorbar(im, ax=ax, label="number of solutions")
ax.set_xlabel("x (mm)")
ax.set_ylabel("z (mm)")
ax.set_aspect("equal")
ax.set_title("Solutions per pose, y = 0, gun pointing down")
plt.show()
