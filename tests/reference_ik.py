"""An independent reference for every IK solution, the singular sets included.

Written from the geometry with numpy and scipy only: it imports nothing of ik7r (the robot is
read from its public fields: the DH table as written, joint signs, coupling, base, tool). It
shares no code with the solver, and its method differs where the solver is weakest: a dense
scan in theta5 graded toward both ends (straight and fully bent wrist) and toward every end of
an arm branch (stretched elbow), a scan in theta1 wherever axis 7 passes near axis 1 (the
shoulder set), closed forms at the singular sets, and multi-start Levenberg-Marquardt
(``scipy.optimize.least_squares``) on the full forward kinematics of the table as written
(rounded, deviating models included), polished to 1e-12.

The geometry (Craig's modified DH, ``theta_i = sign_i q_i + offset_i``, ``q6 = m q5 + c``):

* For the idealised wrist (twists ``(-beta, 2 beta, -beta)``, ``d5 = d6``, ``a4 = a5 = a6 = 0``)
  axes 4 and 7 meet at a point, the virtual wrist centre, at offset ``s(theta5)`` along axis 4
  from frame 4 and ``t(theta5)`` along axis 7 from frame 7, and bend by an angle
  ``phi(theta5)``; all three are computed here by intersecting the two axes numerically.
* The arm ``R perp R parallel R`` (any ``a1, a2, a3, d1, d2 + d3, d4``) places the point at
  ``(a3, -eps3 L, 0)`` of frame 3, ``L = d4 + s``, in closed form: two shoulder branches
  (``A = +-sqrt(rho^2 - b^2)``) and two elbow branches (``theta3 = gamma +- acos(K / R)``).
* A pose is reached exactly when the angle between axis 4 of the arm and axis 7 of the pose
  equals ``phi(theta5)``: the *gap* ``g(theta5) = angle(z4, z7) - phi(theta5)`` has a root.
  ``theta4`` and ``theta7`` then follow from the orientation; at a straight wrist only their sum
  is defined (``q4`` is taken 0).

Every candidate (sign changes of the gap refined by ``brentq``; local minima of ``|g|`` that come
near zero; branch ends; the closed forms) is polished by Levenberg-Marquardt on the exact forward
kinematics and kept when its pose meets ``tol`` (position) and 1e-12 (rotation). Solutions closer
than ``merge`` rad in every joint (or, at a straight wrist, in ``q1, q2, q3, q5`` and
``s4 q4 + s7 q7``) are one.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq, least_squares

__all__ = ["Chain", "reference_fk", "reference_ik", "straight_wrist_close"]


def _wrap(x):
    return np.pi - np.mod(np.pi - np.asarray(x), 2 * np.pi)


def _link(a, alpha, theta, d):
    """Eq. (1), broadcast over theta (n,): RotX(alpha) TransX(a) RotZ(theta) TransZ(d) -> (n, 4, 4)."""
    theta = np.atleast_1d(np.asarray(theta, float))
    ca, sa = math.cos(alpha), math.sin(alpha)
    ct, st = np.cos(theta), np.sin(theta)
    out = np.zeros(theta.shape + (4, 4))
    out[..., 0, 0], out[..., 0, 1], out[..., 0, 3] = ct, -st, a
    out[..., 1, 0], out[..., 1, 1], out[..., 1, 2], out[..., 1, 3] = st * ca, ct * ca, -sa, -sa * d
    out[..., 2, 0], out[..., 2, 1], out[..., 2, 2], out[..., 2, 3] = st * sa, ct * sa, ca, ca * d
    out[..., 3, 3] = 1.0
    return out


def _link1(a, alpha, theta, d):
    """Eq. (1) for one scalar theta: (4, 4)."""
    ca, sa, ct, st = math.cos(alpha), math.sin(alpha), math.cos(theta), math.sin(theta)
    return np.array([[ct, -st, 0.0, a], [st * ca, ct * ca, -sa, -sa * d], [st * sa, ct * sa, ca, ca * d],
                     [0.0, 0.0, 0.0, 1.0]])


def _inv(T):
    R, p = T[:3, :3], T[:3, 3]
    out = np.eye(4)
    out[:3, :3] = R.T
    out[:3, 3] = -R.T @ p
    return out


class Chain:
    """The kinematic data of a robot, read from its public fields only."""

    def __init__(self, robot):
        self.dh = np.array(robot.dh, float)
        self.sign = np.array(robot.joint_sign, float)
        self.m, self.c = (float(x) for x in robot.coupling)
        self.base = np.array(robot.base, float)
        self.tool = np.array(robot.tool, float)
        self.base_inv, self.tool_inv = _inv(self.base), _inv(self.tool)
        a, al, d = self.dh[:, 0], self.dh[:, 1], self.dh[:, 2]
        self.size = float(np.abs(a[1:4]).sum() + np.abs(d[3:7]).sum())
        self.tol = min(1e-9, 1e-12 * self.size)
        # the idealised model the scans run on (the arm as written, the wrist made a mirror)
        beta = (-al[4] + 0.5 * al[5] - al[6]) / 3.0
        dw = 0.5 * (d[4] + d[5])
        self.ideal = self.dh.copy()
        self.ideal[4:7, 0] = 0.0
        self.ideal[4:7, 1] = (-beta, 2 * beta, -beta)
        self.ideal[4:6, 2] = dw
        self.eps1 = math.copysign(1.0, math.sin(al[1]))
        self.eps3 = math.copysign(1.0, math.sin(al[3]))
        self.a1, self.a2, self.a3 = a[1], a[2], a[3]
        self.b, self.d1, self.d4 = d[1] + d[2], d[0], d[3]
        self.beta = beta

    # ------------------------------------------------------------------ joints and DH angles
    def theta(self, q):
        """DH angles (n, 7) of joints q (n, 6)."""
        q = np.atleast_2d(q)
        q7 = np.column_stack([q[:, :5], self.m * q[:, 4] + self.c, q[:, 5]])
        return self.sign * q7 + self.dh[:, 3]

    def joints(self, th):
        """Joints q (6,) of DH angles th (7,) (theta6 is implied by theta5)."""
        idx = [0, 1, 2, 3, 4, 6]
        q = (np.asarray(th)[idx] - self.dh[idx, 3]) * self.sign[idx]
        return _wrap(q)

    def fk(self, q, table=None):
        """World <- tool poses (n, 4, 4) of joints q (n, 6), on ``table`` (default: as written)."""
        table = self.dh if table is None else table
        th = self.theta(q)
        T = np.broadcast_to(self.base, (len(th), 4, 4)).copy()
        for i in range(7):
            T = T @ _link(table[i, 0], table[i, 1], th[:, i], table[i, 2])
        return T @ self.tool


def reference_fk(robot, q):
    """Forward kinematics of ``robot`` (public fields only) for joints q (..., 6)."""
    q = np.asarray(q, float)
    return Chain(robot).fk(q.reshape(-1, 6)).reshape(q.shape[:-1] + (4, 4))


# ---------------------------------------------------------------------- the idealised wrist
def _wrist(ch, t5):
    """For DH theta5 (n,) on the idealised wrist: s (offset of the virtual centre along axis 4
    from frame 4), t (along axis 7 from frame 7), phi (the bend between axes 4 and 7), and
    W (n, 3, 3) the rotation of frame 4 <- frame 7 at theta7 = 0.

    Below abs(theta5) = 1e-4 the two axes are nearly collinear and their intersection is lost
    in rounding: s and t (even and smooth in theta5) are taken from the values at 1e-4 and
    2e-4 (quadratic through the extrapolated value at 0; error of order 1e-16 relative)."""
    t5 = np.atleast_1d(np.asarray(t5, float))
    s, t, phi, W = _wrist_raw(ch, t5)
    small = np.abs(t5) < 1e-4
    if small.any():
        h = 1e-4
        sh, th_, *_ = _wrist_raw(ch, np.array([h, 2 * h]))
        s0, t0 = (4 * sh[0] - sh[1]) / 3, (4 * th_[0] - th_[1]) / 3
        x2 = (t5[small] / h) ** 2
        s[small] = s0 + (sh[0] - s0) * x2
        t[small] = t0 + (th_[0] - t0) * x2
    return s, t, phi, W


def _wrist_raw(ch, t5):
    w = ch.ideal
    T = _link(w[4, 0], w[4, 1], t5, w[4, 2]) @ _link(w[5, 0], w[5, 1], -t5, w[5, 2]) \
        @ _link(w[6, 0], w[6, 1], np.zeros_like(t5), w[6, 2])
    o, z = T[:, :3, 3], T[:, :3, 2]
    # o + t z meets the z axis: its x and y vanish (least squares over the two)
    zz = z[:, 0] ** 2 + z[:, 1] ** 2
    with np.errstate(invalid="ignore", divide="ignore"):
        t = -(o[:, 0] * z[:, 0] + o[:, 1] * z[:, 1]) / zz
    s = o[:, 2] + t * z[:, 2]
    phi = np.arctan2(np.sqrt(zz), z[:, 2])
    return s, t, phi, T[:, :3, :3]


# ---------------------------------------------------------------------- the arm in closed form
def _arm(ch, P, L):
    """DH (theta1, theta2, theta3) (4, n, 3) of the four arm branches placing the point at
    (a3, -eps3 L, 0) of frame 3 at P (n, 3) (frame 0), and the elbow's K / R (4, n) (beyond +-1
    the branch does not exist; NaN angles there)."""
    e1, e3 = ch.eps1, ch.eps3
    x, y, z = P[:, 0], P[:, 1], P[:, 2] - ch.d1
    rho2 = x * x + y * y
    out = np.full((4, len(P), 3), np.nan)
    kr = np.full((4, len(P)), np.nan)
    R = np.hypot(ch.a3, L)
    gamma = np.arctan2(e3 * L, ch.a3)
    for sh in range(2):
        A = (1 if sh == 0 else -1) * np.sqrt(np.maximum(rho2 - ch.b ** 2, 0.0))
        t1 = np.arctan2(y, x) - np.arctan2(-e1 * ch.b, A)
        r, h = A - ch.a1, e1 * z
        K = (r * r + h * h - ch.a2 ** 2 - ch.a3 ** 2 - L * L) / (2 * ch.a2)
        ratio = K / R
        for el in range(2):
            k = 2 * sh + el
            kr[k] = np.where(rho2 >= ch.b ** 2, ratio, np.nan)
            ac = np.arccos(np.clip(ratio, -1, 1))
            t3 = gamma + (ac if el == 0 else -ac)
            X = ch.a2 + ch.a3 * np.cos(t3) + e3 * L * np.sin(t3)
            Y = ch.a3 * np.sin(t3) - e3 * L * np.cos(t3)
            t2 = np.arctan2(h, r) - np.arctan2(Y, X)
            ok = (np.abs(ratio) <= 1) & (rho2 >= ch.b ** 2)
            out[k] = np.where(ok[:, None], np.column_stack([t1, t2, t3]), np.nan)
    return out, kr


def _z4(ch, th):
    """Frame-0 direction of axis 4 for DH arm angles th (..., 3)."""
    t1, t2, t3 = th[..., 0], th[..., 1], th[..., 2]
    c1, s1 = np.cos(t1), np.sin(t1)
    c23, s23 = np.cos(t2 + t3), np.sin(t2 + t3)
    al1 = ch.dh[1, 1]
    ca, sa = math.cos(al1), math.sin(al1)
    # y3 = RotZ(t1) RotX(al1) RotZ(t2 + t3) e_y ;  z4 = -eps3 y3 (alpha3 = eps3 90 deg)
    v = np.stack([-s23, c23 * ca, c23 * sa], axis=-1)
    y3 = np.stack([c1 * v[..., 0] - s1 * v[..., 1], s1 * v[..., 0] + c1 * v[..., 1], v[..., 2]], axis=-1)
    return -ch.eps3 * y3


def _angle(u, v):
    """Angle between unit vectors u (..., 3) and v (3,) (atan2: accurate near 0 and pi)."""
    cx = u[..., 1] * v[2] - u[..., 2] * v[1]
    cy = u[..., 2] * v[0] - u[..., 0] * v[2]
    cz = u[..., 0] * v[1] - u[..., 1] * v[0]
    dot = u[..., 0] * v[0] + u[..., 1] * v[1] + u[..., 2] * v[2]
    return np.arctan2(np.sqrt(cx * cx + cy * cy + cz * cz), dot)


class _Pose:
    def __init__(self, ch, T):
        self.ch = ch
        F = ch.base_inv @ T @ ch.tool_inv  # frame 0 <- frame 7
        self.F = F
        self.p7, self.z7, self.R = F[:3, 3], F[:3, 2], F[:3, :3]

    def gaps(self, t5):
        """(gap (4, n), arm angles (4, n, 3), K/R (4, n)) at DH theta5 (n,)."""
        s, t, phi, _ = _wrist(self.ch, t5)
        P = self.p7[None, :] + t[:, None] * self.z7[None, :]
        th, kr = _arm(self.ch, P, self.ch.d4 + s)
        g = _angle(_z4(self.ch, th), self.z7) - phi[None, :]
        return g, th, kr


# ---------------------------------------------------------------------- completing a candidate
def _complete(ch, pose, th123, t5, q4_zero=False):
    """DH angles (7,) from the arm, theta5 and the orientation (theta4, theta7 by atan2)."""
    T = np.eye(4)
    thfull = [th123[0], th123[1], th123[2]]
    for i in range(3):
        T = T @ _link(ch.dh[i, 0], ch.dh[i, 1], thfull[i], ch.dh[i, 2])[0]
    al3 = ch.dh[3, 1]
    RX = _link(0.0, al3, 0.0, 0.0)[0, :3, :3]
    M = RX.T @ T[:3, :3].T @ pose.R  # = RotZ(t4) W RotZ(t7)
    *_, W = _wrist(ch, np.array([t5]))
    W = W[0]
    if math.hypot(W[0, 2], W[1, 2]) < 1e-12 or q4_zero:
        t4 = 0.0
        Mz = W.T @ M  # RotZ(t7) when t4 = 0 and the wrist is straight
        t7 = math.atan2(Mz[1, 0], Mz[0, 0])
    else:
        t4 = math.atan2(M[1, 2], M[0, 2]) - math.atan2(W[1, 2], W[0, 2])
        # last row: M[2, :] = W[2, :] RotZ(t7)
        t7 = math.atan2(W[2, 1], W[2, 0]) - math.atan2(M[2, 1], M[2, 0])
    return np.array([thfull[0], thfull[1], thfull[2], t4, t5, -t5, t7])


def _frames(ch, q):
    """World poses of frames 1..7 and of the tool for joints q (6,): (8, 4, 4)."""
    th = ch.theta(q[None])[0]
    out = np.empty((8, 4, 4))
    T = ch.base
    for i in range(7):
        T = T @ _link1(ch.dh[i, 0], ch.dh[i, 1], th[i], ch.dh[i, 2])
        out[i] = T
    out[7] = T @ ch.tool
    return out


def _residual_and_jacobian(ch, T, q):
    """The residual (position over the size, rotation entries) (12,) and its Jacobian (12, 6):
    joint i turns about z_i (times its sign), joint 6 follows q5 with the coupling's multiplier."""
    fr = _frames(ch, q)
    F = fr[7]
    res = np.concatenate([(F[:3, 3] - T[:3, 3]) / ch.size, (F[:3, :3] - T[:3, :3]).ravel()])
    z, o = fr[:7, :3, 2], fr[:7, :3, 3]
    Z = np.zeros((7, 3, 3))  # the cross-product matrices [z_i]x
    Z[:, 0, 1], Z[:, 0, 2], Z[:, 1, 2] = -z[:, 2], z[:, 1], -z[:, 0]
    Z[:, 1, 0], Z[:, 2, 0], Z[:, 2, 1] = z[:, 2], -z[:, 1], z[:, 0]
    dp = (Z @ (F[:3, 3] - o)[:, :, None])[:, :, 0] / ch.size
    dR = Z @ F[:3, :3]
    cols = ch.sign[:, None] * np.concatenate([dp, dR.reshape(7, 9)], axis=1)
    J = np.column_stack([cols[0], cols[1], cols[2], cols[3], cols[4] + ch.m * cols[5], cols[6]])
    return res, J


