"""Command-line habits: --robot anywhere, --version, usage on stderr, --json always JSON,
argument counts that say what was expected, rounded --matrix rotations projected."""

from __future__ import annotations

import json

import numpy as np
import pytest
from _run import assert_well_behaved, run_cli
from helpers import SIMULATION1_Q_DEG, SIMULATION1_T, dh_product

Q = [str(v) for v in SIMULATION1_Q_DEG]


def test_robot_before_or_after_the_subcommand_is_the_same():
    a = run_cli("--robot", "irb5400", "fk", *Q, "--json")
    b = run_cli("fk", *Q, "--robot", "irb5400", "--json")
    c = run_cli("fk", "--robot", "irb5400", *Q, "--json")
    assert a[0] == b[0] == c[0] == 0
    assert json.loads(a[1]) == json.loads(b[1]) == json.loads(c[1])
    assert json.loads(a[1])["robot"] == "irb5400"
    assert json.loads(run_cli("fk", *Q, "--json")[1])["robot"] == "paper"


def test_robot_after_nested_subcommands(tmp_path):
    code, out, err = run_cli("paint", "raster", "--robot", "paper", "--spacing", "0", "--out", tmp_path)
    assert code == 2 and "spacing" in err  # parsed: reached the raster's own check


def test_version():
    import ik7r

    code, out, err = run_cli("--version")
    assert code == 0 and out.strip() == f"ik7r {ik7r.__version__}" and err == ""


def test_bare_ik7r_prints_usage_on_stderr():
    code, out, err = run_cli()
    assert code == 2 and out == ""
    assert err.startswith("usage: ik7r") and len(err.splitlines()) <= 2


@pytest.mark.parametrize("argv, expected", [
    (["fk", "1", "2", "3", "4", "5"], "6 joint values (q1 q2 q3 q4 q5 q7, deg) expected, got 5"),
    (["fk", "1", "2", "3", "4", "5", "6", "7"], "6 joint values (q1 q2 q3 q4 q5 q7, deg) expected, got 7"),
    (["fk"], "6 joint values (q1 q2 q3 q4 q5 q7, deg) expected, got 0"),
    (["ik", "--matrix", "1", "0", "0"], "12 or 16 numbers expected (row by row), got 3"),
    (["ik", "--position", "1", "2", "--rpy", "0", "0", "0"], "expected 3 arguments"),
    (["ik", "--position", "1", "2", "3", "--rpy", "inf", "0", "0"], "expected a finite number, got 'inf'"),
    (["fk", "1", "2", "3", "4", "5", "nan"], "expected a finite number, got 'nan'"),
    (["batch", "--random", "-5", "--out", "x"], "expected a non-negative whole number"),
    (["batch", "--random", "1.5", "--out", "x"], "expected a whole number"),
])
def test_argument_messages_say_what_was_expected(argv, expected):
    code, out, err = run_cli(*argv)
    assert_well_behaved(code, err)
    assert code == 2 and expected in err, err


def test_negative_joints_are_values_not_options():
    code, out, err = run_cli("fk", "10", "-20", "0", "-30", "40", "-50", "--json")
    assert code == 0, err
    T = dh_product(np.radians([10, -20, 0, -30, 40, -50]))
    np.testing.assert_allclose(json.loads(out)["position"], T[:3, 3], atol=1e-9)


def _pose_args(q_deg):
    from ik7r.geometry.rotations import matrix_to_rpy

    T = dh_product(np.radians(q_deg))
    rpy = np.degrees(matrix_to_rpy(T[:3, :3]))
    return ["--position", *map(repr, T[:3, 3].tolist()), "--rpy", *map(repr, rpy.tolist())]


@pytest.mark.parametrize("mode", [["--all"], ["--config", "1"]])
def test_json_on_an_unreachable_pose_is_an_empty_list(mode):
    code, out, err = run_cli("ik", "--position", "5000", "0", "0", "--rpy", "0", "0", "0", *mode, "--json")
    assert code == 1
    data = json.loads(out)
    assert data["solutions"] == [] and data["robot"] == "paper"
    assert len(err.splitlines()) == 1 and err.startswith("no solution")


@pytest.mark.parametrize("argv", [
    ["ik", "--matrix", "1", "2", "3", "--json"],
    ["ik", "--position", "1", "2", "3", "--json"],
    ["fk", "1", "2", "--json"],
    ["ik", "--json", "--robot", "/nonexistent.toml", "--position", "1", "2", "3", "--rpy", "0", "0", "0"],
])
def test_json_on_bad_input_is_still_json(argv):
    code, out, err = run_cli(*argv)
    assert code == 2 and len(err.splitlines()) == 1
    data = json.loads(out)
    assert data["status"] == 2 and data["error"] in err


