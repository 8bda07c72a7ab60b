"""
The ABB IRB 5400 from a URDF file
=================================

Any robot of the family can be read from a URDF whose sixth joint is a ``<mimic>`` of the
fifth. Here the built-in IRB 5400 (ROS-Industrial's model, in mm) is written as a URDF (in
metres), read back, and solved: its published, rounded numbers make the wrist very slightly
asymmetric, so ik7r solves the idealised wrist and polishes every solution on the exact
model.
"""

import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import ik7r

irb = ik7r.load_robot("irb5400")
with tempfile.TemporaryDirectory() as tmp:
    path = Path(tmp) / "irb5400.urdf"
    path.write_text(irb.to_urdf())
    robot = ik7r.load_robot(path)              # metres, joint names and limits from the file
print(robot.name, robot.unit, robot.joint_names)
print("deviation from the idealised family member:", robot.family.deviation)

# %%
# One pose, every solution, each exact on the model as written:
q = np.radians([10, 20, -15, 30, 40, -20])
T = robot.fk(q)
solutions = robot.ik_all(T)
err = np.abs(robot.fk(solutions)[:, :3, 3] - T[:3, 3]).max()
print(f"{len(solutions)} solutions; largest position error {err * 1e3:.2e} mm")
assert np.allclose(irb.fk(q)[:3, 3] / 1000, T[:3, 3], atol=1e-12)

# %%
# The postures, seen from the side:
frames = robot.frames(solutions)
fig, ax = plt.subplots(figsize=(7, 6))
for k, F in enumerate(frames):
    P = F[:, :3, 3]
    ax.plot(P[:, 0], P[:, 2], "-o", ms=3, lw=1.5, label=f"configuration {robot.config_of(solutions[k])}")
ax.plot(T[0, 3], T[2, 3], "k*", ms=12, label="target")
ax.set_xlabel("x (m)")
ax.set_ylabel("z (m)")
ax.set_aspect("equal")
ax.legend(fontsize=8)
ax.set_title("IRB 5400 (read from URDF): every solution of one pose")
plt.show()
