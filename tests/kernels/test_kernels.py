"""The compiled kernels' fast forms against their plain definitions.

The solver samples the residual in SIMD loops and carries joint angles as cosine and sine
pairs; these tests check each fast form against the definition it replaces (and the wrist
against its forward rotation), on the paper robot and on a robot with every offset.
"""

import math

import numpy as np
import pytest
from helpers import wrap
from reference_ik import Chain, _Pose, reference_fk

import ik7r
from ik7r._kernels import answers as _answers
from ik7r._kernels import complete as _complete
from ik7r._kernels import constants as _constants
from ik7r._kernels import fk as _kin
from ik7r._kernels import gaps as _gaps
from ik7r._kernels import joints as _joints
from ik7r._kernels import params as _layout
from ik7r._kernels import poly as _poly
from ik7r._kernels import reduced as _reduced
from ik7r._kernels import scans as _scans
from ik7r._kernels import wrist as _wrist
from ik7r.geometry.configs import config_number
from ik7r.robot import Robot

OFFSETS_TOML = """
name = "offsets"
unit = "mm"
[dh]
a = [0, 300, 1200, 186, 0, 0, 0]
alpha = [0, -90, 0, -90, 35, -70, 35]
d = [660, 40, -15, 1400, 79, 79, 82]
theta_offset = [0, -90, 10, 0, 0, 0, 0]
[limits]
lower = [-150, -80, -75, -340, -180, -340]
upper = [150, 80, 75, 340, 180, 340]
"""


@pytest.fixture(scope="module")
def robots(tmp_path_factory):
    path = tmp_path_factory.mktemp("robots") / "offsets.toml"
    path.write_text(OFFSETS_TOML)
    return {"paper": ik7r.load_robot(), "offsets": ik7r.load_robot(path)}


def _approach(rng):
    a = rng.normal(size=3)
    return a / np.linalg.norm(a)


@pytest.mark.parametrize("name", ["paper", "offsets"])
def test_sampled_residual_equals_its_definition(robots, name):
    """The SIMD sampling inside the root isolation gives the residual of ``residual_of`` at
    every Chebyshev point, including points where the shoulder branches are complex
    (``Px^2 + Py^2 < b^2``, completed outside the SIMD loop)."""
    robot = robots[name]
    K = robot.kernel_params
    Bm, bnorm = _poly.bernstein_tables(robot.kernel_params)
    n = Bm.shape[0] - 1
    rng = np.random.default_rng(11)
    lo, hi = _complete._interval(K)
    complex_seen = 0
    for k in range(200):
        a = _approach(rng)
        # half the poses put the virtual centre within the lateral offset of axis 1
        p = rng.uniform(-2000, 2000, 3) if k % 2 else np.array([0.0, 0.0, 1200.0]) + 200 * a
        b, vals, mags = np.empty(n + 1), np.empty(n + 1), np.empty(n + 1)
        u0, u1 = sorted(rng.uniform(lo, hi, 2)) if k % 3 else (lo, hi)
        _poly._bernstein(0, u0, u1, p, a, K, Bm, bnorm, b, vals, mags)
        for j in range(n + 1):
            u = 0.5 * (u0 + u1) + 0.5 * (u1 - u0) * math.cos(math.pi * j / n)
            v, m = _poly.residual_of(0, u, p, a, K)
            assert m >= 0.0 and mags[j] == pytest.approx(m, rel=1e-12)
            assert abs(vals[j] - v) <= 1e-12 * m
            d = K[_layout.KW] / u
            t = K[_layout.D7] + d
            px, py = p[0] - t * a[0], p[1] - t * a[1]
            complex_seen += px * px + py * py < K[_layout.B] ** 2
        np.testing.assert_allclose(b, Bm @ vals, rtol=0, atol=1e-12 * bnorm * mags.max())
    if name == "offsets":
        assert complex_seen > 0  # the completion outside the SIMD loop was exercised


def test_theta5_cosine_and_sine_from_the_half_angle(robots):
    K = robots["paper"].kernel_params
    d = np.linspace(K[_layout.KW], K[_layout.DMAX], 1001)
    for dk in d:
        t5, c5, s5 = _wrist.theta5_cs_of_d(dk, K)
        assert t5 == _wrist.theta5_of_d(dk, K)
        # a few ulps, amplified towards the fold as both come from sin(t5 / 2) close to 1
        tol = 4e-16 / max(math.cos(0.5 * t5), 1e-3)
        assert abs(c5 - math.cos(t5)) < tol and abs(s5 - math.sin(t5)) < tol
        assert _wrist.d_of_theta5(t5, K) == pytest.approx(dk, rel=1e-12)


@pytest.mark.parametrize("name", ["paper", "offsets"])
def test_wrist_from_cosine_and_sine_inverts_the_wrist_rotation(robots, name):
    """``Q = RotZ(t4) W(t5) RotZ(t7)`` built forward is solved back to (t4, t7)."""
    K = robots[name].kernel_params
    rng = np.random.default_rng(5)
    W = np.empty((3, 3))
    for _ in range(500):
        t4, t7 = rng.uniform(-np.pi, np.pi, 2)
        t5 = rng.choice([-1.0, 1.0]) * rng.uniform(1e-3, np.pi - 1e-3)
        _wrist.wrist_rotation(t5, K, W)
        Q = _rot_z(t4) @ W @ _rot_z(t7)
        g4, g7 = _wrist.wrist_ik_cs(Q, math.cos(t5), math.sin(t5), 0.0, K, np.empty((3, 3)))
        assert abs(_constants.wrap(g4 - t4)) < 1e-9 and abs(_constants.wrap(g7 - t7)) < 1e-9


def _rot_z(t):
    c, s = math.cos(t), math.sin(t)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