def _polish(ch, T, q):
    """Levenberg-Marquardt on the exact forward kinematics; None unless the pose is met (a start
    that meets it already is kept as it is)."""
    if _exact(ch, T, q):
        return _wrap(q)
    cache = {}

    def both(x):
        key = x.tobytes()
        if key not in cache:
            cache.clear()
            cache[key] = _residual_and_jacobian(ch, T, x)
        return cache[key]

    sol = least_squares(lambda x: both(x)[0], q, jac=lambda x: both(x)[1], method="lm", xtol=1e-15,
                        ftol=1e-15, gtol=1e-15, max_nfev=100)
    x = _wrap(sol.x)
    return x if _exact(ch, T, x) else None


def _exact(ch, T, q):
    F = _frames(ch, q)[7]
    dp = np.linalg.norm(F[:3, 3] - T[:3, 3])
    return bool(dp <= ch.tol and np.abs(F[:3, :3] - T[:3, :3]).max() <= 1e-12)


def _same(ch, a, b, merge, straight=1e-4):
    d = np.abs(_wrap(a - b))
    if d.max() <= merge:
        return True
    if abs(_wrap(a[4])) < straight and abs(_wrap(b[4])) < straight:  # straight: s4 q4 + s7 q7
        s4, s7 = ch.sign[3], ch.sign[6]
        tot = abs(_wrap(s4 * a[3] + s7 * a[5] - s4 * b[3] - s7 * b[5]))
        return max(d[[0, 1, 2, 4]].max(), tot) <= merge
    return False


