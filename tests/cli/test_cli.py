"""The command line: degrees and mm; exit 0 on success, 1 when no solution, 2 on bad input."""

import json
import subprocess
import sys

import numpy as np
import pytest
from helpers import SIMULATION1_Q_DEG, TABLE2_DEG, dh_product

from ik7r.cli.app import main
from ik7r.geometry.rotations import matrix_to_rpy


def _num(x) -> str:
    return repr(float(x))


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_fk_prints_the_pose(capsys):
    code, out, err = run(capsys, "fk", *map(str, SIMULATION1_Q_DEG))
    assert code == 0 and err == ""
    T = dh_product(np.radians(SIMULATION1_Q_DEG))
    for value in T[:3, 3]:
        assert f"{value:.4f}" in out


def _pose_args(q_deg):
    T = dh_product(np.radians(q_deg))
    rpy = np.degrees(matrix_to_rpy(T[:3, :3]))
    return T, ["--position", *map(_num, T[:3, 3]), "--rpy", *map(_num, rpy)]


def test_ik_all_json_matches_table2(capsys):
    T, args = _pose_args(SIMULATION1_Q_DEG)
    code, out, err = run(capsys, "ik", *args, "--all", "--json")
    assert code == 0, err
    data = json.loads(out)
    sols = np.array([s["q_deg"] for s in data["solutions"]])
    assert len(sols) == 8
    for row in TABLE2_DEG:
        assert np.abs(sols - row).max(axis=1).min() < 5e-5
    for s in sols:
        F = dh_product(np.radians(s))
        assert np.linalg.norm(F[:3, 3] - T[:3, 3]) < 1e-6


def test_ik_one_config_with_matrix(capsys):
    T, _ = _pose_args(SIMULATION1_Q_DEG)
    code, out, err = run(capsys, "ik", "--matrix", *map(_num, T[:3].reshape(-1)), "--config", "3", "--json")
    assert code == 0, err
    q = np.array(json.loads(out)["solutions"][0]["q_deg"])
    np.testing.assert_allclose(q, TABLE2_DEG[2], atol=5e-5)


def test_unreachable_exits_1_with_one_line(capsys):
    code, out, err = run(capsys, "ik", "--position", "9000", "0", "0", "--rpy", "0", "0", "0", "--all")
    assert code == 1
    assert err.strip().count("\n") == 0 and "no solution" in err


def test_missing_configuration_exits_1(capsys):
    far = ["--position", "9000", "0", "0", "--rpy", "0", "0", "0"]
    code, out, err = run(capsys, "ik", *far, "--config", "2")
    assert code == 1 and "no solution" in err


@pytest.mark.parametrize("argv", [
    ["ik", "--position", "1", "2", "--rpy", "0", "0", "0"],
    ["ik", "--position", "1", "2", "x", "--rpy", "0", "0", "0"],
    ["ik", "--matrix", "1", "2", "3"],
    ["ik", "--position", "1000", "0", "0", "--rpy", "0", "0", "0", "--config", "9"],
    ["ik", "--matrix", *["1"] * 12],
    ["fk", "1", "2", "3"],
    ["fk", "1", "2", "3", "4", "5", "nan"],
    ["--robot", "/no/such/robot.toml", "fk", "0", "0", "0", "0", "0", "0"],
    ["nosuchcommand"],
])
def test_bad_input_exits_2_with_one_line(capsys, argv):
    code, out, err = run(capsys, *argv)
    assert code == 2
    assert err.startswith("error:") and err.strip().count("\n") == 0
    assert "Traceback" not in err


def test_console_script_runs_as_a_process():
    proc = subprocess.run([sys.executable, "-m", "ik7r", "ik", "--position", "9000", "0", "0",
                           "--rpy", "0", "0", "0", "--all"], capture_output=True, text=True)
    assert proc.returncode == 1 and "Traceback" not in proc.stderr


def test_one_shot_commands_run_without_numba_and_agree():
    """`ik7r ik` runs its kernels as plain Python (fast start-up): same answers as compiled."""
    import os

    args = ["ik", "--position", "733.5055", "1297.2539", "482.878", "--rpy", "0.4894", "-53.5252",
            "-115.2529", "--all", "--json"]
    env = dict(os.environ, IK7R_JIT="0")
    code = ("import sys, ik7r.cli.app; rc = ik7r.cli.app.main(sys.argv[1:]); "
            "assert 'numba' not in sys.modules, 'numba imported'; sys.exit(rc)")
    proc = subprocess.run([sys.executable, "-c", code, *args], capture_output=True, text=True, env=env)
    assert proc.returncode == 0, proc.stderr
    plain = np.array([s["q_deg"] for s in json.loads(proc.stdout)["solutions"]])
    compiled_out = subprocess.run([sys.executable, "-m", "ik7r", *args], capture_output=True, text=True,
                                  env=dict(os.environ, IK7R_JIT="1"))
    compiled = np.array([s["q_deg"] for s in json.loads(compiled_out.stdout)["solutions"]])
    assert plain.shape == compiled.shape == (8, 6)
    np.testing.assert_allclose(plain, compiled, atol=1e-9)
