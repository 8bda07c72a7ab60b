"""Off-line painting programs (issue 6): paths, trajectory IK, interpolation, CSV, CLI.

Every joint result is checked by forward kinematics against the path, never against another
output of the painting code. Paths are short so that the file runs in a few seconds.
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers import dh_product

from ik7r.cli.app import main
from ik7r.geometry.rotations import invert, rot_x, transform
from ik7r.painting import (
    CSV_COLUMNS,
    GUN_DOWN,
    BranchChange,
    JointLimit,
    NearSingularity,
    PathNotFeasible,
    SpeedLimit,
    TimeScaled,
    Timing,
    Unreachable,
    WristCrossing,
    load_path_csv,
    paint_path,
    paint_raster,
    path_from_poses,
    plot_joint_trajectory,
    raster_path,
    solve_path,
    workpiece_frame,
)

MM_TOL = 0.01  # the default deviation tolerance (mm)


def _line(a, b, n):
    a, b = np.asarray(a, float), np.asarray(b, float)
    return a + np.linspace(0.0, 1.0, n)[:, None] * (b - a)


def _gun_path(points):
    return path_from_poses(transform(GUN_DOWN, points))


def _fk_base(robot, q):
    return invert(robot.base) @ robot.fk(q)


# ----------------------------------------------------------------------------- paths
def test_raster_geometry_in_a_tilted_workpiece_frame():
    T_bw = workpiece_frame((1000.0, 50.0, 300.0), np.radians([10.0, -5.0, 30.0]))
    w, h, spacing, margin, standoff, step = 300.0, 250.0, 60.0, 20.0, 150.0, 7.0
    p = raster_path(T_bw, size=(w, h), spacing=spacing, margin=margin, standoff=standoff, step=step)
    local = (invert(T_bw) @ p.transforms)
    xyz = local[:, :3, 3]
    n_pass = int(np.ceil(h / spacing)) + 1
    gap = h / (n_pass - 1)
    assert gap <= spacing
    np.testing.assert_allclose(xyz[:, 2], standoff, atol=1e-9)  # standoff above the surface
    # straight samples sit on the passes; turns stay outside the rectangle and its margins
    on_pass = np.abs(xyz[:, 0]) <= w / 2 + margin + 1e-9
    ys = -h / 2 + gap * np.arange(n_pass)
    assert np.all(np.min(np.abs(xyz[on_pass, 1][:, None] - ys[None, :]), axis=1) < 1e-9)
    assert np.all(np.abs(xyz[:, 0]) <= w / 2 + margin + gap / 2 + 1e-9)
    assert np.isclose(xyz[:, 1].min(), -h / 2) and np.isclose(xyz[:, 1].max(), h / 2)
    assert np.isclose(xyz[0, 0], -(w / 2 + margin)) and np.isclose(abs(xyz[-1, 0]), w / 2 + margin)
    # samples no farther apart than step; u is the arc length (chords never longer)
    chords = np.linalg.norm(np.diff(p.positions, axis=0), axis=1)
    assert chords.max() <= step + 1e-9
    assert np.all(chords <= np.diff(p.u) + 1e-9)
    assert np.isclose(p.u[-1], n_pass * (w + 2 * margin) + (n_pass - 1) * np.pi * gap / 2)
    # constant gun orientation: x along the workpiece x, y and z opposite
    np.testing.assert_allclose(local[:, :3, :3], np.broadcast_to(np.diag([1.0, -1.0, -1.0]), (len(p), 3, 3)),
                               atol=1e-12)
    # the exact geometry reproduces the samples, and stays on the plane in between
    P, R = p.at(p.u)
    np.testing.assert_allclose(P, p.positions, atol=1e-9)
    mid = 0.5 * (p.u[:-1] + p.u[1:])
    Pm, _ = p.at(mid)
    zm = (Pm - T_bw[:3, 3]) @ T_bw[:3, :3]
    np.testing.assert_allclose(zm[:, 2], standoff, atol=1e-9)


def test_paper_gun_orientation():
    p = raster_path(size=(100.0, 0.0))
    R = p.rotations[0]
    np.testing.assert_allclose(R[:, 0], [1, 0, 0], atol=1e-15)
    np.testing.assert_allclose(R[:, 1], [0, -1, 0], atol=1e-15)
    np.testing.assert_allclose(R[:, 2], [0, 0, -1], atol=1e-15)


@pytest.mark.parametrize("kwargs", [dict(spacing=0.0), dict(step=-1.0), dict(size=(0.0, 10.0)),
                                    dict(margin=float("nan")), dict(size=(1.0, 2.0, 3.0))])
def test_raster_rejects_bad_input(kwargs):
    with pytest.raises(ValueError):
        raster_path(**kwargs)


def test_path_rejects_coincident_samples():
    with pytest.raises(ValueError, match="samples 1 and 2"):
        _gun_path(np.array([[1000.0, 0, 0], [1010, 0, 0], [1010, 0, 0]]))


def test_csv_path_orientations_and_workpiece_frame(tmp_path):
    from scipy.spatial.transform import Rotation

    rng = np.random.default_rng(7)
    n = 6
    xyz = rng.uniform(-100, 100, (n, 3))
    rpy = rng.uniform(-60, 60, (n, 3))
    R_ref = Rotation.from_euler("xyz", rpy, degrees=True).as_matrix()  # fixed axes X-Y-Z (URDF)
    quat = Rotation.from_matrix(R_ref).as_quat()[:, [3, 0, 1, 2]]  # (w, x, y, z)
    T_bw = workpiece_frame((900.0, -20.0, 150.0), np.radians([0.0, 20.0, 45.0]))
    f_rpy = tmp_path / "rpy.csv"
    f_rpy.write_text("# a comment\nx,y,z,roll,pitch,yaw,speed\n"
                     + "".join(f"{a},{b},{c},{r},{p},{y},1\n" for (a, b, c), (r, p, y) in zip(xyz, rpy)))
    f_q = tmp_path / "quat.csv"
    f_q.write_text("qw,qx,qy,qz,x,y,z\n" + "".join(
        ",".join(f"{v:.17g}" for v in np.r_[qq, pp]) + "\n" for qq, pp in zip(quat, xyz)))
    f_p = tmp_path / "pos.csv"
    f_p.write_text("x,y,z\n" + "".join(f"{a},{b},{c}\n" for a, b, c in xyz))
    expect_p = xyz @ T_bw[:3, :3].T + T_bw[:3, 3]
    for f in (f_rpy, f_q):
        path = load_path_csv(f, T_bw)
        np.testing.assert_allclose(path.positions, expect_p, atol=1e-9)
        np.testing.assert_allclose(path.rotations, T_bw[:3, :3] @ R_ref, atol=1e-9)
    path = load_path_csv(f_p, T_bw)
    np.testing.assert_allclose(path.rotations[2], T_bw[:3, :3] @ GUN_DOWN, atol=1e-12)
    # in between samples: linear positions, and rotations on the geodesic
    u = 0.5 * (path.u[2] + path.u[3])
    P, _ = path.at([u])
    np.testing.assert_allclose(P[0], 0.5 * (expect_p[2] + expect_p[3]), atol=1e-9)


def test_csv_path_errors_name_the_line(tmp_path):
    f = tmp_path / "bad.csv"
    f.write_text("x,y,z\n1,2,3\n4,oops,6\n")
    with pytest.raises(ValueError, match="line 3"):
        load_path_csv(f)
    f.write_text("x,y\n1,2\n")
    with pytest.raises(ValueError, match="lacks columns"):
        load_path_csv(f)
    f.write_text("x,y,z,qw,qx,qy,qz\n0,0,0,2,0,0,0\n1,0,0,1,0,0,0\n")
    with pytest.raises(ValueError, match="unit norm"):
        load_path_csv(f)
    with pytest.raises(FileNotFoundError):
        load_path_csv(tmp_path / "missing.csv")


# ----------------------------------------------------------------------------- the paper's scenario
@pytest.fixture(scope="module")
def paper_result(robot):
    return paint_raster(robot, duration=20.0, config=1)


def test_default_scenario_contract(robot, paper_result, tmp_path):
    res = paper_result
    tr = res.trajectory
    assert res.events == []
    # rows every 10 ms, plus (issue 16) a row at each joint's peak speed and acceleration
    grid = np.arange(2001) / 100.0
    assert np.all(np.min(np.abs(tr.t[:, None] - grid[None, :]), axis=0) < 1e-12)
    extra = len(tr.t) - 2001
    assert 0 < extra <= 12
    assert tr.q.shape == tr.dq.shape == tr.ddq.shape == (len(tr.t), 6)
    assert tr.t[0] == 0.0 and tr.t[-1] == 20.0 and np.all(np.diff(tr.t) > 0)
    out = plot_joint_trajectory(tr, tmp_path / "figure12.png", robot=robot)
    assert out.stat().st_size > 10_000
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_default_scenario_is_far_from_limits_and_singularities(robot, paper_result):
    """The documented choice of the default rectangle: configuration 1 everywhere, every joint at
    least 25 deg inside its limits, theta5 at least 40 deg from 0 and 180, a well-conditioned
    Jacobian."""
    sol = paper_result.solution
    assert sol.feasible and np.all(sol.ok)
    assert np.all(robot.config_of(sol.q) == 1)
    margin = np.minimum(sol.q - robot.lower, robot.upper - sol.q).min()
    assert np.degrees(margin) > 25.0
    q5 = np.abs(sol.q[:, 4])
    assert np.degrees(np.minimum(q5, np.pi - q5).min()) > 40.0
    J = robot.jacobian(sol.q[::20])
    J[:, :3, :] /= 1000.0  # metres, so that lengths and angles weigh alike
    assert np.linalg.cond(J).max() < 10.0


def test_samples_satisfy_fk_and_are_continuous(robot, paper_result):
    tr = paper_result.trajectory
    path = paper_result.path
    T = _fk_base(robot, tr.knot_q)
    P, R = path.at(tr.knot_u)
    assert np.abs(T[:, :3, 3] - P).max() < 1e-8
    assert np.abs(T[:, :3, :3] - R).max() < 1e-10
    assert np.all(tr.knot_q >= robot.lower - 1e-12) and np.all(tr.knot_q <= robot.upper + 1e-12)
    # continuity: consecutive samples 5 mm apart move no joint by more than 1 deg
    assert np.degrees(np.abs(np.diff(tr.knot_q, axis=0)).max()) < 1.0
    # the interpolated trajectory starts and ends at rest on the first and last path points
    np.testing.assert_allclose(tr.dq[[0, -1]], 0.0, atol=1e-9)
    np.testing.assert_allclose(tr.ddq[[0, -1]], 0.0, atol=1e-7)
    np.testing.assert_allclose(_fk_base(robot, tr.q[[0, -1]])[:, :3, 3], path.positions[[0, -1]], atol=1e-8)


def test_interpolated_deviation_within_tolerance_at_random_times(robot, paper_result, rng):
    tr = paper_result.trajectory
    t = rng.uniform(0, tr.duration, 3000)
    q, _, _ = tr.evaluate(t)
    P, _ = paper_result.path.at(tr.timing.u_of_t(t))
    dev = np.linalg.norm(_fk_base(robot, q)[:, :3, 3] - P, axis=1)
    # the check runs at 7 points per interval and every row; random times may fall between them
    assert dev.max() <= 1.5 * MM_TOL
    assert tr.max_deviation <= MM_TOL


def test_rows_are_derivatives_of_each_other(paper_result, rng):
    tr = paper_result.trajectory
    i = rng.choice(np.arange(1, len(tr.t) - 1), 50, replace=False)
    h = 1e-5
    qp, dqp, _ = tr.evaluate(tr.t[i] + h)
    qm, dqm, _ = tr.evaluate(tr.t[i] - h)
    np.testing.assert_allclose((qp - qm) / (2 * h), tr.dq[i], atol=1e-5)
    np.testing.assert_allclose((dqp - dqm) / (2 * h), tr.ddq[i], atol=1e-3)
    # the joint speeds and accelerations are within the robot's limits
    assert np.all(np.abs(tr.dq) <= paper_result.robot.velocity)
    assert np.all(np.abs(tr.ddq) <= paper_result.robot.acceleration)


def test_painting_keeps_configurations_by_the_solvers_rule(robot, rng):
    """A painting path keeps its configuration by the rule the solver states: the configuration
    number of the paper's Appendix 3, and a solution on a boundary belongs to both sides."""
    from ik7r.painting.trajectory import _matches

    Q = rng.uniform(-2 * np.pi, 2 * np.pi, (300, 6))
    Q[:20, 4] = 0.0  # straight wrist: both wrist indicators
    Q[20:40, 0] = np.pi / 2 + rng.uniform(-5e-7, 5e-7, 20)  # q1 on the arm boundary: both arms
    Q[40:60, 2] = -np.pi / 2 + rng.uniform(-5e-7, 5e-7, 20)  # q3 on the elbow boundary: both elbows
    cfg = robot.config_of(Q)
    for i, q in enumerate(Q):
        same = {int(cfg[i])}
        if i < 20:
            same.add(int(cfg[i]) + (1 if cfg[i] % 2 else -1))
        elif i < 40:
            same.add(int(cfg[i]) + (4 if cfg[i] <= 4 else -4))
        elif i < 60:
            same.add(int(cfg[i]) + (2 if (cfg[i] - 1) % 4 < 2 else -2))
        assert [c for c in range(1, 9) if _matches(q, c)] == sorted(same), (i, q)


