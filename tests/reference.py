"""An independent, brute-force reference for the number of IK solutions of the paper robot.

Written from the paper's geometry with numpy only (no ik7r code): for the symmetric hollow
wrist, axes 4 and 7 meet at a point (the virtual wrist centre) whose offsets along the two axes
depend on theta5 only. For each theta5 on a dense grid, the arm (theta1..3) places that point
(four branches, the paper's Appendix 1 written anew), and the pose is reached exactly when the
angle between axis 4 (set by the arm) and axis 7 (set by the pose) equals the wrist's bend
angle at theta5. Each sign change of that residual over theta5 in (0, pi) is one arm solution,
which the wrist completes in two ways (+theta5 and -theta5).
"""

from __future__ import annotations

import numpy as np
from helpers import TABLE1, dh_link


def _wrist_geometry(t5):
    """For theta5 (array), the offsets (s along axis 4 from frame 4, t along axis 7 from frame 7)
    of the point where the two axes meet, and the cosine of the bend angle between them."""
    s_out, t_out, c_out = [], [], []
    for t in np.atleast_1d(t5):
        T47 = np.eye(4)
        for i, th in zip((4, 5, 6), (t, -t, 0.0)):
            a, al, d = TABLE1[i]
            T47 = T47 @ dh_link(a, al, th, d)
        z4, o7, z7 = np.array([0, 0, 1.0]), T47[:3, 3], T47[:3, 2]
        # o4 + s z4 = o7 + t z7  (least squares; the lines meet for the symmetric wrist)
        A = np.column_stack([z4, -z7])
        (s, tt), *_ = np.linalg.lstsq(A, o7, rcond=None)
        assert np.linalg.norm(s * z4 - o7 - tt * z7) < 1e-6
        s_out.append(s)
        t_out.append(tt)
        c_out.append(z7[2])
    return np.array(s_out), np.array(t_out), np.array(c_out)


def _arm_branches(P, L):
    """Axis 4's direction for the four arm branches placing the point at distance L along
    axis 4 (from the x3 axis) at P (n, 3): (4, n, 3), NaN where a branch does not exist.

    Table 1's arm in closed form: in the arm plane the point is RotZ(theta2) applied to
    (a2 + L sin theta3, -L cos theta3), and axis 4 points along (sin(theta2 + theta3),
    -cos(theta2 + theta3)); theta1 turns the plane (radial coordinate +rho or -rho).
    """
    a2 = TABLE1[2][0]
    out = np.full((4, len(P), 3), np.nan)
    k = (np.sum(P**2, axis=1) - L**2 - a2**2) / (2 * a2 * L)  # sin(theta3)
    exists = np.abs(k) <= 1
    ks = np.clip(k, -1, 1)
    rho = np.hypot(P[:, 0], P[:, 1])
    phi = np.arctan2(P[:, 1], P[:, 0])
    for b, (flip, t3) in enumerate([(1, np.arcsin(ks)), (1, np.pi - np.arcsin(ks)),
                                    (-1, np.arcsin(ks)), (-1, np.pi - np.arcsin(ks))]):
        t1 = phi if flip == 1 else phi + np.pi
        x, y = a2 + L * np.sin(t3), -L * np.cos(t3)
        t2 = np.arctan2(P[:, 2], flip * rho) - np.arctan2(y, x)
        s23, c23 = np.sin(t2 + t3), np.cos(t2 + t3)
        z4 = np.stack([np.cos(t1) * s23, np.sin(t1) * s23, -c23], axis=1)
        out[b] = np.where(exists[:, None], z4, np.nan)
    return out


_GRID: dict[int, tuple] = {}


def count_solutions(T_0_7, n_grid=4000):
    """(count, ambiguous): solutions of the pose T_0_7 (frame 0 <- frame 7, mm), and whether a
    near-tangential root or a root next to a branch end (elbow stretched) makes the sampled
    count uncertain (then skip the pose)."""
    if n_grid not in _GRID:
        t5 = np.linspace(0.0, np.pi, n_grid + 1)[1:-1]
        _GRID[n_grid] = _wrist_geometry(t5)
    s, t, cb = _GRID[n_grid]
    p7, z7 = T_0_7[:3, 3], T_0_7[:3, 2]
    P = p7[None, :] + t[:, None] * z7[None, :]
    Z4 = _arm_branches(P, TABLE1[3][2] + s)
    count, ambiguous = 0, False
    for b in range(4):
        f = Z4[b] @ z7 - cb
        good = np.isfinite(f)
        sign_change = (f[:-1] * f[1:]) < 0
        count += 2 * int(np.sum(sign_change))
        near = np.abs(np.where(good, f, np.inf)) < 2e-2
        # a branch that ends (elbow stretched) close to a root of f
        for e in np.flatnonzero(np.diff(good.astype(int))):
            ambiguous |= bool(np.any(near[max(0, e - n_grid // 40):e + n_grid // 40 + 2]))
        # a local minimum of |f| close to zero without a sign change: tangential
        af = np.where(good, np.abs(f), np.inf)
        inner = (af[1:-1] <= af[:-2]) & (af[1:-1] <= af[2:]) & (af[1:-1] < 1e-4)
        no_change = ~(sign_change[:-1] | sign_change[1:])
        ambiguous |= bool(np.any(inner & no_change))
        # roots at the ends of the theta5 range (straight or fully bent wrist)
        ambiguous |= bool(np.any(np.abs(f[[0, -1]]) < 1e-3))
    return count, ambiguous