@pytest.mark.parametrize("name", ["paper", "offsets"])
def test_indicator_from_cosine_and_sine(robots, name):
    """The configuration filter's test on (cos, sin) of a DH angle agrees with the indicator
    of the user angle (configs.config_number) away from its boundaries."""
    K = robots[name].kernel_params
    rng = np.random.default_rng(9)
    margin = 1e-3
    for theta in rng.uniform(-2 * np.pi, 2 * np.pi, 2000):
        for i in (0, 2):  # joint 1 (Arm) and joint 3 (Elbow)
            q = np.zeros(6)
            q[i] = (theta - K[_layout.DH + 4 * i + 3]) * K[_layout.SIGN + i]
            near = abs(abs(_constants.wrap(q[i])) - math.pi / 2) < 2 * margin
            # configuration 1 is Arm 1, Elbow 1; Arm is the 4s bit, Elbow the 2s bit
            bit = 4 if i == 0 else 2
            indicator = 1 - ((config_number(q) - 1) & bit) // bit
            for asked in (0, 1):
                got = _joints.may_match(i, math.cos(theta), math.sin(theta), asked, margin, K)
                if near:
                    assert got or asked != indicator
                else:
                    assert got == (asked == indicator)


def test_sincos_within_an_ulp_of_the_c_library():
    """The forward kinematics' own sine and cosine, against ``math`` over the angles joints
    take (and beyond), at the quadrant boundaries and at special values."""
    rng = np.random.default_rng(13)
    xs = np.concatenate([
        rng.uniform(-4.0, 4.0, 20000),
        rng.uniform(-1e4, 1e4, 5000),
        np.arange(-16, 17) * (math.pi / 4),  # quadrant boundaries and their halves
        np.nextafter(np.arange(-8, 9) * (math.pi / 2), np.inf),
        [0.0, -0.0, 1e-300, -1e-300, 99999.9, -99999.9, 1e5, 3e8],
    ])
    for x in xs:
        c, s = _kin.sincos(x)
        assert abs(c - math.cos(x)) <= 2.3e-16 and abs(s - math.sin(x)) <= 2.3e-16, x
    for x in (math.inf, -math.inf, math.nan):
        assert all(math.isnan(v) for v in _kin.sincos(x))


def test_rotation_log_inverts_the_exponential_up_to_pi():
    """The polish's rotation error: exp(log R) = R, including angles at and near pi."""
    from scipy.spatial.transform import Rotation

    rng = np.random.default_rng(17)
    axes = rng.normal(size=(400, 3))
    axes /= np.linalg.norm(axes, axis=1)[:, None]
    angles = np.concatenate([rng.uniform(0, np.pi, 200), np.pi - np.geomspace(1e-3, 1e-12, 100),
                             np.full(100, np.pi)])
    w = np.empty(3)
    for axis, angle in zip(axes, angles):
        R = Rotation.from_rotvec(angle * axis).as_matrix()
        _kin.rotation_log(R, w)
        assert np.linalg.norm(w) <= np.pi + 1e-12
        np.testing.assert_allclose(Rotation.from_rotvec(w).as_matrix(), R, atol=1e-9)


@pytest.mark.parametrize(("lo", "hi"), [(0.0, 1.0), (1.0, 0.0)])
def test_brent_minimiser_takes_its_bracket_in_either_order(lo, hi):
    """A reduced scan toward smaller values hands Brent's minimiser its bracket high end first:
    it must find the same least point (0.3 of a parabola, to its tolerance) as the other way
    round (its stopping test took the reversed bracket as done at the first point, 0.618)."""
    st, u = _poly.brent_start(lo, hi)
    for _ in range(200):
        st = _poly.brent_take(st, u, (u - 0.3) ** 2)
        st, u, done = _poly.brent_next(st)
        if done:
            break
    assert done
    assert abs(st[2] - 0.3) <= 1e-6


@pytest.mark.parametrize(("roots", "floor", "dips"), [
    ((0.06, 0.92), 0.0, True),  # (two roots in the first cell)
    ((0.5, 0.5), 0.0, True),  # (a tangency inside it)
    ((0.5, 0.5), 0.2, True),  # (down to 0.2 from 0.45 at both ends: below half)
    ((0.5, 0.5), 1.0, False),  # (a shallow bottom, 1.0 against 1.25)
    ((-0.5, -0.5), 0.1, False),  # (its bottom before the first point)
    ((1.3, 1.3), 0.0, False),  # (its bottom in the second cell: dips_to_zero's)
    ((-2.0, 4.0), 0.0, False),  # (its bottom at the second point, far below zero: no dip here)
])
@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_first_cell_dip_of_a_parabola(roots, floor, dips, sign):
    """``reduced.first_cell_dips`` on a parabola ``sign ((x - r1) (x - r2) + floor)`` sampled at
    x = 0, 1, 2 (a scan's first three points), against where its bottom is (written here): a dip
    inside the first cell (0 < x < 1) that comes down to half of its lesser end or beyond zero."""
    x = np.array([0.0, 1.0, 2.0])
    r = sign * ((x - roots[0]) * (x - roots[1]) + floor)
    assert (r[0] * r[1] > 0.0) or not dips  # (a first cell without a sign change)
    bottom_x = 0.5 * (roots[0] + roots[1])
    bottom = sign * (floor - 0.25 * (roots[1] - roots[0]) ** 2)
    expected = 0.0 < bottom_x < 1.0 and (abs(bottom) < 0.5 * min(abs(r[0]), abs(r[1])) or bottom * r[0] <= 0)
    assert expected == dips
    assert _reduced.first_cell_dips(r[0], r[1], r[2]) == dips


@pytest.mark.parametrize("undefined", [np.inf, np.nan])
@pytest.mark.parametrize("edge", [0.05, 0.2, 0.45, 0.7])
def test_brent_minimiser_where_the_function_is_undefined(edge, undefined):
    """Brent's minimiser (``poly.brent_*``, shared by every bracket's minimiser) on a function
    that is undefined below ``edge`` (``+inf``, or NaN as a residual with an imaginary square
    root gives): it finds the least value, on a grid written here, and its plain-Python form
    raises no floating-point warning (it used to make a parabola through the undefined points,
    ``inf - inf``, and a NaN first value stopped it there)."""
    import warnings

    def f(x):
        # numpy scalars, as the kernels' values are (Python floats give nan without a warning)
        return np.float64(undefined if x < edge else (x - 0.3) ** 2 + 0.01 * math.sin(9.0 * x))

    start = getattr(_poly.brent_start, "py_func", _poly.brent_start)
    take = getattr(_poly.brent_take, "py_func", _poly.brent_take)
    step = getattr(_poly.brent_next, "py_func", _poly.brent_next)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with np.errstate(all="raise"):
            st, u = start(np.float64(0.0), np.float64(1.0))
            for _ in range(200):
                st = take(st, u, f(u))
                st, u, done = step(st)
                if done:
                    break
    grid = np.linspace(edge, 1.0, 200_001)
    values = np.array([f(x) for x in grid])
    assert np.isfinite(values).all()
    assert done
    # (its tolerance is 2e-9 of the bracket in x, and the slope at most 1 here)
    assert st[5] <= values.min() + 1e-8, (st[2], grid[values.argmin()])
    assert abs(st[2] - grid[values.argmin()]) < 1e-4