def test_timing_is_rest_to_rest_and_invertible():
    tm = Timing(1000.0, 10.0, 1.5)
    t = np.linspace(0, 10, 2001)
    u = tm.u_of_t(t)
    assert u[0] == 0.0 and np.isclose(u[-1], 1000.0)
    assert np.all(np.diff(u) > 0)
    np.testing.assert_allclose(tm.t_of_u(u), t, atol=1e-9)
    v = np.gradient(u, t)
    assert v[0] < 1e-3 * tm.speed and v[-1] < 1e-3 * tm.speed
    np.testing.assert_allclose(v[800:1200], tm.speed, rtol=1e-9)


# ----------------------------------------------------------------------------- theta5 = 0
def _crossing_path(robot, offset=0.37):
    """A path whose continuous joint motion is a straight joint-space line through theta5 = 0,
    crossing it between samples 20 and 21 (``offset`` of a step after sample 20)."""
    qa = np.radians([10.0, 60.0, -20.0, 30.0, 20.0, 40.0])
    qb = np.radians([20.0, 70.0, -10.0, 50.0, -20.0, 60.0])
    n = 41
    s = 0.5 + (np.arange(n) - 20 - offset) / (n - 1)  # q5 = 0 at s = 0.5
    Q = qa + s[:, None] * (qb - qa)
    assert Q[20, 4] > 0 > Q[21, 4]
    return path_from_poses(robot.fk(Q)), Q


