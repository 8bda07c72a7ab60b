"""``ik7r paint mesh`` and ``ik7r gun fit`` end to end: files, film against the closed form of
overlapping strokes, planning for a target, bad input."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from ik7r.cli import main
from ik7r.painting.spray import load_gun


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture(scope="module")
def panel_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("mesh")
    code = main(["paint", "mesh", "panel", "--target-thickness", "15", "--tolerance-thickness", "1.5",
                 "--out", str(out)])
    return code, out


def test_paint_mesh_writes_every_output(panel_run):
    code, out = panel_run
    assert code == 0
    names = {p.name for p in out.iterdir()}
    # the film's outputs and the timing figures of issue 16 (gun speed, joint speeds and accelerations)
    assert names == {"trajectory.csv", "thickness.csv", "thickness.png", "view.html", "report.txt",
                     "report.json", "gun_speed.png", "joint_limits.png"}
    for png in ("gun_speed.png", "joint_limits.png"):
        assert (out / png).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    header = (out / "trajectory.csv").read_text().splitlines()[0].split(",")
    assert header[:4] == ["t", "x", "y", "z"] and header[-1] == "spray"
    table = np.loadtxt(out / "trajectory.csv", delimiter=",", skiprows=1)
    assert set(np.unique(table[:, -1])) == {0.0, 1.0}
    assert (out / "thickness.csv").read_text().splitlines()[0] == "x,y,z,thickness_um"
    th = np.loadtxt(out / "thickness.csv", delimiter=",", skiprows=1)
    assert th.shape == (3111, 4)
    assert (out / "thickness.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    html = (out / "view.html").read_text()
    assert "<script>" in html and "src=" not in html and "http" not in html.replace("http-equiv", "")
    rep = json.loads((out / "report.json").read_text())
    assert {"film", "plan", "events", "gun", "part", "film_step", "trajectory"} <= set(rep)
    assert "within 15 +- 1.5 um" in (out / "report.txt").read_text()


def test_paint_mesh_film_and_plan(panel_run):
    _, out = panel_run
    rep = json.loads((out / "report.json").read_text())
    film, plan = rep["film"], rep["plan"]
    # planning: the mean over the part is the target (thickness ~ 1/speed at a fixed spacing)
    assert film["mean_um"] == pytest.approx(15.0, rel=0.005)
    assert plan["speed"] == pytest.approx(plan["trial_speed"] * plan["trial_mean_um"] / 15.0, rel=1e-9)
    # in the middle of the panel the film is that of infinitely many Gaussian strokes D apart at
    # the commanded speed: 2 pi sigma^2 q0 / (v D), within the ripple and the 0.5 % promise
    gun = load_gun("bell")
    sigma, q0, D, v = gun.params["sigma"], gun.peak_rate, plan["spacing"], plan["speed"]
    expected = 2 * math.pi * sigma ** 2 * q0 / (v * D)
    th = np.loadtxt(out / "thickness.csv", delimiter=",", skiprows=1)
    centre = (np.abs(th[:, 0]) <= 100) & (np.abs(th[:, 1]) <= 100)
    assert np.abs(th[centre, 3] / expected - 1).max() <= plan["ripple"] + 0.005
    # the spacing chosen keeps the ripple within 1 % (the Gaussian formula agrees)
    assert plan["ripple"] <= 0.01
    assert plan["ripple_gaussian_formula"] == pytest.approx(plan["ripple"], rel=0.05)
    assert 0 < film["share_within"] <= 1 and film["min_um"] < film["mean_um"] < film["max_um"]


def test_paint_mesh_bad_input(capsys, tmp_path):
    bad = tmp_path / "junk.stl"
    bad.write_text("solid junk\nnot a facet\n")
    code, out, err = run(capsys, "paint", "mesh", bad, "--out", tmp_path / "o")
    assert code == 2 and "junk.stl" in err and len(err.strip().splitlines()) == 1
    code, out, err = run(capsys, "paint", "mesh", "panel", "--duration", "20", "--out", tmp_path / "o")
    assert code == 2 and "--speed" in err
    code, out, err = run(capsys, "paint", "mesh", "nothing-here", "--out", tmp_path / "o")
    assert code == 2 and "nothing-here" in err
    code, out, err = run(capsys, "paint", "mesh", "panel", "--gun", tmp_path / "gun.toml",
                         "--out", tmp_path / "o")
    assert code == 2 and "gun.toml" in err
    assert not (tmp_path / "o").exists()


def test_gun_fit_command(capsys, tmp_path):
    sigma, q0, v = 25.0, 80.0, 300.0
    y = np.linspace(-100, 100, 81)
    T = math.sqrt(2 * math.pi) * sigma * q0 / v * np.exp(-(y - 3.0) ** 2 / (2 * sigma ** 2))
    fp = tmp_path / "stripe.csv"
    fp.write_text("offset,thickness_um\n" + "\n".join(f"{a:.17g},{b:.17g}" for a, b in zip(y, T)) + "\n")
    code, out, err = run(capsys, "gun", "fit", fp, "--model", "gaussian", "--speed", v, "--standoff", 220)
    assert code == 0, err
    assert "residual rms" in out
    gun = load_gun(tmp_path / "stripe.toml")
    assert gun.model == "gaussian" and gun.standoff == 220.0
    assert gun.params["sigma"] == pytest.approx(sigma, rel=1e-6)
    assert gun.peak_rate == pytest.approx(q0, rel=1e-6)
    fp.write_text("x,thickness\n1,2\n")
    code, out, err = run(capsys, "gun", "fit", fp, "--model", "beta", "--speed", v, "--standoff", 220)
    assert code == 2 and "offset" in err


def test_film_instants_follow_the_step_rule():
    import ik7r
    from ik7r.painting.film import film_step
    from ik7r.painting.mesh import paint_mesh
    from ik7r.painting.parts import builtin_part

    robot = ik7r.load_robot()
    r = paint_mesh(robot, builtin_part("panel", cell=20.0), spacing=100.0, speed=600.0)
    poses, tr = r.poses, r.program.trajectory
    h = film_step(r.gun)
    assert r.step == h
    # the poses are the forward kinematics of the interpolated joints, in the part frame
    T = np.linalg.inv(r.part.T_base_part) @ robot.fk(tr.evaluate(poses.t)[0])
    np.testing.assert_allclose(poses.T_part_tool, T, atol=1e-9)
    # on sprayed intervals the pattern centre at the reference standoff moves at most h
    c = T[:, :3, 3] + r.gun.standoff * T[:, :3, 2]
    move = np.linalg.norm(np.diff(c, axis=0), axis=1)
    assert move[poses.sprayed].max() <= h * (1 + 1e-3)
    # the gun is on for the time the timing spends on the spray-on stretches: the sprayed length
    # at the commanded speed, plus what the ramps (slower, into and out of the time-optimal
    # turns) add; the ramps lie in the overspray, off the part
    path = r.program.path
    m = np.diff(np.concatenate([[0], path.spray.astype(int), [0]]))
    runs = zip(np.flatnonzero(m == 1), np.flatnonzero(m == -1) - 1)
    t_on = sum(float(tr.timing.t_of_u(path.u[b]) - tr.timing.t_of_u(path.u[a])) for a, b in runs)
    assert poses.spray_time == pytest.approx(t_on, rel=1e-3)
    ramps = tr.ramps
    assert len(ramps) > 0
    T_part_base = np.linalg.inv(r.part.T_base_part)
    for u0, u1 in ramps:
        x = (T_part_base[:3, :3] @ path.at(np.linspace(u0, u1, 50))[0].T + T_part_base[:3, 3:])[0]
        assert np.all(np.abs(x) >= 250.0 - 1e-9)
    extra = float(np.sum(tr.timing.t_of_u(ramps[:, 1]) - tr.timing.t_of_u(ramps[:, 0])
                         - (ramps[:, 1] - ramps[:, 0]) / 600.0))
    assert r.plan["sprayed_length"] / 600.0 * (1 - 1e-6) <= t_on <= r.plan["sprayed_length"] / 600.0 + extra


_HARNESS = r"""
const fs = require('fs'), vm = require('vm');
const html = fs.readFileSync(process.argv[2], 'utf8');
const js = html.match(/<script>([\s\S]*)<\/script>/)[1];
const calls = [];
const gl = new Proxy({}, {get(t, k) {
  if (typeof k === 'string' && k === k.toUpperCase()) return k;
  return (...a) => { calls.push(k); if (k === 'getAttribLocation') return 0;
    if (k.startsWith('create') || k === 'getExtension') return {}; };
}});
function el() { return {style: {}, textContent: '', appendChild() {}, clientWidth: 800, clientHeight: 600,
  getContext() { return gl; }}; }
