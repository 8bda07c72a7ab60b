"""
Film of overlapping strokes against the closed form
===================================================

Three guns spray five straight strokes 50 mm apart over a flat plate at their reference
standoff. The film integrated by ik7r (markers) is compared with the closed-form stroke
profiles summed across the strokes (lines): the two agree within 0.5 % of the peak.
"""

import matplotlib.pyplot as plt
import numpy as np

from ik7r.painting.film import film_step, film_thickness, poses_from_samples
from ik7r.painting.spray import load_gun, stroke_profile

speed, offsets = 500.0, [-100.0, -50.0, 0.0, 50.0, 100.0]
y = np.linspace(-250, 250, 201)
V = np.column_stack([np.zeros_like(y), y, np.zeros_like(y)])  # a line of points across the strokes
N = np.tile([0.0, 0.0, 1.0], (len(y), 1))
faces = np.array([[0, 1, 2]])

fig, ax = plt.subplots(figsize=(8, 4.5))
for name, colour in (("bell", "tab:blue"), ("beta", "tab:orange"), ("fan", "tab:green")):
    gun = load_gun(name)
    h = film_step(gun)
    xs = np.arange(-gun.reach - 50, gun.reach + 50 + h, h)
    t, T, on, t0 = [], [], [], 0.0
    for k, off in enumerate(offsets):  # strokes along x, gun pointing down, off between strokes
        t.append(t0 + (xs - xs[0]) / speed)
        pose = np.tile(np.eye(4), (len(xs), 1, 1))
        pose[:, :3, :3] = np.diag([1.0, -1.0, -1.0])
        pose[:, :3, 3] = np.column_stack([xs, np.full(len(xs), off), np.full(len(xs), gun.standoff)])
        T.append(pose)
        on += [True] * (len(xs) - 1) + ([False] if k + 1 < len(offsets) else [])
        t0 = t[-1][-1] + 1.0
    poses = poses_from_samples(np.concatenate(t), np.concatenate(T), on)
    film = film_thickness(V, N, faces, poses, gun)
    ref = sum(stroke_profile(gun, y - off, speed) for off in offsets)
    err = np.abs(film - ref).max() / ref.max()
    ax.plot(y, ref, color=colour, lw=1.5, label=f"{name} ({gun.model}): closed form")
    ax.plot(y[::4], film[::4], "o", color=colour, ms=3,
            label=f"{name}: ik7r, max error {100 * err:.3f} % of peak")
ax.set_xlabel("distance across the strokes (mm)")
ax.set_ylabel("film thickness (um)")
ax.set_title(f"Five strokes 50 mm apart at {speed:g} mm/s")
ax.legend(fontsize=7)
fig.tight_layout()
plt.show()