def test_theta5_crossing_followed_continuously_with_keep_branch(robot):
    path, Q = _crossing_path(robot)
    sol = solve_path(robot, path, 1, keep="branch")
    assert sol.feasible
    # the continuous branch is the joint-space line the path was made from
    np.testing.assert_allclose(sol.q, Q, atol=1e-8)
    crossings = [e for e in sol.events if isinstance(e, WristCrossing)]
    assert len(crossings) == 1
    c = crossings[0]
    assert c.index == 21 and c.angle == 0.0 and (c.config_before, c.config_after) == (1, 2)
    assert "theta5 crosses 0" in str(c) and "samples 20 and 21" in str(c)
    assert not any(isinstance(e, BranchChange) for e in sol.events)
    assert any(isinstance(e, NearSingularity) for e in sol.events)
    res = paint_path(robot, path, duration=4.0, keep="branch")
    q5 = res.trajectory.q[:, 4]
    assert q5[0] > 0 > q5[-1]
    assert np.all(np.abs(np.diff(q5)) < np.radians(1.0))  # no jump: a continuous crossing
    assert any(isinstance(e, WristCrossing) for e in res.events)


def test_theta5_crossing_with_keep_config_is_a_reported_branch_change(robot):
    path, Q = _crossing_path(robot)
    sol = solve_path(robot, path, 1)
    assert not sol.feasible
    assert np.all(robot.config_of(sol.q) == 1)
    T = _fk_base(robot, sol.q)
    assert np.abs(T[:, :3, 3] - path.positions).max() < 1e-8
    kinds = {type(e): e for e in sol.events}
    assert kinds[WristCrossing].index == 21
    jump = kinds[BranchChange]
    assert jump.index == 21 and np.degrees(jump.jump) > 90.0
    with pytest.raises(PathNotFeasible) as info:
        paint_path(robot, path, duration=4.0)
    msg = str(info.value)
    assert "branch change between samples 20 and 21" in msg and "theta5 crosses 0" in msg
    assert info.value.solution is not None


