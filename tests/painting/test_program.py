"""Issue 16: the RAPID module and the JSON program, read back and checked by forward kinematics.

The module is parsed by ``rapid_reader`` (written from the RAPID syntax, not from ik7r's writer);
every target's axes (deg) go through the independent eq. (1) product, and the spray state of
every move is compared with the raster's geometry (on along the passes, off in the turns).
"""

from __future__ import annotations

import json

import numpy as np
import pytest
import rapid_reader
from helpers import dh_product

from ik7r.cli import main
from ik7r.geometry.rotations import invert
from ik7r.painting import make_program, paint_raster, workpiece_frame, write_program_json, write_rapid
from ik7r.painting.program import rapid_text

W, H, MARGIN, SPEED = 200.0, 100.0, 40.0, 400.0


@pytest.fixture(scope="module")
def painted(robot):
    return paint_raster(robot, speed=SPEED, size=(W, H), spacing=50.0, margin=MARGIN, step=10.0)


def _tip(robot, q_rad):
    T = np.array([dh_product(x) for x in q_rad]) @ robot.tool
    return (invert(robot.base) @ T)[:, :3, 3]


def _workpiece_xy(p):
    T_bw = workpiece_frame()
    return (p - T_bw[:3, 3]) @ T_bw[:3, :2]


def test_rapid_module_round_trip(robot, painted, tmp_path):
    prog = make_program(robot, painted.path, painted.trajectory)
    f = write_rapid(prog, tmp_path / "paint_raster.mod", moves_per_proc=40)
    mod = rapid_reader.parse(f.read_text())
    assert mod.name == "paint_raster" and "main" in mod.procs
    moves = rapid_reader.run(mod)
    n = len(painted.trajectory.knot_u)
    assert len(moves) == n  # the approach to the first target, then one move per target
    assert len(mod.procs) - 1 == int(np.ceil((n - 1) / 40))  # split into procedures of <= 40 moves
    # every target lies on the path (by FK of its axes, to the path's densely sampled points)
    q = np.radians([m.axes for m in moves])
    p = _tip(robot, q)
    uu = np.linspace(0, painted.path.u[-1], 200001)
    dense, _ = painted.path.at(uu)
    from scipy.spatial import cKDTree

    dist, _ = cKDTree(dense).query(p)
    spacing = np.linalg.norm(np.diff(dense, axis=0), axis=1).max()
    assert dist.max() <= 1e-4 + spacing / 2  # 6 decimals of a degree, and the sampling of the path
    assert all(m.external == [9e9] * 6 for m in moves)
    # the \T times add up to the planned duration; the approach is not timed
    assert moves[0].time is None and moves[0].zone == "fine"
    T = np.array([m.time for m in moves[1:]])
    assert np.all(T > 0)
    assert abs(T.sum() - painted.trajectory.duration) < 1e-6
    # the robot stops (fine) only at the end; other targets blend in a 1 mm zone
    assert moves[-1].zone == "fine" and {m.zone for m in moves[1:-1]} == {"zpath"}
    assert mod.zonedata["zpath"][:2] == ["FALSE", 1.0]
    # the gun: on along the passes (margins included), off in the turns, decided from geometry
    xy = _workpiece_xy(0.5 * (p[1:] + p[:-1]))
    on_pass = np.abs(xy[:, 0]) <= W / 2 + MARGIN + 1e-6
    state = np.array([m.outputs.get("doGunOn", 0) for m in moves[1:]])
    np.testing.assert_array_equal(state == 1, on_pass)
    assert moves[0].outputs == {"doGunOn": 0}
    assert rapid_reader.parse(f.read_text()).procs["main"][-1] == "SetDO doGunOn, 0;"


def test_rapid_signal_and_bad_names(robot, painted):
    prog = make_program(robot, painted.path, painted.trajectory, signal="doSpray1")
    text = rapid_text(prog, module="M1")
    assert "doGunOn" not in text and "SetDO doSpray1, 1;" in text
    with pytest.raises(ValueError, match="RAPID identifier"):
        make_program(robot, painted.path, painted.trajectory, signal="do gun")
    with pytest.raises(ValueError, match="module must be a RAPID identifier"):
        rapid_text(prog, module="1abc")


def test_json_program(robot, painted, tmp_path):
    prog = make_program(robot, painted.path, painted.trajectory)
    data = json.loads(write_program_json(prog, tmp_path / "p.json").read_text())
    assert data["format"] == "ik7r-program" and data["joints"] == ["q1", "q2", "q3", "q4", "q5", "q7"]
    tg = data["targets"]
    q = np.array([t["q_rad"] for t in tg])
    np.testing.assert_allclose(np.degrees(q), [t["q_deg"] for t in tg], atol=1e-12)
    np.testing.assert_allclose(_tip(robot, q), [t["position"] for t in tg], atol=1e-8)
    assert abs(sum(t["dt"] for t in tg) - data["duration"]) < 1e-9
    assert abs(data["duration"] - painted.trajectory.duration) < 1e-12
    xy = _workpiece_xy(0.5 * (_tip(robot, q[1:]) + _tip(robot, q[:-1])))
    np.testing.assert_array_equal([t["spray_after"] for t in tg[:-1]],
                                  np.abs(xy[:, 0]) <= W / 2 + MARGIN + 1e-6)


def test_cli_writes_program_and_pictures(tmp_path, capsys):
    out = tmp_path / "o"
    mod, js = tmp_path / "cell.mod", tmp_path / "cell.json"
    rc = main(["paint", "raster", "--size", "200", "100", "--spacing", "50", "--margin", "40", "--step", "10",
               "--speed", "400", "--no-animation", "--rapid", str(mod), "--program", str(js),
               "--signal", "doGun2", "--out", str(out)])
    assert rc == 0
    for name in ("gun_speed.png", "joint_limits.png", "figure12.png", "trajectory.csv", "report.txt"):
        assert (out / name).stat().st_size > 500, name
    moves = rapid_reader.run(rapid_reader.parse(mod.read_text()))
    assert {m.outputs.get("doGun2") for m in moves[1:]} == {0, 1}
    dur = json.loads(js.read_text())["duration"]
    assert abs(sum(m.time for m in moves[1:]) - dur) < 1e-6
    text = capsys.readouterr().out
    assert "gun speed 400 mm/s where the spray is on" in text and "within" in text
    # no stray temporary files next to the outputs
    assert sorted(p.name for p in tmp_path.iterdir()) == ["cell.json", "cell.mod", "o"]


@pytest.mark.parametrize("argv", [["--slow-down"], ["--speed", "100", "--duration", "3"], ["--speed", "-1"],
                                  ["--signal", "9x", "--speed", "100"],
                                  ["--rapid", "/nonexistent/dir/a.mod"]])
def test_cli_program_options_bad_input_exits_2(argv, tmp_path, capsys):
    assert main(["paint", "raster", "--size", "100", "0", "--out", str(tmp_path / "o")] + argv) == 2
    assert capsys.readouterr().err.startswith("error:")


def test_cli_too_fast_exits_1_with_the_report(tmp_path, capsys):
    rc = main(["paint", "raster", "--size", "300", "0", "--margin", "100", "--step", "10", "--speed", "4000",
               "--no-plots", "--out", str(tmp_path / "o")])
    assert rc == 1
    err = capsys.readouterr().err
    assert "commanded speed too high" in err and "--slow-down" in err