# ---------------------------------------------------------------------- the scans
def _grid(ends, n=1500, depth=15):
    """A theta5 grid on [0, pi] graded toward 0, pi and every point of ``ends``."""
    g = [np.linspace(0.0, np.pi, n)]
    fine = 10.0 ** -np.linspace(1, depth, 6 * depth)
    g.append(fine)
    g.append(np.pi - fine)
    for e in ends:
        g.append(e + fine[fine < 0.05])
        g.append(e - fine[fine < 0.05])
    g = np.concatenate(g)
    return np.unique(np.clip(g, 0.0, np.pi))


def _branch_ends(pose, grid):
    """theta5 where an arm branch ends (|K / R| = 1: the elbow stretches; or rho = |b|), refined
    by brentq on K / R -+ 1 (continuous), else by bisection."""
    _, _, kr = pose.gaps(grid)
    ends = []
    for k in range(4):
        ok = np.isfinite(kr[k]) & (np.abs(kr[k]) <= 1)
        for i in np.flatnonzero(ok[:-1] != ok[1:]):
            a, b = grid[i], grid[i + 1]
            if np.isfinite(kr[k, i]) and np.isfinite(kr[k, i + 1]):
                one = math.copysign(1.0, kr[k, i] if not ok[i] else kr[k, i + 1])
                ends.append(brentq(lambda t, k=k, one=one: pose.gaps(np.array([t]))[2][k, 0] - one,
                                   a, b, xtol=1e-16, rtol=1e-15))
                continue
            fa = ok[i]
            for _ in range(60):
                m = 0.5 * (a + b)
                _, _, km = pose.gaps(np.array([m]))
                okm = bool(np.isfinite(km[k, 0]) and abs(km[k, 0]) <= 1)
                if okm == fa:
                    a = m
                else:
                    b = m
            ends.append(a if fa else b)
    return ends