def test_near_miss_of_theta5_zero_reports_speed_excess(robot):
    path, Q = _crossing_path(robot)
    T = path.transforms
    T[:, :3, :3] = T[:, :3, :3] @ rot_x(np.radians(0.5))  # the wrist never quite straightens
    near = path_from_poses(T)
    res = paint_path(robot, near, duration=4.0)
    ns = [e for e in res.events if isinstance(e, NearSingularity)]
    assert ns and "wrist flip" in str(ns[0])
    fast = {e.joint for e in res.events if isinstance(e, SpeedLimit)}
    assert {3, 5} <= fast  # q4 and q7


# ----------------------------------------------------------------------------- unreachable
def test_unreachable_stretch_is_reported_sample_by_sample(robot):
    out_and_back = [_line([1200, 0, 200], [2300, 0, 200], 45), _line([2300, 0, 200], [1200, 0, 200], 45)[1:]]
    pts = np.vstack(out_and_back)
    path = _gun_path(pts)
    sol = solve_path(robot, path)
    # independent: which samples have no configuration-1 solution within the limits?
    expect = [i for i, T in enumerate(path.transforms)
              if not np.any(robot.config_of(robot.ik_all(T, within_limits=True)) == 1)]
    events = [e for e in sol.events if isinstance(e, Unreachable)]
    got = sorted(i for e in events for i in range(e.first, e.last + 1))
    assert got == expect and len(expect) > 10
    assert np.all(np.isnan(sol.q[expect])) and np.all(sol.ok == ~np.isin(np.arange(len(path)), expect))
    assert any("out of reach" in e.reason for e in events)
    with pytest.raises(PathNotFeasible) as info:
        paint_path(robot, path)
    assert f"samples {expect[0]}-" in str(info.value)