@pytest.mark.parametrize("name", ["paper", "irb5400"])
def test_a_nan_candidate_is_never_accepted(name):
    """``answers.accept`` (the one gate every candidate passes before it is appended) refuses a
    candidate whose forward kinematics is NaN, on an exact and on a deviating model: a NaN
    residual compares false with the tolerance both ways, so the test must ask "within", not
    "beyond". A regular candidate of the same pose is accepted (the gate is not shut)."""
    robot = ik7r.load_robot() if name == "paper" else ik7r.load_robot("irb5400")
    K = robot.kernel_params
    q0 = np.array([0.3, 0.4, -0.2, 0.5, 0.7, -0.6])
    Td = np.ascontiguousarray(robot.fk(q0))
    ws = np.zeros(_constants.WORK_SIZE)
    mats = ws[_constants.W_MATS:_constants.W_MATS + _constants.NMATS * 16].reshape((_constants.NMATS, 4, 4))
    out = np.zeros((_layout.MAX_SOLUTIONS, 6))
    for bad in range(6):
        q = q0.copy()
        q[bad] = np.nan
        count, exact = _answers.accept(q, Td, K, out, 0, mats, False, False)
        assert (count, exact) == (0, False), bad
    count, exact = _answers.accept(q0.copy(), Td, K, out, 0, mats, False, False)
    assert (count, exact) == (1, True)
    assert np.abs(_constants.wrap(out[0] - q0)).max() < 1e-12


def _gap_poses(name, seed, n):
    """(K, p, a, th) of ``n`` uniform poses of the robot ``name`` (seed ``seed``): the kernel
    parameters, the pose's point and approach in frame 0 as the gaps take them, a work array."""
    robot = ik7r.load_robot() if name == "paper" else ik7r.load_robot(name)
    K = robot.kernel_params
    Q = np.random.default_rng(seed).uniform(-np.pi, np.pi, (n, 6))
    T07 = np.empty((4, 4))
    th = np.empty(_constants.NTH)
    for Td in robot.fk(Q):
        _complete.frame07(Td, K, T07)
        yield K, T07[:3, 3].copy(), T07[:3, 2] / np.linalg.norm(T07[:3, 2]), th


@pytest.mark.parametrize("name", ["paper", "irb5400"])
def test_gap_dips_stop_early_only_far_from_zero(name):
    """The early stop of the dips' minimiser (``DIP_FLOOR``, ``DIP_EARLY``) on the theta5 gap:
    over every dip of its grid on [0, pi] (all four arm branches, 150 poses), a dip stopped
    early would not have come down to SHOULDER_DIP (the largest threshold a dip's bottom is
    compared with) if minimised to the end; and the stop does save work on some dips."""
    m = _constants.SCAN_GRID
    grid = np.linspace(0.0, np.pi, m + 1)
    stopped = 0
    for K, p, a, th in _gap_poses(name, 5, 150):
        for front in (1.0, -1.0):
            for elbow in (1.0, -1.0):
                g = np.array([abs(v) if ok else np.inf
                              for v, ok in (_gaps.gap(t, p, a, front, elbow, K, th) for t in grid)])
                for i in range(1, m):
                    if not (np.isfinite(g[i - 1:i + 2]).all() and g[i] < g[i - 1] and g[i] <= g[i + 1]):
                        continue
                    full = _gaps.gap_min(grid[i - 1], grid[i + 1], p, a, front, elbow, K, th, 0.0)
                    early = _gaps.gap_min(grid[i - 1], grid[i + 1], p, a, front, elbow, K, th,
                                               _constants.DIP_FLOOR)
                    assert early[1] >= full[1]
                    if early != full:
                        stopped += 1
                        assert early[1] >= _constants.DIP_FLOOR
                        assert full[1] >= _constants.SHOULDER_DIP, (p, a, front, elbow, i, full)
    assert stopped > 0


_LATERAL_MEMBER = [[0.0, 0.0, 68.0, 0.0], [261.0, -math.pi / 2, -36.0, 0.0], [1121.0, 0.0, -112.0, 0.0],
                   [6.0, math.pi / 2, 1159.0, 0.0], [0.0, -0.5468116546498234, 75.0, 0.0],
                   [0.0, 1.0937978422248464, 75.0, 0.0], [0.0, -0.5468116546498234, 194.0, 0.0]]


@pytest.mark.parametrize("name", ["irb5400", "lateral"])
def test_reach_excess_is_the_references_elbow_cosine(name):
    """``reach_excess`` (how far the elbow is beyond its reach, from which the near-miss scan
    finds an arm branch's islands) is ``|K / R| - 1`` of the reference's closed-form arm
    (``reference_ik._arm``, sharing no code with the kernels) for each shoulder branch, on a
    grid of theta5 over [0, pi] for 40 uniform poses of the IRB 5400 and of a rounded member
    with lateral offsets; where it is clear of zero its sign is whether the branch reaches
    (``gap_reaches``); both signs occur."""
    robot = (ik7r.load_robot("irb5400") if name == "irb5400"
             else Robot(name="lateral", dh=np.array(_LATERAL_MEMBER)))
    K = robot.kernel_params
    ch = Chain(robot)
    grid = np.linspace(0.0, np.pi, 33)
    T07 = np.empty((4, 4))
    th = np.empty(_constants.NTH)
    signs = set()
    for Td in robot.fk(np.random.default_rng(41).uniform(-np.pi, np.pi, (40, 6))):
        _complete.frame07(Td, K, T07)
        p, a = T07[:3, 3].copy(), T07[:3, 2] / np.linalg.norm(T07[:3, 2])
        _, _, kr = _Pose(ch, Td).gaps(grid)
        for front, row in ((1.0, kr[0]), (-1.0, kr[2])):
            e = np.array([_gaps.reach_excess(t, p, a, front, K) for t in grid])
            ok = np.isfinite(row)  # (the reference leaves K / R undefined inside the offset's cylinder)
            np.testing.assert_allclose(e[ok], np.abs(row[ok]) - 1.0, rtol=0.0, atol=1e-9)
            for t, v in zip(grid[ok], e[ok]):
                if abs(v) > 1e-9:
                    assert _gaps.gap_reaches(t, p, a, front, 1.0, K, th) == (v < 0.0), (front, t, v)
                    signs.add(v < 0.0)
    assert signs == {True, False}