def _theta5_candidates(pose, near=1e-2):
    """(branch, theta5) candidates of the theta5 scan: sign changes of the gap, and its dips,
    branch ends and range ends below ``near`` (rad)."""
    coarse = np.linspace(0.0, np.pi, 800)
    grid = _grid(_branch_ends(pose, coarse))
    g, _, _ = pose.gaps(grid)
    cands = []
    for k in range(4):
        gk = g[k]
        fin = np.isfinite(gk)
        for i in np.flatnonzero(fin[:-1] & fin[1:] & (gk[:-1] * gk[1:] <= 0)):
            f = lambda t, k=k: pose.gaps(np.array([t]))[0][k, 0]  # noqa: E731
            if gk[i] == 0:
                cands.append((k, grid[i]))
                continue
            if gk[i + 1] == 0:
                continue
            try:
                cands.append((k, brentq(f, grid[i], grid[i + 1], xtol=1e-16, rtol=1e-15)))
            except ValueError:
                pass
        # dips of |g| that come near zero (tangential roots, clusters) and values at the ends of
        # the branch (stretched elbow) or of the range (straight and fully bent wrist)
        ag = np.where(fin, np.abs(gk), np.inf)
        inner = np.flatnonzero((ag[1:-1] <= ag[:-2]) & (ag[1:-1] <= ag[2:]) & (ag[1:-1] < near)) + 1
        cands += [(k, grid[i]) for i in inner]
        edge = np.flatnonzero(fin & ~np.roll(fin, 1) | fin & ~np.roll(fin, -1))
        cands += [(k, grid[i]) for i in edge if ag[i] < near]
        for i in (0, len(grid) - 1):
            if ag[i] < near:
                cands.append((k, grid[i]))
    return cands


