"""Bad input to every public function: a typed error saying what was expected and what came."""

import numpy as np
import pytest

import ik7r
from ik7r.ik.numeric import damped_least_squares, manipulability, newton_raphson


@pytest.fixture(scope="module")
def T(robot):
    return robot.fk(np.radians([60, 60, 0, -30, 60, 30]))


def _not_orthonormal(T):
    bad = T.copy()
    bad[:3, :3] *= 1.001
    return bad


def _nan(T):
    bad = T.copy()
    bad[0, 3] = np.nan
    return bad


def _improper(T):
    bad = T.copy()
    bad[:3, 0] *= -1  # det = -1
    return bad


def _bottom(T):
    bad = T.copy()
    bad[3, 0] = 0.5
    return bad


@pytest.mark.parametrize("bad,match", [
    (_not_orthonormal, "not proper orthonormal.*expected within 1e-06"),
    (_nan, "NaN or infinity"),
    (_improper, "det = -1"),
    (_bottom, "bottom row"),
])
@pytest.mark.parametrize("call", ["ik", "ik_all", "ik_paper", "newton_raphson", "dls"])
def test_bad_pose_raises(robot, T, bad, match, call):
    Tb = bad(T)
    fn = {
        "ik": lambda: robot.ik(Tb, 1),
        "ik_all": lambda: robot.ik_all(Tb),
        "ik_paper": lambda: robot.ik_paper(Tb, 1, theta5_start=0.3),
        "newton_raphson": lambda: newton_raphson(robot, Tb, np.zeros(6)),
        "dls": lambda: damped_least_squares(robot, Tb, np.zeros(6)),
    }[call]
    with pytest.raises(ValueError, match=match):
        fn()


@pytest.mark.parametrize("shape", [(4,), (3, 4), (4, 3), (2, 4, 4)])
def test_wrong_pose_shape(robot, shape):
    arr = np.broadcast_to(np.eye(4), shape).copy() if shape[-2:] == (4, 4) else np.zeros(shape)
    with pytest.raises(ValueError, match=r"shape"):
        robot.ik_all(arr)
    with pytest.raises(ValueError, match=r"shape"):
        robot.ik(arr, 1)


@pytest.mark.parametrize("shape", [(4, 4), (4,), (2, 3, 4)])
def test_batch_wrong_shape(robot, shape):
    arr = np.broadcast_to(np.eye(4), shape).copy() if shape[-2:] == (4, 4) else np.zeros(shape)
    with pytest.raises(ValueError, match=r"shape \((N|\.\.\.), 4, 4\).*got"):
        robot.ik_batch(arr, 1)
    with pytest.raises(ValueError, match=r"shape \((N|\.\.\.), 4, 4\).*got"):
        robot.ik_all_batch(arr)


def test_non_numeric_pose(robot):
    with pytest.raises(ValueError, match="numbers"):
        robot.ik_all([["a"] * 4] * 4)


@pytest.mark.parametrize("config", [0, 9, -1, 2.5, "1", True, (1, 1), (1, 1, 2), (1, 0, -1), None])
def test_unknown_config(robot, T, config):
    with pytest.raises(ValueError, match="config"):
        robot.ik(T, config)
    with pytest.raises(ValueError, match="config"):
        robot.ik_batch(T[None], config)
    with pytest.raises(ValueError, match="config"):
        robot.ik_paper(T, config, theta5_start=0.3)


@pytest.mark.parametrize("q,match", [
    (np.zeros(5), r"shape \(\.\.\., 6\)"),
    (np.zeros(7), r"shape \(\.\.\., 6\)"),
    (np.array([0, 0, np.nan, 0, 0, 0]), "finite"),
    (np.array([0, 0, np.inf, 0, 0, 0]), "finite"),
    (3.0, r"shape"),
    ("abc", "numbers"),
])
def test_bad_joints(robot, q, match):
    for fn in (robot.fk, robot.frames, robot.jacobian, robot.config_of, robot.indicators,
               lambda x: manipulability(robot, x)):
        with pytest.raises(ValueError, match=match):
            fn(q)


def test_bad_seed(robot, T):
    with pytest.raises(ValueError, match="seed"):
        robot.ik(T, 1, seed=np.zeros(5))
    with pytest.raises(ValueError, match="seed"):
        robot.ik_all(T, seed=[np.nan] * 6)


def test_robot_constructor_rejects_bad_tables():
    from ik7r.robot.model import Robot

    with pytest.raises(ValueError, match=r"dh must have shape \(7, 4\)"):
        Robot("x", np.zeros((6, 4)))
    good = ik7r.load_robot()
    with pytest.raises(ValueError, match="lower limits"):
        good.replace(lower=good.upper + 1)
    with pytest.raises(ValueError, match="rigid transform"):
        good.with_tool(np.diag([2.0, 1, 1, 1]))
    with pytest.raises(ik7r.FamilyError):
        dh = good.dh.copy()
        dh[4, 1] = np.radians(10)  # twist of joint 5 breaks the mirror wrist
        good.replace(dh=dh)