@pytest.mark.parametrize("name", ["paper", "irb5400"])
def test_gap_reaches_is_the_gaps_ok(name):
    """``gap_reaches`` (the cheap predicate of the bisections for arm branch ends) is the ``ok``
    of ``_gap`` itself, on a grid of each bend gap (theta5 on [0, pi], theta1 on the whole turn)
    and at every midpoint of a bisection for a branch end of that grid (where the two differ
    only in the last bits, if at all); both values occur."""
    seen = set()
    ends = 0
    for K, p, a, th in _gap_poses(name, 11, 60):
        for front, lo, hi in ((1.0, 0.0, np.pi), (-1.0, 0.0, np.pi), (0.0, -np.pi, np.pi)):
            for elbow in (1.0, -1.0):
                grid = np.linspace(lo, hi, 65)

                def both(t, K=K, p=p, a=a, th=th, front=front, elbow=elbow):
                    ok = _gaps.gap(t, p, a, front, elbow, K, th)[1]
                    assert _gaps.gap_reaches(t, p, a, front, elbow, K, th) == ok, (front, elbow, t)
                    seen.add(ok)
                    return ok

                oks = [both(t) for t in grid]
                for i in range(64):
                    if oks[i] == oks[i + 1]:
                        continue
                    ends += 1
                    t_in, t_out = (grid[i], grid[i + 1]) if oks[i] else (grid[i + 1], grid[i])
                    for _ in range(60):
                        tm = 0.5 * (t_in + t_out)
                        if tm in (t_in, t_out):
                            break
                        if both(tm):
                            t_in = tm
                        else:
                            t_out = tm
    assert seen == {True, False} and ends > 0


def _weighted_error(robot, q, Td):
    """The pose error of ``q`` as the reduced residual takes it (position over the robot's size,
    then the world rotation vector taking the pose to ``Td``), from the public FK and scipy."""
    from scipy.spatial.transform import Rotation

    T = robot.fk(q)
    rot = Rotation.from_matrix(Td[:3, :3] @ T[:3, :3].T).as_rotvec()
    return np.concatenate([(Td[:3, 3] - T[:3, 3]) / robot.kernel_params[_layout.SCALE], rot])


def test_reduced_residual_against_a_converged_least_squares():
    """The straight-wrist scan's reduced residual (``_reduced_at``: Gauss-Newton on five joints
    with one fixed, stopped before a step below REDUCED_SETTLE) against a least-squares point
    converged to the end by scipy (finite differences, its own pose error): the residual norm
    it returns is the converged one, and its determinant ``det [J_other | e]`` is the one at
    the converged point, on the IRB 5400 near straight wrists (where the scan runs), on both
    sides of exact solutions."""
    from scipy.optimize import least_squares

    robot = ik7r.load_robot("irb5400")
    K = robot.kernel_params
    rng = np.random.default_rng(4)
    work = [np.empty((4, 4)), np.empty((6, 6)), np.empty((6, 6)), np.empty(6), np.empty(6),
            np.empty(6), np.empty((7, 6))]
    signs = set()
    free = [0, 1, 2, 4, 5]
    for _ in range(20):
        src = rng.uniform(-np.pi, np.pi, 6)
        src[4] = rng.uniform(-1e-3, 1e-3)
        Td = robot.fk(src)
        v = src[3] + rng.uniform(-0.3, 0.3)
        q = src.copy()
        q[:3] += rng.uniform(-1e-3, 1e-3, 3)  # (a start like the scan's: the arm near, q5 near 0)
        r, norm, ok = _reduced._reduced_at(q, 3, v, Td, K, *work)
        assert ok

        def err(x, v=v, Td=Td):
            qq = np.empty(6)
            qq[free] = x
            qq[3] = v
            return _weighted_error(robot, qq, Td)

        fit = least_squares(err, q[free], xtol=1e-15, ftol=1e-15, gtol=1e-15, method="lm")
        ref_norm = np.linalg.norm(fit.fun)
        assert abs(norm - ref_norm) <= 10 * _constants.REDUCED_SETTLE ** 2, (norm, ref_norm)
        assert np.abs(q[free] - fit.x).max() < 1e-4
        qls = src.copy()
        qls[free] = fit.x
        qls[3] = v
        J = np.empty((6, 6))
        _kin.jacobian(qls, K, J)
        J[:3] /= K[_layout.SCALE]
        A = J.copy()
        A[:, 3] = fit.fun
        ref = np.linalg.det(A)
        assert abs(r - ref) <= 1e-5 * abs(ref) + 1e-15, (r, ref)
        signs.add(np.sign(ref))
    assert signs == {-1.0, 1.0}


def test_least_squares_step_is_numpys_least_squares_in_five_joints():
    """``_least_squares_step`` (the reduced residual's Gauss-Newton step, by Cholesky on the
    normal equations) against numpy's least squares of the five other columns (an SVD), on
    Jacobians of the IRB 5400 from regular to near its singular sets and on random matrices
    with columns scaled over 1e-3 .. 1e3; below the caller's 1e-15 (singular) for a
    rank-deficient one."""
    robot = ik7r.load_robot("irb5400")
    K = robot.kernel_params
    rng = np.random.default_rng(21)
    A = np.empty((6, 6))
    g = np.empty(6)
    dq = np.empty(6)
    for k in range(300):
        if k % 2:
            J = rng.normal(size=(6, 6)) * 10.0 ** rng.uniform(-3, 3, 6)
        else:
            q = rng.uniform(-np.pi, np.pi, 6)
            q[4] = 10.0 ** rng.uniform(-6, 0)  # (nearly straight to bent wrists)
            J = np.empty((6, 6))
            _kin.jacobian(q, K, J)
            J[:3] /= K[_layout.SCALE]
        e = rng.normal(size=6)
        j = int(rng.integers(6))
        others = [c for c in range(6) if c != j]
        rel = _reduced._least_squares_step(J, e, j, A, g, dq)
        Jo = J[:, others]
        ref = np.linalg.lstsq(Jo, e, rcond=None)[0]
        sv = np.linalg.svd(Jo, compute_uv=False)
        assert rel > 0.0 and dq[j] == 0.0
        # (the normal equations' error grows as the square of the condition number)
        tol = 1e-13 * (sv[0] / sv[-1]) ** 2
        assert np.abs(dq[others] - ref).max() <= tol * np.abs(ref).max(), (k, sv[0] / sv[-1])
    J[:, 2] = 2.0 * J[:, 1]
    assert _reduced._least_squares_step(J, e, 0, A, g, dq) < 1e-15