def test_joint_limit_is_reported(robot):
    path = _gun_path(_line([500, -300, 200], [500, 1500, 200], 50))
    sol = solve_path(robot, path, progress=True)  # the bar stays silent: stderr is not a terminal
    limits = [e for e in sol.events if isinstance(e, JointLimit)]
    assert limits and limits[0].joint == 0 and np.isclose(limits[0].limit, robot.upper[0])
    un = [e for e in sol.events if isinstance(e, Unreachable)]
    assert un and "q1 = " in un[0].reason and "outside [-70, 70]" in un[0].reason
    # the last solved sample is on q1's limit side, inside the range
    good = sol.q[sol.ok]
    assert np.all(good[:, 0] <= robot.upper[0] + 1e-12)


# ----------------------------------------------------------------------------- limits and time
def test_speed_limits_reported_or_time_rescaled(robot, rng):
    path = raster_path(size=(400.0, 0.0), step=10.0)
    with_report = paint_path(robot, path, duration=0.3)
    assert any(isinstance(e, SpeedLimit) for e in with_report.events)
    assert np.nanmax(with_report.trajectory.speed_ratio) > 1
    res = paint_path(robot, path, duration=0.3, rescale=True)
    scaled = [e for e in res.events if isinstance(e, TimeScaled)]
    assert len(scaled) == 1 and scaled[0].after > 0.3 and np.isclose(res.trajectory.duration, scaled[0].after)
    assert not any(isinstance(e, SpeedLimit) for e in res.events)
    t = np.sort(rng.uniform(0, res.trajectory.duration, 20000))
    _, dq, ddq = res.trajectory.evaluate(t)
    # checked at discrete points: allow 1 % between them
    assert np.all(np.abs(dq) <= robot.velocity * 1.01)
    assert np.all(np.abs(ddq) <= robot.acceleration * 1.01)
    # the same path, only slower
    P, _ = path.at(res.trajectory.timing.u_of_t(t))
    q, _, _ = res.trajectory.evaluate(t)
    assert np.linalg.norm(_fk_base(robot, q)[:, :3, 3] - P, axis=1).max() <= 1.5 * MM_TOL