const els = {};
const ctx = {atob, Float32Array, Uint32Array, Uint8Array, Math, window: {}, body: {},
  document: {getElementById(id) { return els[id] || (els[id] = el()); }, createElement: el, body: {}}};
vm.createContext(ctx);
vm.runInContext(js + ';globalThis.M = matrix(); globalThis.C = ctr; globalThis.N = idx.length;', ctx);
const M = ctx.M, c = ctx.C;
function proj(p) {
  const r = [0, 1, 2, 3].map(i => M[i] * p[0] + M[4 + i] * p[1] + M[8 + i] * p[2] + M[12 + i]);
  return r.map(x => x / r[3]); }
console.log(JSON.stringify({calls: calls.filter(k => k.startsWith('draw')), n: ctx.N,
  centre: proj(c), up: proj([c[0], c[1], c[2] + 100])}));
"""


def test_view_html_script_runs_and_projects(panel_run, tmp_path):
    """The embedded viewer runs (in node, with a stub WebGL context): it draws the part and the
    lines, and its camera puts the scene's centre mid-screen with the base's z up."""
    import shutil
    import subprocess

    node = shutil.which("node")
    if node is None:
        pytest.skip("node is not installed")
    _, out = panel_run
    js = tmp_path / "harness.js"
    js.write_text(_HARNESS)
    res = subprocess.run([node, str(js), str(out / "view.html")], capture_output=True, text=True,
                         timeout=60)
    assert res.returncode == 0, res.stderr
    r = json.loads(res.stdout)
    assert r["calls"] == ["drawElements", "drawArrays"]
    assert r["n"] == 3 * 6000  # the panel's triangles
    assert abs(r["centre"][0]) < 1e-6 and abs(r["centre"][1]) < 1e-6 and -1 < r["centre"][2] < 1
    assert r["up"][1] > 0.01


def test_units_everywhere_a_robot_in_metres_lays_the_same_film():
    import ik7r
    from ik7r.painting import load_part, paint_mesh
    from ik7r.robot import robot_in_unit

    mm = ik7r.load_robot()
    m = robot_in_unit(mm, "m")
    a = paint_mesh(mm, load_part("panel", unit="mm"), spacing=100.0, speed=600.0)
    b = paint_mesh(m, load_part("panel", unit="m"), spacing=0.1, speed=0.6)
    assert len(a.program.path) == len(b.program.path)
    assert b.step == pytest.approx(a.step / 1000)
    np.testing.assert_allclose(b.thickness, a.thickness, rtol=0, atol=1e-6 * a.thickness.max())
    with pytest.raises(ValueError, match="mm"):
        load_part("panel", part_unit="m")


def test_paint_mesh_from_a_file_in_metres_and_on_the_irb5400(capsys, tmp_path):
    import trimesh

    plate = trimesh.creation.box(extents=(0.4, 0.3, 0.01))  # a closed plate, in metres
    fp = tmp_path / "plate.stl"
    plate.export(fp)
    out = tmp_path / "o"
    code, stdout, err = run(capsys, "paint", "mesh", fp, "--part-unit", "m", "--frame", 1100, 0, -5, 0, 0, 0,
                            "--speed", 600, "--no-plots", "--out", out)
    assert code == 0, err
    rep = json.loads((out / "report.json").read_text())
    assert rep["part"]["painted_faces"] == 2  # the top of the box: the side the gun sees
    assert rep["film"]["painted_area"] == pytest.approx(400 * 300, rel=1e-5)
    th = np.loadtxt(out / "thickness.csv", delimiter=",", skiprows=1)
    assert np.abs(th[:, :3]).max() == pytest.approx(0.2, rel=1e-6)  # written back in metres
    out2 = tmp_path / "o2"
    code, stdout, err = run(capsys, "--robot", "irb5400", "paint", "mesh", "hood", "--speed", 600,
                            "--no-plots", "--out", out2)
    assert code == 0, err
    assert json.loads((out2 / "report.json").read_text())["film"]["mean_um"] > 0


def test_paint_mesh_without_acceleration_limits_runs_at_constant_path_speed():
    """The IRB 5400's URDF gives no acceleration limits: no time-optimal timing is possible, so
    the path runs at the constant path speed of the commanded gun speed, and says so; the gun's
    speed on every sprayed row (FK of the joint velocities) is the commanded one."""
    import ik7r
    from ik7r.painting import workpiece_frame
    from ik7r.painting.mesh import paint_mesh
    from ik7r.painting.parts import builtin_part

    robot = ik7r.load_robot("irb5400")
    assert robot.acceleration is None
    part = builtin_part("panel", T_base_part=workpiece_frame((1600.0, 0.0, 500.0)))
    res = paint_mesh(robot, part, spacing=100.0, speed=400.0, occlusion=False)
    assert "no joint acceleration limits" in res.plan["timing"] and "timing:" in res.report()
    tr = res.program.trajectory
    assert tr.spray.any()
    np.testing.assert_allclose(tr.gun_speed[tr.spray], 400.0, rtol=1e-3)
    assert np.all(tr.speed_ratio <= 1.0)
    assert res.stats.mean > 0