def test_polish_settle_stops_unverified_next_to_the_solution():
    """``polish`` with ``settle``: it stops after the first Newton step below ``settle`` and
    says False (nothing verified), leaving an error of the order of that step squared; without
    it the same start is verified (True) to the tolerance."""
    robot = ik7r.load_robot("irb5400")
    K = robot.kernel_params
    rng = np.random.default_rng(8)
    for _ in range(20):
        src = rng.uniform(-np.pi, np.pi, 6)
        src[4] = rng.choice([-1, 1]) * rng.uniform(0.3, 2.8)  # (a regular wrist)
        Td = robot.fk(src)
        start = src + rng.uniform(-1e-3, 1e-3, 6)
        q = start.copy()
        assert not _kin.polish(q, Td, K, 4, False, 0, 1e-4)
        assert np.abs(q - src).max() < 1e-6
        q = start.copy()
        assert _kin.polish(q, Td, K, 8)
        assert np.abs(q - src).max() < 1e-9


def test_partner_filter_is_the_frobenius_condition_number():
    """``_condition_frobenius`` (the partner search's cheap filter) is numpy's Frobenius-norm
    condition number, hence between the 2-norm one and 6 times it, on Jacobians from regular to
    nearly singular (the IRB 5400 at random joints and with the elbow and wrist nearly
    stretched), and infinite for a singular matrix."""
    robot = ik7r.load_robot("irb5400")
    K = robot.kernel_params
    rng = np.random.default_rng(9)
    work = [np.empty((6, 6)), np.empty((6, 6))]
    for k in range(30):
        q = rng.uniform(-np.pi, np.pi, 6)
        if k % 3 == 0:
            q[4] = 10.0 ** rng.uniform(-8, -2)  # (a nearly straight wrist)
        J = np.empty((6, 6))
        _kin.jacobian(q, K, J)
        J[:3] /= K[_layout.SCALE]
        c = _reduced._condition_frobenius(J, *work)
        ref = np.linalg.cond(J, "fro")
        assert abs(c - ref) <= 1e-8 * ref, (c, ref)
        c2 = np.linalg.cond(J, 2)
        assert c2 * (1 - 1e-9) <= c <= 6 * c2 * (1 + 1e-9)
    J[:, 2] = J[:, 1]
    assert _reduced._condition_frobenius(J, *work) == np.inf


def test_isolate_bounded_where_the_residual_stays_at_rounding(monkeypatch):
    """An exact 45 deg member with offsets (benchmarks/edges.py's offsets_b45), a pose whose
    residual stays within a few roundings of zero over a stretch of 3e-4 of the range (mixed
    signs beyond the bound there, so never "zero within rounding"): every rounding wiggle was
    split down to WMIN, 8,883 samplings (8.6 ms compiled, over item 8's 5 ms). Past
    ISOLATE_BUDGET samplings such intervals no wider than ZERO_WIDTH are handed on undecided;
    the pose's four solutions, its source among them, are still found, each exact."""
    b = math.radians(45.0)
    dh = np.array([[0, 0, 400, 0], [250, math.pi / 2, 0, 0], [1100, 0, 0, 0], [150, math.pi / 2, 1200, 0],
                   [0, -b, 90, 0], [0, 2 * b, 90, 0], [0, -b, 110, 0]], float)
    robot = Robot(name="offsets_b45", dh=dh)
    q = np.array([-0.19215119, -0.68618644, 1.49903145, 1.66677822, 2.30244521, 2.89027813])
    K = robot.kernel_params
    T = robot.fk(q)
    T07 = np.empty((4, 4))
    _complete.frame07(T, K, T07)
    p, a = T07[:3, 3].copy(), T07[:3, 2] / np.linalg.norm(T07[:3, 2])
    Bm, bnorm = _poly.bernstein_tables(K)
    lo, hi = _complete._interval(K)
    sampled = [0]
    compiled = _poly._bernstein

    def counted(*args):
        sampled[0] += 1
        return compiled(*args)

    monkeypatch.setattr(_poly, "_bernstein", counted)  # (seen by isolate's Python original)
    n = _constants.NBRACKETS
    blo, bhi, bsure = np.empty(n), np.empty(n), np.empty(n)
    count = _poly.isolate.py_func(0, lo, hi, p, a, K, Bm, bnorm, blo, bhi, bsure,
                                  np.empty((n, Bm.shape[0])), np.empty(_poly.ISOLATE_WORK))
    assert count > 0 and (bsure[:count] == 0.0).any()  # the stretch is there, undecided
    assert sampled[0] <= 2 * _poly.ISOLATE_BUDGET, sampled[0]
    sols = robot.ik_all(T)
    assert np.abs(wrap(sols - q)).max(axis=1).min() < 1e-9
    F = reference_fk(robot, sols)
    assert np.linalg.norm(F[:, :3, 3] - T[:3, 3], axis=1).max() <= robot.position_tolerance
    assert len(sols) == 4