def _shoulder_candidates(pose, n=20000):
    """Candidates of the theta1 scan, for an arm without lateral offset whose line of virtual
    centres p7 + t z7 passes near axis 1: the arm's plane at theta1 (it contains axis 1) meets
    the line at one t, hence at one theta5 (t is monotone in theta5), and the gap becomes a
    function of theta1 alone (near the shoulder set theta1 swings through pi while theta5 hardly
    moves, which no theta5 grid resolves)."""
    ch = pose.ch
    if abs(ch.b) > 1e-9 * ch.size:
        return []
    p, z = pose.p7, pose.z7
    zz = z[0] ** 2 + z[1] ** 2
    if zz < 1e-18:
        return []
    tc = -(p[0] * z[0] + p[1] * z[1]) / zz
    if math.hypot(p[0] + tc * z[0], p[1] + tc * z[1]) > 1e-2 * ch.size:
        return []
    tgrid = np.linspace(0.0, np.pi, 20001)
    _, tw, _, _ = _wrist(ch, tgrid)
    fin = np.isfinite(tw)
    tgrid, tw = tgrid[fin], tw[fin]
    if tw[-1] < tw[0]:
        tgrid, tw = tgrid[::-1], tw[::-1]
    if not np.all(np.diff(tw) > 0):
        return []
    t1s = np.linspace(-np.pi, np.pi, n, endpoint=False)
    c1, s1 = np.cos(t1s), np.sin(t1s)
    zn = -z[0] * s1 + z[1] * c1
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (p[0] * s1 - p[1] * c1) / zn
    inside = np.isfinite(t) & (t >= tw[0]) & (t <= tw[-1])
    if not inside.any():
        return []
    t1s, c1, s1, t = t1s[inside], c1[inside], s1[inside], t[inside]
    t5 = np.interp(t, tw, tgrid)
    s, _, phi, _ = _wrist(ch, t5)
    P = p[None, :] + t[:, None] * z[None, :]
    r = P[:, 0] * c1 + P[:, 1] * s1 - ch.a1
    h = ch.eps1 * (P[:, 2] - ch.d1)
    L = ch.d4 + s
    R = np.hypot(ch.a3, L)
    gamma = np.arctan2(ch.eps3 * L, ch.a3)
    K = (r * r + h * h - ch.a2 ** 2 - ch.a3 ** 2 - L * L) / (2 * ch.a2)
    out = []
    for el in (1.0, -1.0):
        t3 = gamma + el * np.arccos(np.clip(K / R, -1, 1))
        X = ch.a2 + ch.a3 * np.cos(t3) + ch.eps3 * L * np.sin(t3)
        Y = ch.a3 * np.sin(t3) - ch.eps3 * L * np.cos(t3)
        t2 = np.arctan2(h, r) - np.arctan2(Y, X)
        th = np.column_stack([t1s, t2, t3])
        g = np.where(np.abs(K / R) <= 1, _angle(_z4(ch, th), z) - phi, np.nan)
        prod = g[:-1] * g[1:]
        for j in np.flatnonzero(np.isfinite(prod) & (prod <= 0)):
            out.append((th[j], t5[j]))
        ag = np.where(np.isfinite(g), np.abs(g), np.inf)
        for j in np.flatnonzero((ag[1:-1] <= ag[:-2]) & (ag[1:-1] <= ag[2:]) & (ag[1:-1] < 1e-2)) + 1:
            out.append((th[j], t5[j]))
    return out


def straight_wrist_close(robot, T):
    """Closed form at the straight wrist (DH theta5 = 0, idealised wrist): the four arm branches
    placing the virtual centre, kept where axis 4 is axis 7 (angle below 1e-6 rad); joints with
    q4 = 0 (only s4 q4 + s7 q7 is defined). Not polished."""
    ch = Chain(robot)
    pose = _Pose(ch, np.asarray(T, float))
    g, th, _ = pose.gaps(np.array([0.0]))
    out = []
    for k in range(4):
        if np.isfinite(g[k, 0]) and abs(g[k, 0]) < 1e-6:
            out.append(ch.joints(_complete(ch, pose, th[k, 0], 0.0, q4_zero=True)))
    return np.array(out).reshape(-1, 6)