def test_matrix_rounded_to_four_decimals_is_projected_with_a_note():
    """The paper prints Simulation 1's pose to 4 decimals (orthonormality error about 1e-4): the
    command line projects it onto the nearest rotation (here checked against scipy's), says so
    in one line, and solves that pose exactly."""
    from scipy.spatial.transform import Rotation

    vals = [repr(float(v)) for v in SIMULATION1_T[:3].reshape(-1)]
    code, out, err = run_cli("ik", "--matrix", *vals, "--all", "--json")
    assert code == 0, err
    assert len(err.splitlines()) == 1 and err.startswith("note: --matrix rotation projected")
    R = Rotation.from_matrix(SIMULATION1_T[:3, :3]).as_matrix()  # nearest rotation (independent)
    sols = [s["q_deg"] for s in json.loads(out)["solutions"]]
    assert len(sols) == 8
    for s in sols:
        F = dh_product(np.radians(s))
        assert np.abs(F[:3, 3] - SIMULATION1_T[:3, 3]).max() < 1e-6
        assert np.abs(F[:3, :3] - R).max() < 1e-9


def test_matrix_beyond_the_cli_tolerance_is_refused():
    M = SIMULATION1_T.copy()
    M[0, 0] += 0.01
    code, out, err = run_cli("ik", "--matrix", *map(repr, M[:3].reshape(-1).tolist()))
    assert code == 2 and "not proper orthonormal" in err and len(err.splitlines()) == 1


def test_the_api_stays_strict_and_offers_the_projection_explicitly():
    import ik7r
    from ik7r.geometry.checks import check_transforms, project_transforms

    with pytest.raises(ValueError, match="not proper orthonormal"):
        check_transforms(SIMULATION1_T)
    with pytest.raises(ValueError):
        ik7r.load_robot().ik_all(SIMULATION1_T)
    T, err, moved = project_transforms(SIMULATION1_T)
    assert 1e-6 < err < 1e-3 and 0 < moved < 1e-3
    R = T[:3, :3]
    np.testing.assert_allclose(R.T @ R, np.eye(3), atol=1e-14)
    assert np.linalg.det(R) > 0
    with pytest.raises(ValueError, match="det"):
        project_transforms(np.diag([1.0, 1.0, -1.0, 1.0]))
    assert len(ik7r.load_robot().ik_all(T)) == 8


def test_huge_numbers_at_the_prompt_give_one_line():
    for argv in (["ik", "--position", "1e308", "0", "0", "--rpy", "0", "0", "0", "--all"],
                 ["ik", "--position", "1e308", "-1e308", "1e308", "--rpy", "1e308", "0", "0"],
                 ["fk", "1e308", "0", "0", "0", "0", "0"]):
        code, out, err = run_cli(*argv)
        assert_well_behaved(code, err)
        assert len(err.splitlines()) <= 1


def test_batch_poses_rounded_by_another_tool_are_projected_with_a_note(tmp_path):
    from scipy.spatial.transform import Rotation

    import ik7r

    robot = ik7r.load_robot()
    q = np.random.default_rng(17).uniform(-1, 1, (30, 6))
    T = np.round(robot.fk(q), 4)  # as exported with 4 decimals
    T[3, 0, 0] += 0.01  # beyond the command line's 1e-3: stays a bad row
    np.save(tmp_path / "poses.npy", T)
    code, out, err = run_cli("batch", "--poses", tmp_path / "poses.npy", "--out", tmp_path / "s", "--json")
    assert code == 0, err
    assert len(err.splitlines()) == 1 and "29 poses" in err and "projected" in err
    assert json.loads(out)["invalid"] == 1
    sols = np.load(tmp_path / "s" / "q.npy")
    off = np.load(tmp_path / "s" / "offsets.npy")
    assert off[4] == off[3]  # the bad row has no solution
    for i in (0, 10, 29):
        R = Rotation.from_matrix(T[i, :3, :3]).as_matrix()  # the nearest rotation, independently
        assert off[i + 1] > off[i]
        for s in sols[off[i]:off[i + 1]]:
            F = dh_product(s)
            assert np.abs(F[:3, 3] - T[i, :3, 3]).max() < 1e-6 and np.abs(F[:3, :3] - R).max() < 1e-9