def test_fold_gap_pair_is_the_fold_gap_of_each_elbow():
    """``_fold_gap_pair`` (both elbow branches from one evaluation of the arm they share) gives
    exactly :func:`_fold_gap`'s value and ``ok`` of each elbow, bit for bit, on a 45 deg member
    with offsets (the fold scan's robots) over the fold span and below it; both ``ok`` occur.
    Its shortfall (how far the elbow falls short of the centre) is positive exactly where
    neither elbow reaches, and with that much ``reach`` the fold gap gives the stretched arm."""
    b = math.radians(45.0)
    dh = np.array([[0, 0, 400, 0], [250, math.pi / 2, 0, 0], [1100, 0, 0, 0], [150, math.pi / 2, 1200, 0],
                   [0, -b, 90, 0], [0, 2 * b, 90, 0], [0, -b, 110, 0]], float)
    K = Robot(name="b45", dh=dh).kernel_params
    Q = np.random.default_rng(1271).uniform(-np.pi, np.pi, (40, 6))
    T07 = np.empty((4, 4))
    th = np.empty(_constants.NTH)
    seen = set()
    for Td in Robot(name="b45", dh=dh).fk(Q):
        _complete.frame07(Td, K, T07)
        p, a = T07[:3, 3].copy(), T07[:3, 2] / np.linalg.norm(T07[:3, 2])
        for sw in np.linspace(-0.15, 0.25, 41):
            for front in (1.0, -1.0):
                pair = _gaps.fold_gap_pair(sw, p, a, front, K, th)
                one = (_gaps.fold_gap(sw, p, a, front, 1.0, K, th)
                       + _gaps.fold_gap(sw, p, a, front, -1.0, K, th))
                assert pair[:4] == one, (sw, front)
                seen.update((pair[1], pair[3]))
                short = pair[4]
                assert (short > 0.0) == (not (pair[1] or pair[3])) or abs(short) < 1e-9, (sw, front, short)
                if 0.0 < short < math.inf:
                    _, ok = _gaps.fold_gap(sw, p, a, front, 1.0, K, th, 0.0, False, short * (1 + 1e-9))
                    assert ok, (sw, front, short)
    assert seen == {True, False}


def test_fold_meetings_are_where_the_shoulder_branches_are_born():
    """``fold_meetings`` (closed form: a quadratic in u) against the fold gap's own reach, on a
    45 deg member with a 150 mm lateral offset: on a dense grid of sw (4,000 points over the fold
    span and below it) every point where a shoulder branch goes from not defined at all
    (shortfall infinite) to defined lies within a grid step of a meeting, the two branches
    are one arm there (their shortfalls part as the square root of the distance from the point,
    on the side where they are defined), and every meeting in
    the range has such a change beside it. Poses are drawn where the centre passes within the
    offset of axis 1 (some have meetings in range, some none: both occur)."""
    b = math.radians(45.0)
    dh = np.array([[0, 0, 400, 0], [250, math.pi / 2, 150, 0], [1100, 0, 0, 0], [150, math.pi / 2, 1200, 0],
                   [0, -b, 90, 0], [0, 2 * b, 90, 0], [0, -b, 110, 0]], float)
    robot = Robot(name="b45_lateral", dh=dh)
    K = robot.kernel_params
    rng = np.random.default_rng(1290)
    Q = rng.uniform(-np.pi, np.pi, (60, 6))
    Q[:, 4] = rng.choice([-1.0, 1.0], 60) * (np.pi - rng.uniform(0.0, 0.5, 60))
    T07 = np.empty((4, 4))
    grid = np.linspace(-0.05, 0.25, 4001)
    step = grid[1] - grid[0]
    counts = []
    for Td in robot.fk(Q):
        _complete.frame07(Td, K, T07)
        p, a = T07[:3, 3].copy(), T07[:3, 2] / np.linalg.norm(T07[:3, 2])
        meet = [m for m in _gaps.fold_meetings(p, a, K) if grid[0] < m < grid[-1]]
        counts.append(len(meet))
        for front in (1.0, -1.0):
            short = np.array([_gaps.fold_shortfall(x, p, a, front, K) for x in grid])
            born = np.flatnonzero(np.isfinite(short[1:]) != np.isfinite(short[:-1]))
            for i in born:
                assert min((abs(m - grid[i]) for m in meet), default=np.inf) <= 2 * step, (grid[i], meet)
            for m in meet:
                assert any(abs(m - grid[i]) <= 2 * step for i in born), (m, grid[born])
                side = 1.0 if math.isfinite(_gaps.fold_shortfall(m + 1e-9, p, a, front, K)) else -1.0
                assert not math.isfinite(_gaps.fold_shortfall(m - side * 1e-9, p, a, front, K))
                apart = [abs(_gaps.fold_shortfall(m + side * d, p, a, 1.0, K)
                             - _gaps.fold_shortfall(m + side * d, p, a, -1.0, K)) for d in (1e-6, 1e-12)]
                # (the branches part as the square root of the distance from where they meet:
                # 1e-3 of the difference at 1e-6 is left at 1e-12, not more if the point is right)
                assert apart[1] <= 2e-3 * apart[0], (m, apart)
    assert 0 in counts and max(counts) >= 1


def test_fold_short_min_finds_the_least_and_greatest_shortfall():
    """``fold_short_min`` (Brent) as the fold scan uses it: over the two cells around each
    grid point (SCAN_GRID cells over the fold span) whose shortfall is a grid minimum (or, with
    ``sign`` -1, a maximum), on the 45 deg member with a lateral offset, against a dense grid
    (2,001 points) over those cells: the least found is no higher than the dense grid's least
    plus its resolution (the greatest no lower than its greatest less it), and it is the
    shortfall at the point returned."""
    b = math.radians(45.0)
    dh = np.array([[0, 0, 400, 0], [250, math.pi / 2, 150, 0], [1100, 0, 0, 0], [150, math.pi / 2, 1200, 0],
                   [0, -b, 90, 0], [0, 2 * b, 90, 0], [0, -b, 110, 0]], float)
    robot = Robot(name="b45_lateral", dh=dh)
    K = robot.kernel_params
    T07 = np.empty((4, 4))
    m = _constants.SCAN_GRID
    top = _scans.FOLD_SCAN_TOP
    checked = {1.0: 0, -1.0: 0}
    for Td in robot.fk(np.random.default_rng(1291).uniform(-np.pi, np.pi, (150, 6))):
        _complete.frame07(Td, K, T07)
        p, a = T07[:3, 3].copy(), T07[:3, 2] / np.linalg.norm(T07[:3, 2])
        for front in (1.0, -1.0):
            grid = np.array([_gaps.fold_shortfall(top * i / m, p, a, front, K) for i in range(m + 1)])
            for i in range(1, m):
                for sign in (1.0, -1.0):
                    three = sign * grid[i - 1:i + 2]
                    if not (np.isfinite(three).all() and three[1] <= three[0] and three[1] <= three[2]):
                        continue
                    xs = np.linspace(top * (i - 1) / m, top * (i + 1) / m, 2001)
                    dense = sign * np.array([_gaps.fold_shortfall(x, p, a, front, K) for x in xs])
                    if not np.isfinite(dense).all():
                        continue  # (a meeting inside: not a piece the scan minimises over)
                    res = np.abs(np.diff(dense)).max()
                    t, s = _gaps.fold_short_min(xs[0], xs[-1], p, a, front, K, sign)
                    assert s == _gaps.fold_shortfall(t, p, a, front, K)
                    assert sign * s <= dense.min() + res, (i, sign, s, dense.min())
                    checked[sign] += 1
    assert min(checked.values()) >= 5, checked