def reference_ik(robot, T, merge=1e-6, extra_starts=None):
    """Every solution of the pose ``T`` (4, 4) of ``robot`` found by the reference: (M, 6)
    joints in (-pi, pi], each polished on the exact forward kinematics of the table as written
    and meeting min(1e-9, 1e-12 size) in position and 1e-12 in rotation; deduplicated.
    ``extra_starts`` (k, 6): more starts for the polish (for example, perturbed sources)."""
    ch = Chain(robot)
    T = np.asarray(T, float)
    pose = _Pose(ch, T)
    starts = []
    cands: list[tuple[int, float]] = []
    # a deviating model's exact solutions can be far from the idealised model's roots next to
    # the singular sets (0.016 rad in theta1 at the IRB 5400's straight wrist): wider nets
    deviating = bool(np.abs(ch.dh[4:7, :3] - ch.ideal[4:7, :3]).max() > 0)
    far = (3e-2, 5e-2) if deviating else (1e-3, 1e-2)
    for k, t5 in sorted(_theta5_candidates(pose, 5e-2 if deviating else 1e-2)):
        if cands and cands[-1][0] == k and abs(cands[-1][1] - t5) < 1e-8:
            continue  # graded grids next to the fold of a 45 deg twist (noise there)
        cands.append((k, t5))
    for k, t5 in cands:
        _, th, _ = pose.gaps(np.array([t5]))
        if np.all(np.isfinite(th[k, 0])):
            for sgn in (1.0, -1.0):
                full = _complete(ch, pose, th[k, 0], sgn * t5)
                starts.append(ch.joints(full))
                if deviating and abs(t5) < 1e-2:
                    # a (nearly) straight wrist of a deviating model: the exact model's axes 4
                    # and 7 are not collinear there, so the split of theta4 + theta7 is fixed,
                    # weakly: start from splits all round
                    for t4 in np.linspace(-np.pi, np.pi, 12, endpoint=False):
                        f = full.copy()
                        f[3], f[6] = full[3] + t4, full[6] - t4
                        starts.append(ch.joints(f))
    for th, t5 in _shoulder_candidates(pose):
        for sgn in (1.0, -1.0):
            starts.append(ch.joints(_complete(ch, pose, th, sgn * t5)))
    if extra_starts is not None:
        starts += list(np.atleast_2d(extra_starts))
    sols: list[np.ndarray] = []
    tried = np.empty((0, 6))
    for q0 in starts:
        if not np.all(np.isfinite(q0)) or any(_same(ch, q0, y, 1e-8) for y in sols):
            continue
        # starts within 1e-6 rad of one tried already (the graded grids give many next to the
        # fully bent wrist of a 45 deg twist, where the gap is within rounding of zero) add nothing
        if len(tried) and np.abs(_wrap(tried - q0)).max(axis=1).min() < 1e-6:
            continue
        tried = np.vstack([tried, q0])
        # a start far from the pose is spurious (a sign change of the gap within its rounding
        # next to the fold of a 45 deg twist): the scans' starts are within about the model's
        # deviation of an exact solution
        r = _residual_and_jacobian(ch, T, q0)[0]
        if np.abs(r[:3]).max() > far[0] or np.abs(r[3:]).max() > far[1]:
            continue
        x = _polish(ch, T, q0)
        if x is not None and not any(_same(ch, x, y, merge, 1e-9) for y in sols):
            sols.append(x)
    return np.array(sols).reshape(-1, 6)


# ---------------------------------------------------------------------- poses on the singular sets
#: The singular sets :func:`singular_joints` places joints on.
KINDS = ("straight", "near_straight", "bent", "stretched", "shoulder", "near_shoulder")


def singular_joints(robot, rng, kind, n):
    """Joints (n, 6) on (or near) a singular set of ``robot``, from the geometry above:

    * ``straight``: DH theta5 = 0 (axes 4 and 7 collinear); ``near_straight``: 1e-9 .. 1e-3 from it;
    * ``bent``: DH theta5 = pi (the fully bent wrist);
    * ``stretched``: DH theta3 = gamma or gamma + pi, the elbow's K / R = +-1 (``gamma`` of the
      virtual centre's distance L = d4 + s(theta5) and a3);
    * ``shoulder``: the virtual centre on axis 1 (arms without lateral offset), theta2 in closed
      form; ``near_shoulder``: at 1e-9 .. 1e-3 of the size from it. With a lateral offset b the
      same radial coordinate in the arm's plane (0, or 1e-9 .. 1e-3 of the size) places the centre
      on (or beside) the cylinder of radius abs(b) about axis 1, where the arm's two shoulder
      branches meet;
    * ``fold_axis`` (not in :data:`KINDS`; the hunts' ``--kinds fold_axis``): DH theta5 within
      1e-6 .. 1e-2 of pi (either side) and the approach (axis 7, in the base's frame) within
      1e-6 .. 3e-2 rad of axis 1, in a random direction: theta1 and theta2 solved for it by
      least squares from random joints (drawn again where that fails; with a 45 deg twist axis 7
      is (nearly) parallel to axis 4 there, so theta4 hardly turns the approach). Axes 1, 4 and 7
      are then (nearly) parallel.
    """
    ch = Chain(robot)
    th = rng.uniform(-np.pi, np.pi, (n, 7))
    if kind == "straight":
        th[:, 4] = 0.0
    elif kind == "near_straight":
        th[:, 4] = rng.choice([-1.0, 1.0], n) * 10.0 ** rng.uniform(-9, -3, n)
    elif kind == "bent":
        th[:, 4] = np.pi
    elif kind in ("stretched", "shoulder", "near_shoulder"):
        s, *_ = _wrist(ch, np.abs(th[:, 4]))
        L = ch.d4 + s
        gamma = np.arctan2(ch.eps3 * L, ch.a3)
        if kind == "stretched":
            th[:, 2] = gamma + np.pi * rng.integers(0, 2, n)
        else:
            delta = 0.0 if kind == "shoulder" else (rng.choice([-1.0, 1.0], n) * ch.size
                                                     * 10.0 ** rng.uniform(-9, -3, n))
            t3 = th[:, 2]
            X = ch.a2 + ch.a3 * np.cos(t3) + ch.eps3 * L * np.sin(t3)
            Y = ch.a3 * np.sin(t3) - ch.eps3 * L * np.cos(t3)
            # radial coordinate a1 + cos(t2) X - sin(t2) Y = delta
            c = np.clip((delta - ch.a1) / np.hypot(X, Y), -1.0, 1.0)
            th[:, 1] = -np.arctan2(Y, X) + rng.choice([-1.0, 1.0], n) * np.arccos(c)
    elif kind == "fold_axis":
        return np.array([_fold_axis_joints(ch, rng) for _ in range(n)])
    else:
        raise ValueError(f"kind must be one of {KINDS} or 'fold_axis'; got {kind!r}")
    th[:, 5] = -th[:, 4]
    return np.array([ch.joints(t) for t in th])