def test_tool_is_the_target(robot):
    tool = transform(rot_x(np.radians(20.0)), [0.0, 30.0, 250.0])
    path = raster_path(workpiece_frame((1100.0, 0.0, 0.0)), size=(200.0, 0.0), step=10.0, standoff=100.0)
    res = paint_path(robot, path, duration=3.0, tool=tool)
    q = res.solution.q
    # independent FK (the paper's eq. (1) product) times the tool: the gun tip is on the path
    T = np.array([dh_product(x) for x in q]) @ tool
    assert np.abs(T[:, :3, 3] - path.positions).max() < 1e-8
    bare = np.array([dh_product(x) for x in q])
    assert np.abs(bare[:, :3, 3] - path.positions).max() > 100.0


# ----------------------------------------------------------------------------- CLI
def test_cli_raster_writes_a_csv_that_matches_fk(tmp_path, capsys):
    out = tmp_path / "prog"
    rc = main(["paint", "raster", "--size", "300", "200", "--spacing", "100", "--step", "10",
               "--duration", "6", "--frames", "3", "--out", str(out)])
    assert rc == 0
    for name in ("trajectory.csv", "figure12.png", "path3d.png", "animation.gif", "report.txt"):
        assert (out / name).stat().st_size > 0, name
    text = (out / "trajectory.csv").read_text().splitlines()
    assert text[0] == ",".join(CSV_COLUMNS)
    data = np.loadtxt(out / "trajectory.csv", delimiter=",", skiprows=1)
    col = {c: i for i, c in enumerate(CSV_COLUMNS)}
    t = data[:, col["t"]]
    assert t[0] == 0 and t[-1] == 6.0
    # every 10 ms, plus the peak instants (issue 16)
    grid = np.arange(601) / 100.0
    assert np.all(np.min(np.abs(t[:, None] - grid[None, :]), axis=0) < 1e-9) and len(t) - 601 <= 12
    qdeg = data[:, [col[f"q{i}"] for i in (1, 2, 3, 4, 5, 7)]]
    # every row: FK of its joints is its path point, within the deviation tolerance (0.01 mm,
    # checked at every row by the interpolation) plus what 12 printed digits lose (< 1e-6 mm)
    T = np.array([dh_product(np.radians(q)) for q in qdeg])
    err = np.linalg.norm(T[:, :3, 3] - data[:, [col["x"], col["y"], col["z"]]], axis=1)
    assert err.max() <= MM_TOL + 1e-6
    # the coupled joint 6 = -joint 5, for positions, velocities and accelerations
    for pre in ("q", "dq", "ddq"):
        np.testing.assert_allclose(data[:, col[f"{pre}6"]], -data[:, col[f"{pre}5"]], atol=1e-9)
    # velocity columns integrate to the position columns (trapezoid rule, error dt^3/12 * jerk)
    dq = data[:, [col[f"dq{i}"] for i in (1, 2, 3, 4, 5, 7)]]
    ddq = data[:, [col[f"ddq{i}"] for i in (1, 2, 3, 4, 5, 7)]]
    dt = np.diff(t)[:, None]
    assert np.abs(np.diff(qdeg, axis=0) - 0.5 * dt * (dq[1:] + dq[:-1])).max() < 2e-3
    assert np.abs(np.diff(dq, axis=0) - 0.5 * dt * (ddq[1:] + ddq[:-1])).max() < 0.2
    assert "no events" in capsys.readouterr().out