def test_reduced_scans_that_join_a_curve_take_its_grid(monkeypatch):
    """The rounded 45 deg robot of benchmarks/edges.py at a straight wrist near the shoulder set:
    its candidates, up to 0.3 rad apart in q1, each began a whole-turn reduced scan of their
    straight-wrist family (26 scans of 4 curves, 17 ms compiled, over item 8's 5 ms). A scan
    whose two last grid points coincide with an earlier one's (SCAN_MEMO_TOL) has joined its
    curve and takes the rest of its grid, and its cells' refinement, from that scan: starts 0.3
    and 0.6 rad off in q1 evaluate a few grid points, not REDUCED_GRID + 1, and add nothing the
    first did not; a start on another arm branch tracks a curve of its own. Every solution the
    scans add is exact (reference forward kinematics)."""
    b = math.radians(45.0)
    dh = np.array([[0, 0, 400, 0], [250, math.pi / 2, 0, 0], [1100, 0, 0, 0], [150, math.pi / 2, 1200, 0],
                   [0, -b, 90, 0], [0, 2 * b - 1e-4, 90.1, 0], [0, -b, 110, 0]], float)
    robot = Robot(name="rounded_b45", dh=dh)
    q = np.array([0.4501849955241335, 1.3315137868387232, 2.105068308873941, -0.36118377721668216,
                  0.0, -0.7134564149856786])
    T = robot.fk(q)
    K = robot.kernel_params
    s4, s7 = robot.joint_sign[3], robot.joint_sign[6]
    ws = np.empty(_constants.WORK_SIZE)
    ws[_constants.W_NRSCAN] = 0.0
    mats = ws[_constants.W_MATS:_constants.W_MATS + _constants.NMATS * 16].reshape((_constants.NMATS, 4, 4))
    mats[_constants.MAT_MEMO_N, 0, 0] = 0.0
    out = np.empty((64, 6))
    evaluations = [0]
    compiled = _reduced._reduced_at

    def counted(*args):
        evaluations[0] += 1
        return compiled(*args)

    monkeypatch.setattr(_reduced, "_reduced_at", counted)  # (seen by _reduced_scan's original)
    # (and by the refinements as written: a compiled one not in numba's cache would be compiled
    # here, against the counter, which numba cannot type)
    monkeypatch.setattr(_reduced, "_reduced_root", _reduced._reduced_root.py_func)
    monkeypatch.setattr(_reduced, "_inside_ends", _reduced._inside_ends.py_func)

    def scan(arm, count):
        """The family's scan as _straight_family starts it: q4 = -pi, q5 = 0, the sum kept."""
        total = s4 * q[3] + s7 * q[5]
        start = np.array([arm[0], arm[1], arm[2], -math.pi, 0.0, s7 * (total + s4 * math.pi)])
        evaluations[0] = 0
        count = _reduced.reduced_scan.py_func(start, 3, -math.pi, math.pi, _constants.REDUCED_GRID,
                                                T, K, out, count, ws, mats)
        return count, evaluations[0], int(ws[_constants.W_NRSCAN])

    count, first, curves = scan(q[:3], 0)
    assert count >= 1 and first >= _constants.REDUCED_GRID + 1 and curves == 1
    for dq1 in (0.3, -0.3, 0.6):
        again, joined, curves = scan(q[:3] + [dq1, 0.0, 0.0], count)
        assert again == count and curves == 1, (dq1, again, curves)
        assert joined <= 12, (dq1, joined)
    other = robot.ik_all(T)
    other = other[np.abs(wrap(other[:, 1] - q[1])) > 0.5][0]  # the other elbow's arm
    more, own, curves = scan(other[:3], count)
    assert curves == 2 and own >= _constants.REDUCED_GRID + 1
    assert more > count
    F = reference_fk(robot, out[:more])
    assert np.linalg.norm(F[:, :3, 3] - T[:3, 3], axis=1).max() <= robot.position_tolerance
    assert np.abs(F[:, :3, :3] - T[:3, :3]).max() <= 2 * robot.rotation_tolerance


def test_a_shoulder_dip_found_twice_is_scanned_once():
    """``_dip_scanned``: the first dip of an elbow branch is new (and remembered); the same dip
    again within SHOULDER_DIP_SAME (also across the wrap at +-pi) is not, while a dip on the
    other elbow branch or SHOULDER_DIP_SAME beyond is; a new pose (the count reset) forgets."""
    ws = np.zeros(_constants.WORK_SIZE)
    same = _constants.SHOULDER_DIP_SAME
    assert not _scans._dip_scanned(1.25, 1.0, ws)
    assert _scans._dip_scanned(1.25 + 0.5 * same, 1.0, ws)
    assert not _scans._dip_scanned(1.25, -1.0, ws)
    assert not _scans._dip_scanned(1.25 + 2 * same, 1.0, ws)
    assert not _scans._dip_scanned(math.pi - 0.25 * same, -1.0, ws)
    assert _scans._dip_scanned(-math.pi + 0.25 * same, -1.0, ws)
    ws[_constants.W_NSDIP] = 0.0
    assert not _scans._dip_scanned(1.25, 1.0, ws)