def _fold_axis_joints(ch, rng, attempts=50):
    """Joints (6,) of ``singular_joints``' ``fold_axis`` kind."""
    for _ in range(attempts):
        th = rng.uniform(-np.pi, np.pi, 7)
        th[4] = np.pi - rng.choice([-1.0, 1.0]) * 10.0 ** rng.uniform(-6, -2)
        th[5] = -th[4]
        tilt, phi = 10.0 ** rng.uniform(-6, -1.5), rng.uniform(-np.pi, np.pi)
        aim = tilt * np.array([np.cos(phi), np.sin(phi)])

        def off(x, th=th, aim=aim):
            t = th.copy()
            t[0], t[1] = x
            T = ch.base_inv @ ch.fk(ch.joints(t)[None])[0] @ ch.tool_inv
            return T[:2, 2] - aim

        fit = least_squares(off, th[[0, 1]], xtol=1e-15, ftol=1e-15, gtol=1e-15)
        if np.abs(fit.fun).max() <= 1e-12:
            th[0], th[1] = fit.x
            return ch.joints(th)
    raise RuntimeError("no joints with the approach along axis 1 found")


def answered_twice(robot, sols, T):
    """Pairs (i, j) of answers ``sols`` of the pose ``T`` that are one solution: the later among
    the earlier by :func:`among`."""
    return [(i, j) for i in range(len(sols)) for j in range(i) if among(robot, sols[j:j + 1], sols[i], T)]


def among(robot, sols, q, T, tol=1e-6, reach=1e-2):
    """Whether joints ``q`` (a solution of the pose ``T``) are one solution with an answer of
    ``sols`` (M, 6). Every joint counts; only a path of poses met within the tolerance joins two
    joint vectors that differ by more than ``tol`` rad. In order:

    1. an answer within ``tol`` rad in every joint;
    2. at a straight wrist (both DH theta5 within 1e-4 of 0) an answer with q1, q2, q3, q5 and
       ``s4 q4 + s7 q7`` within ``tol``, when the split turned from ``q``'s to the answer's (q4
       turned, q7 back by the same: 9 points with ``q``'s other joints, then half way on to the
       answer) meets the pose: on the idealised family the split of an exactly straight wrist is
       free, but on a model that deviates from it (or with the wrist bent at all) the pose may
       fix it, and then the sum alone would pass another solution (where the wrist is bent at
       all, the arm may have to follow the turn: then the path of least pose error of 4.);
    3. an answer less than ``reach`` rad away (every joint) joined to ``q`` by a segment whose 9
       points meet the pose (where the forward kinematics is flat to high order an exact
       solution is a valley of poses equal within the tolerance, and any point of it is that
       solution);
    4. the same answer joined by the path of least pose error (:func:`least_error_path_meets`),
       for valleys that curve away from the segment.

    Every pose is computed with this module's forward kinematics."""
    sols = np.asarray(sols).reshape(-1, 6)
    if len(sols) == 0:
        return False
    d = np.abs(_wrap(sols - q))
    if d.max(axis=1).min() <= tol:
        return True
    ch = Chain(robot)
    for s in sols[_straight_matches(ch, sols, q, tol)]:
        turn = _wrap(s[3] - q[3])  # q4 turned, q7 back by the same (s4 q4 + s7 q7 kept)
        path = np.repeat(q[None], 10, axis=0)
        path[:9, 3] += np.linspace(0.0, 1.0, 9) * turn
        path[:9, 5] -= ch.sign[6] * ch.sign[3] * np.linspace(0.0, 1.0, 9) * turn
        path[9] = path[8] + 0.5 * _wrap(s - path[8])  # then on to the answer (within tol)
        if _meets(ch, T, s[None]) and (_meets(ch, T, path) or least_error_path_meets(robot, T, q, s)):
            return True
    k = int(np.argmin(d.max(axis=1)))
    step = _wrap(sols[k] - q)
    if np.abs(step).max() >= reach:
        return False
    return (_meets(ch, T, q + np.linspace(0.0, 1.0, 9)[:, None] * step)
            or least_error_path_meets(robot, T, q, sols[k]))


def _straight_matches(ch, sols, q, tol, straight=1e-4):
    """Which answers match ``q`` at a straight wrist (DH theta5 within ``straight`` of 0) in q1,
    q2, q3, q5 and the sum s4 q4 + s7 q7."""
    if abs(_wrap(ch.theta(q)[0, 4])) >= straight:
        return np.zeros(len(sols), bool)
    rest = np.abs(_wrap(sols[:, [0, 1, 2, 4]] - q[[0, 1, 2, 4]])).max(axis=1)
    s4, s7 = ch.sign[3], ch.sign[6]
    total = np.abs(_wrap(s4 * (sols[:, 3] - q[3]) + s7 * (sols[:, 5] - q[5])))
    return (np.abs(_wrap(ch.theta(sols)[:, 4])) < straight) & (np.maximum(rest, total) <= tol)