def test_cli_path_from_csv(tmp_path, capsys):
    f = tmp_path / "stroke.csv"
    pts = _line([-150, 0, 0], [150, 0, 0], 31)
    f.write_text("x,y,z,roll,pitch,yaw\n" + "".join(f"{x},{y},{z},180,0,0\n" for x, y, z in pts))
    out = tmp_path / "prog"
    rc = main(["paint", "path", str(f), "--frame", "1100", "0", "300", "0", "0", "0", "--duration", "3",
               "--no-plots", "--out", str(out)])
    assert rc == 0
    data = np.loadtxt(out / "trajectory.csv", delimiter=",", skiprows=1)
    np.testing.assert_allclose(data[0, 1:4], [950.0, 0.0, 300.0], atol=1e-9)
    np.testing.assert_allclose(data[-1, 1:4], [1250.0, 0.0, 300.0], atol=1e-9)
    assert not (out / "figure12.png").exists()


def test_cli_unreachable_path_exits_1_with_a_report(tmp_path, capsys):
    f = tmp_path / "far.csv"
    pts = _line([1500, 0, 200], [2600, 0, 200], 23)
    f.write_text("x,y,z\n" + "".join(f"{x},{y},{z}\n" for x, y, z in pts))
    rc = main(["paint", "path", str(f), "--out", str(tmp_path / "o"), "--no-plots"])
    err = capsys.readouterr().err
    assert rc == 1
    assert "unreachable: samples" in err and "out of reach" in err
    assert "unreachable" in (tmp_path / "o" / "report.txt").read_text()


@pytest.mark.parametrize("argv", [["paint"], ["paint", "raster", "--spacing", "0"],
                                  ["paint", "raster", "--config", "9"],
                                  ["paint", "path", "/nonexistent/path.csv"]])
def test_cli_bad_input_exits_2(argv, tmp_path, capsys):
    assert main(argv + (["--out", str(tmp_path)] if len(argv) > 1 else [])) == 2
    assert capsys.readouterr().err.startswith("error:")


def test_path_spray_flags_switch_at_samples():
    from ik7r.painting import Path

    P = np.array([[0.0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0]])
    R = np.repeat(np.eye(3)[None], 4, axis=0)
    path = Path(P, R, [0.0, 1, 2, 3], spray=[1, 1, 0, 1])
    assert path.spray.dtype == bool and not path.spray.flags.writeable
    # segment 0-1 on (both ends on), 1-2 off, 2-3 off; samples keep their own flag
    np.testing.assert_array_equal(path.sprayed([0.0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0]),
                                  [True, True, True, False, False, False, True])
    assert Path(P, R, [0.0, 1, 2, 3]).spray.all()
    with pytest.raises(ValueError, match="spray must be 4 flags"):
        Path(P, R, [0.0, 1, 2, 3], spray=[1, 0, 2, 1])