def test_arm_just_out_of_reach_takes_the_nearest_arm_within_its_slack():
    """``arm_ik``'s ``slack``: a point 1e-6 of the reach beyond the stretched elbow of the IRB
    5400 (the elbow's cosine beyond 1 by a few 1e-6) is out of reach by default and within a
    slack of 1e-3; the arm then given is the stretched one, whose angles are those of the point
    just inside the boundary to within the arc cosine's square root of the overshoot."""
    from ik7r._kernels import arm as _arm

    K = ik7r.load_robot("irb5400").kernel_params
    a1, a2, a3, d1, Ld = (K[_layout.A1], K[_layout.A2], K[_layout.A3], K[_layout.D1], K[_layout.D4])
    far = a2 + math.hypot(a3, Ld)  # from axis 2, the elbow stretched (the cosine at 1)
    t1, phi = 0.4, 0.3

    def arm(scale, slack):
        rho = a1 + scale * far * math.cos(phi)
        pz = d1 + K[_layout.EPS1] * scale * far * math.sin(phi)
        return _arm.arm_ik(rho * math.cos(t1), rho * math.sin(t1), pz, Ld, 1.0, 1.0, 0.0, K, slack)

    inside = arm(1.0 - 1e-9, 1e-12)
    assert inside[3]
    assert not arm(1.0 + 1e-6, 1e-12)[3]
    out = arm(1.0 + 1e-6, 1e-3)
    assert out[3]
    assert np.abs(wrap(np.array(out[:3]) - np.array(inside[:3]))).max() <= 1e-3  # (sqrt(2 x 4e-6): 3e-4)


def test_straight_snap_beside_axis1_with_the_elbow_stretched_is_polished_straight(robots):
    """``_straight_damped``: axis 7 on axis 1, the wrist straight and the elbow stretched (q =
    [0.3, 90, -90, 0, 0, 0] deg on the paper robot). The polynomial's arm there is 4.4e-7 rad off
    in q2 (a double root, good to about sqrt(eps)); the damped polish free in q5 took that up with
    a bend of 4e-7 (one of the two nearly straight shadows) and the snap was given up, so the
    answer depended on a later candidate landing exactly. Held straight (``fk.polish`` with ``free``
    4: q1..q4 move, q5 and q7 are held),
    the snap polishes to an exactly straight solution the reference's forward kinematics
    confirms."""
    robot = robots["paper"]
    K = robot.kernel_params
    q = np.array([0.3, np.pi / 2, -np.pi / 2, 0.0, 0.0, 0.0])
    Td = robot.fk(q)
    snap = np.array([0.0, 1.5707958859156517, -1.570796342533527, 0.0, 0.0, -0.30000000000002947])
    mats = np.zeros((_constants.NMATS, 4, 4))
    assert _answers.straight_damped(snap, Td, K, np.zeros(6), False, mats)
    assert snap[4] == 0.0
    T = reference_fk(robot, snap)
    assert np.abs(T[:3, 3] - Td[:3, 3]).max() <= robot.position_tolerance
    assert np.abs(T[:3, :3] - Td[:3, :3]).max() <= 1e-9


@pytest.mark.parametrize("name", ["paper", "offsets", "irb5400"])
def test_arm_cosines_and_sines_place_the_point_of_the_reference_arm(robots, name):
    """``arm_cs`` (the arm's cosines and sines without a trigonometric call, what the bend gaps
    use): for random DH angles of joints 1 to 3, the point at ``Ld`` along axis 4 made by the
    reference's DH links is placed again by one of the four branches, whose cosines and sines
    are those of the angles; ``arm_ik``'s angles are theirs, in (-pi, pi]."""
    from reference_ik import _link

    from ik7r._kernels import arm as _arm

    robot = robots[name] if name in robots else ik7r.load_robot(name)
    K = robot.kernel_params
    dh = np.array(robot.dh, float)
    rng = np.random.default_rng(1205)
    worst = 0.0
    for _ in range(200):
        th = rng.uniform(-np.pi, np.pi, 3)
        T = np.eye(4)
        for i in range(4):
            T = T @ _link(dh[i, 0], dh[i, 1], np.array([th[i] if i < 3 else 0.0]), dh[i, 2])[0]
        extra = rng.uniform(0.0, 0.2) * K[_layout.SCALE]
        P = T[:3, 3] + extra * T[:3, 2]
        Ld = K[_layout.D4] + extra
        best = np.inf
        for front in (1.0, -1.0):
            for elbow in (1.0, -1.0):
                c1, s1, c2, s2, c3, s3, ok = _arm.arm_cs(P[0], P[1], P[2], Ld, front, elbow, 0.0, K)
                t1, t2, t3, ok_ik = _arm.arm_ik(P[0], P[1], P[2], Ld, front, elbow, 0.0, K)
                if not ok:
                    continue
                assert ok_ik
                got = np.array([[c1, s1], [c2, s2], [c3, s3]])
                angles = np.array([t1, t2, t3])
                assert np.all(np.abs(angles) <= np.pi)
                assert np.abs(np.column_stack([np.cos(angles), np.sin(angles)]) - got).max() < 1e-12
                assert np.abs(np.hypot(got[:, 0], got[:, 1]) - 1.0).max() < 1e-12
                best = min(best, np.abs(got - np.column_stack([np.cos(th), np.sin(th)])).max())
        worst = max(worst, best)
    assert worst < 1e-9


@pytest.mark.parametrize("name", ["paper", "offsets"])
def test_other_wrist_of_an_arm_is_its_other_solution(robots, name):
    """``_other_wrist``: on the idealised model each arm comes with both wrists, so the other
    wrist of an exact solution (its arm kept, theta5 of the other sign) is exact too, checked by
    the reference's forward kinematics, and is no copy of the first (q5 of the other sign, q4
    and q7 moved)."""
    robot = robots[name]
    K = robot.kernel_params
    rng = np.random.default_rng(1204)
    th, M = np.empty(6), np.empty((4, 4))
    Q, W, qq, T07 = np.empty((3, 3)), np.empty((3, 3)), np.empty(6), np.empty((4, 4))
    for _ in range(20):
        q = rng.uniform(-np.pi, np.pi, 6)
        q[4] = rng.choice([-1.0, 1.0]) * rng.uniform(0.1, np.pi - 0.1)
        T = robot.fk(q)
        _complete.frame07(T, K, T07)
        _joints.other_wrist(q, T07[:3, :3].copy(), K, th, M, Q, W, qq)
        assert np.array_equal(qq[:3], q[:3])
        assert qq[4] * q[4] < 0.0 and abs(abs(qq[4]) - abs(q[4])) < 1e-12
        F = reference_fk(robot, qq)
        assert np.linalg.norm(F[:3, 3] - T[:3, 3]) <= robot.position_tolerance
        assert np.abs(F[:3, :3] - T[:3, :3]).max() <= 2 * robot.rotation_tolerance