def _meets(ch, T, Q):
    """Whether every joint vector of ``Q`` (n, 6) meets the pose ``T`` (position: the robot's
    tolerance plus the rounding of two FK products; rotation: 1e-12)."""
    F = ch.fk(Q)
    dp = np.linalg.norm(F[:, :3, 3] - T[:3, 3], axis=-1)
    dr = np.abs(F[:, :3, :3] - T[:3, :3]).max(axis=(1, 2))
    return bool(np.all(dp <= ch.tol + 1e-12 * max(1.0, ch.size / 1e3)) and np.all(dr <= 1e-12))


def least_error_path_meets(robot, T, a, b, steps=20):
    """Whether the exact joint vectors ``a`` and ``b`` are one solution along the path of least
    pose error between them: the joint of their largest difference stepped from one to the other
    in ``steps`` steps, the five others by Levenberg-Marquardt (scipy, on this module's residual
    and Jacobian) converged from the point before; every point must meet the pose. Where the
    least squares of the residual (position over the size) does not meet it, the least squares
    of the errors over their tolerances is tried from there as well: the first trades position
    for rotation at about twice the tolerances' rate, and a rounded member's valley, whose
    points within both tolerances a walk joins, peaked at 1.07 times the position tolerance."""
    ch = Chain(robot)
    a, b = np.asarray(a, float), np.asarray(b, float)
    j = int(np.argmax(np.abs(_wrap(b - a))))
    free = [i for i in range(6) if i != j]
    # the residual's rows over the tolerances: position (over the size) by tol / size, rotation 1e-12
    scale = np.r_[np.full(3, ch.size / ch.tol), np.full(9, 1e12)]
    x = a.copy()
    for v in a[j] + np.linspace(0.0, 1.0, steps + 1)[1:-1] * _wrap(b[j] - a[j]):
        x[j] = v
        for w in (np.ones(12), scale):
            def both(z, x=x, w=w):
                y = x.copy()
                y[free] = z
                r, J = _residual_and_jacobian(ch, T, y)
                return w * r, w[:, None] * J[:, free]

            x[free] = least_squares(lambda z: both(z)[0], x[free], jac=lambda z: both(z)[1],
                                    method="lm", xtol=1e-15, ftol=1e-15, gtol=1e-15).x
            if _meets(ch, T, x[None]):
                break
        else:
            return False
    return True


def exact(robot, sols, T, margin=1e-12):
    """Position errors (M,) and rotation errors (M,) of ``sols`` (M, 6) against ``T`` (one pose,
    or one per solution) on this module's forward kinematics,
    and whether each meets the robot's tolerance min(1e-9, 1e-12 size) (plus ``margin`` for two
    products that round differently) and 1e-12 in rotation plus 1e-15."""
    ch = Chain(robot)
    F = ch.fk(np.asarray(sols).reshape(-1, 6))
    T = np.asarray(T)  # one pose (4, 4), or one per solution (M, 4, 4)
    dp = np.linalg.norm(F[:, :3, 3] - T[..., :3, 3], axis=-1)
    dr = np.abs(F[:, :3, :3] - T[..., :3, :3]).max(axis=(1, 2))
    return dp, dr, (dp <= ch.tol + margin) & (dr <= 1e-12 + 1e-15)


# ---------------------------------------------------------------------- family members
def family_member(rng, beta_deg=None, lateral=True, rounded=False):
    """A random DH table (7, 4) of the family (mm, rad): shoulder offset a1, upper arm a2, elbow
    offset a3, lateral offset d2 + d3 (when ``lateral``), base height d1, forearm d4, wrist
    twists (-beta, 2 beta, -beta) with beta in [15, 45] deg (or ``beta_deg``), d5 = d6, flange d7,
    alpha1 and alpha3 of either sign. ``rounded``: lengths rounded to 1 mm and angles to 0.01 deg,
    as a published datasheet gives them (2 beta rounded is then not twice beta rounded: the
    wrist deviates from the mirror)."""
    beta = math.radians(rng.uniform(15.0, 45.0) if beta_deg is None else beta_deg)
    e1, e3 = rng.choice([-1.0, 1.0], 2)
    b2 = rng.uniform(-150, 150) if lateral else 0.0
    b3 = rng.uniform(-150, 150) if lateral else -b2
    dw = rng.uniform(60, 150)
    dh = np.array([
        [0.0, 0.0, rng.uniform(0, 900), 0.0],
        [rng.uniform(0, 400), e1 * np.pi / 2, b2, 0.0],
        [rng.uniform(700, 1400), 0.0, b3, 0.0],
        [rng.uniform(0, 250), e3 * np.pi / 2, rng.uniform(700, 1500), 0.0],
        [0.0, -beta, dw, 0.0],
        [0.0, 2 * beta, dw, 0.0],
        [0.0, -beta, rng.uniform(20, 200), 0.0],
    ])
    if rounded:
        dh[:, [0, 2]] = np.round(dh[:, [0, 2]])
        dh[:, 1] = np.radians(np.round(np.degrees(dh[:, 1]), 2))
    return dh
