"""``make bench``: the film of a 100,000-vertex part over a 60 s painting trajectory.

The part is the built-in hood meshed finely (about 103,000 vertices, 205,000 faces); the
trajectory is its surface raster solved on the paper robot and timed at the speed that makes
it last 60 s. Timed: the film integration (the step rule's instants, forward kinematics of the
interpolated joints, the compiled kernel with per-pose depth-buffer occlusion), after one
warm-up call that loads the compiled kernel. Baseline in the same run: the projection formula
in vectorised numpy without occlusion on a subset of the poses, scaled to all of them.
Budget (issue 15): at most 10 s on the project's 2-core machine.
"""

from __future__ import annotations

import sys
import time

import numpy as np

import ik7r
from ik7r.geometry.rotations import invert
from ik7r.painting import solve_path
from ik7r.painting.film import film_step, film_thickness, gun_poses, part_film, poses_from_samples
from ik7r.painting.mesh import time_at_speed
from ik7r.painting.parts import builtin_part
from ik7r.painting.spray import load_gun, surface_rate
from ik7r.painting.surface import surface_raster

BUDGET_S = 10.0


def main() -> int:
    robot = ik7r.load_robot()
    gun = load_gun("bell")
    part = builtin_part("hood", cell=1.85)
    path = surface_raster(part, spacing=55.0, standoff=200.0, overspray=60.0, approach=150.0)
    sol = solve_path(robot, path, 1)
    if not sol.feasible:
        print(sol.report())
        return 1
    speed = path.u[-1] / 59.5  # 60 s with a 0.5 s ramp
    traj, _ = time_at_speed(robot, sol, speed, ramp=0.5, approach=150.0)
    # warm-up: load the compiled kernel (and compile it on a first run)
    tiny = builtin_part("panel", cell=100.0)
    film_thickness(tiny.vertices, tiny.vertex_normals, tiny.faces,
                   poses_from_samples([0, 1], np.stack([np.eye(4)] * 2)), gun)

    t0 = time.perf_counter()
    poses = gun_poses(robot, traj, path, part.T_base_part, gun)
    t1 = time.perf_counter()
    film = part_film(part, poses, gun)
    t2 = time.perf_counter()
    total = t2 - t0

    # baseline: numpy, no occlusion, on 20 sprayed poses, scaled to all sprayed poses
    w = poses.weights
    idx = np.flatnonzero(w > 0)
    sub = idx[np.linspace(0, len(idx) - 1, 20).astype(int)]
    N = part.vertex_normals
    tb = time.perf_counter()
    for m in sub:
        Tt = invert(poses.T_part_tool[m])
        surface_rate(gun, part.vertices @ Tt[:3, :3].T + Tt[:3, 3], N @ Tt[:3, :3].T)
    base = (time.perf_counter() - tb) * len(idx) / len(sub)

    print(f"film of {len(part.vertices):,} vertices ({len(part.faces):,} faces) over a {traj.duration:.1f} s "
          f"trajectory: {len(poses.t)} instants ({len(idx)} sprayed), step {film_step(gun):g} mm")
    print(f"  instants + FK {t1 - t0:.2f} s, kernel with occlusion {t2 - t1:.2f} s, total {total:.2f} s "
          f"(budget {BUDGET_S:g} s: {'ok' if total <= BUDGET_S else 'OVER'})")
    print(f"  baseline numpy projection without occlusion: {base:.2f} s (estimated from {len(sub)} poses); "
          f"ratio {base / (t2 - t1):.1f}x")
    print(f"  film mean {float(np.mean(film[film > 0])):.2f} um where painted")
    return 0 if total <= BUDGET_S else 1


if __name__ == "__main__":
    sys.exit(main())
