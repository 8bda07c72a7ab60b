"""Robot files: the built-in robot, TOML reading and writing, and clear errors."""

import numpy as np
import pytest
from helpers import TABLE1

import ik7r
from ik7r.robot.files import robot_from_toml


def test_builtin_paper_robot_is_table1(robot):
    assert robot.unit == "mm" and robot.name == "paper"
    a, alpha, d = (np.array(c, dtype=float) for c in zip(*TABLE1))
    np.testing.assert_allclose(robot.dh[:, 0], a)
    np.testing.assert_allclose(np.degrees(robot.dh[:, 1]), alpha)
    np.testing.assert_allclose(robot.dh[:, 2], d)
    np.testing.assert_allclose(np.degrees(robot.lower), [-70, -80, -70, -360, -180, -360])
    np.testing.assert_allclose(np.degrees(robot.upper), [70, 135, 70, 360, 180, 360])


def test_toml_round_trip(robot, tmp_path, rng):
    path = tmp_path / "copy.toml"
    path.write_text(robot.to_toml())
    back = ik7r.load_robot(path)
    q = rng.uniform(-np.pi, np.pi, (20, 6))
    np.testing.assert_allclose(back.fk(q), robot.fk(q), atol=1e-9)
    np.testing.assert_allclose(back.lower, robot.lower)
    np.testing.assert_allclose(back.upper, robot.upper)


def test_missing_file():
    with pytest.raises(FileNotFoundError, match="no such robot file"):
        ik7r.load_robot("/nonexistent/robot.toml")
    with pytest.raises(FileNotFoundError):
        ik7r.load_robot("no_such_robot_name")


TOML_OK = """
name = "t"
unit = "mm"
[dh]
a = [0, 0, 1000, 0, 0, 0, 0]
alpha = [0, 90, 0, 90, -35, 70, -35]
d = [0, 0, 0, 900, 80, 80, 100]
[limits]
lower = [-70, -80, -70, -360, -180, -360]
upper = [70, 135, 70, 360, 180, 360]
"""


@pytest.mark.parametrize("edit,match", [
    (lambda s: s.replace("a = [0, 0, 1000, 0, 0, 0, 0]", "a = [0, 0, 1000]"), "'a'.*7"),
    (lambda s: s.replace("[dh]", "[dhx]"), "dh"),
    (lambda s: s + "\n[[[", "TOML"),
    (lambda s: s.replace("-35, 70, -35]", "-35, 70, 'x']"), "alpha"),
])
def test_malformed_toml_names_file_and_problem(tmp_path, edit, match):
    path = tmp_path / "bad.toml"
    path.write_text(edit(TOML_OK))
    with pytest.raises(ValueError, match=match) as info:
        ik7r.load_robot(path)
    assert "bad.toml" in str(info.value)


def test_valid_toml_text_loads():
    r = robot_from_toml(TOML_OK)
    assert r.name == "t"


def test_out_of_family_toml_names_joint(tmp_path):
    path = tmp_path / "odd.toml"
    path.write_text(TOML_OK.replace("alpha = [0, 90, 0, 90, -35, 70, -35]",
                                    "alpha = [0, 90, 30, 90, -35, 70, -35]"))
    with pytest.raises(ik7r.FamilyError, match="joint"):
        ik7r.load_robot(path)


def test_unknown_suffix(tmp_path):
    path = tmp_path / "robot.yaml"
    path.write_text("x: 1")
    with pytest.raises(ik7r.RobotFileError, match="expected .toml or .urdf"):
        ik7r.load_robot(path)
