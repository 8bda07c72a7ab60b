"""URDF robots: the ABB IRB 5400 file, generated family members, and clear errors."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from _urdf_fixtures import (
    SHARED_IRB5400,
    STYLES,
    chain_urdf,
    random_transform,
    reference_robots,
    yourdfpy_fk,
)

import ik7r
from ik7r.errors import FamilyError, RobotFileError
from ik7r.geometry.rotations import invert, wrap_angle
from ik7r.robot.urdf import robot_from_urdf_string

REFS = reference_robots()
FK_TOL = 1e-12  # metres and rotation entries
needs_irb = pytest.mark.skipif(not SHARED_IRB5400.is_file(), reason=f"{SHARED_IRB5400} not present")


# ---------------------------------------------------------------------------- helpers
def _solution_errors(robot, T, sols):
    """Largest position (robot unit) and rotation-entry errors of ``sols`` (M, 6) for pose T."""
    if len(sols) == 0:
        return 0.0, 0.0
    F = robot.fk(sols)
    return (float(np.linalg.norm(F[:, :3, 3] - T[:3, 3], axis=1).max()),
            float(np.abs(F[:, :3, :3] - T[:3, :3]).max()))


def _round_trip(robot, Q):
    """(worst position error, worst rotation error, indices of q not among ik_all(fk(q)))."""
    worst_p = worst_r = 0.0
    missed = []
    for n, q in enumerate(Q):
        T = robot.fk(q)
        sols = robot.ik_all(T)
        ep, er = _solution_errors(robot, T, sols)
        worst_p, worst_r = max(worst_p, ep), max(worst_r, er)
        if len(sols) == 0 or np.abs(wrap_angle(sols - q)).max(axis=1).min() > 1e-7:
            missed.append(n)
    return worst_p, worst_r, missed


def _irb_text():
    return SHARED_IRB5400.read_text()


def _load(text, **kw):
    return robot_from_urdf_string(text, source="test.urdf", **kw)


# ---------------------------------------------------------------------------- the IRB 5400
@pytest.fixture(scope="module")
def irb():
    return ik7r.load_robot(SHARED_IRB5400)


@needs_irb
def test_irb5400_fk_equals_the_urdf_chain(irb):
    rng = np.random.default_rng(1)
    Q = rng.uniform(irb.lower, irb.upper, (100, 6))
    T_ref = yourdfpy_fk(_irb_text(), irb.independent_joint_names, Q, "tool0", "base_link")
    assert irb.unit == "m"
    assert np.abs(irb.fk(Q) - T_ref).max() < FK_TOL
    T_graph = yourdfpy_fk(_irb_text(), irb.independent_joint_names, Q[:5], "tool0", "base_link",
                          scene_graph=True)
    assert np.abs(irb.fk(Q[:5]) - T_graph).max() < 1e-12


@needs_irb
def test_irb5400_parameters_are_the_published_ones(irb):
    f = irb.family
    # the description of the arm: 300 mm shoulder offset, 186 mm elbow offset, no lateral offset
    assert abs(f.a1) == pytest.approx(0.300, abs=1e-12)
    assert abs(f.a3) == pytest.approx(0.186, abs=1e-12)
    assert f.b == pytest.approx(0.0, abs=1e-12)
    # the rounded wrist numbers make d5 and d6 differ by about 0.085 mm
    assert abs(irb.dh[4, 2] - irb.dh[5, 2]) == pytest.approx(0.085e-3, abs=0.001e-3)
    assert irb.independent_joint_names == ("joint_1", "joint_2", "joint_3", "joint_4", "joint_5", "joint_6")
    assert irb.joint_names[5] == "joint_5b"
    np.testing.assert_array_equal(irb.lower, [-2.617, -1.396, -1.308, -6.0, -6.0, -6.0])
    np.testing.assert_array_equal(irb.upper, [2.617, 1.396, 1.308, 6.0, 6.0, 6.0])
    np.testing.assert_array_equal(irb.velocity, [2.3911, 2.3911, 2.3911, 8.1157, 6.1086, 9.3375])


@needs_irb
def test_irb5400_every_ik_all_solution_is_exact(irb):
    rng = np.random.default_rng(2)
    Q = rng.uniform(irb.lower, irb.upper, (300, 6))
    worst_p, worst_r, missed = _round_trip(irb, Q)
    assert worst_p <= irb.position_tolerance
    assert worst_r <= 1e-9
    assert missed == [], f"ik_all missed q for poses {[Q[n].tolist() for n in missed]}"


@needs_irb
def test_irb5400_ik_all_is_complete(irb):
    rng = np.random.default_rng(0)
    Q = rng.uniform(irb.lower, irb.upper, (300, 6))
    _, _, missed = _round_trip(irb, Q)
    assert missed == [], f"ik_all missed q for poses {[Q[n].tolist() for n in missed]}"


IRB_MISSED = [  # regression: joint vectors (within the limits) whose pose ik_all(fk(q)) once missed q
    [-0.4995756703741212, -0.841751579730159, -1.0705900326603772, 0.9639886318422075, -2.415646406172929,
     2.0639385354763125],
    [0.6347095611292173, 0.20312529104347954, 1.2826708485981848, -0.014543901339793663, 3.142285317698203,
     -5.609275077244243],
    [-0.4904632425521158, -0.9117545378310117, -1.1947921458190467, 0.5818634556120434,
     -0.20442334279054286, -5.935294606435218],
]


@needs_irb
@pytest.mark.parametrize("q", IRB_MISSED)
def test_irb5400_known_missed_solutions(irb, q):
    q = np.array(q)
    assert np.all((irb.lower <= q) & (q <= irb.upper))
    sols = irb.ik_all(irb.fk(q))
    assert len(sols) and np.abs(wrap_angle(sols - q)).max(axis=1).min() < 1e-7


@needs_irb
def test_builtin_irb5400_is_the_urdf_in_mm(irb):
    mm = ik7r.load_robot("irb5400")
    assert mm.unit == "mm"
    rng = np.random.default_rng(3)
    Q = rng.uniform(mm.lower, mm.upper, (200, 6))
    T_m, T_mm = irb.fk(Q), mm.fk(Q)
    assert np.abs(T_mm[:, :3, 3] - 1000.0 * T_m[:, :3, 3]).max() < 1e-12 * 1000 * 4  # 4 m reach, in mm
    assert np.abs(T_mm[:, :3, :3] - T_m[:, :3, :3]).max() < FK_TOL
    np.testing.assert_allclose(mm.lower, irb.lower, rtol=0, atol=1e-15)
    np.testing.assert_allclose(mm.upper, irb.upper, rtol=0, atol=1e-15)
    np.testing.assert_allclose(mm.velocity, irb.velocity, rtol=0, atol=1e-14)


@needs_irb
def test_base_and_tip_keywords():
    text = _irb_text()
    rng = np.random.default_rng(4)
    q = rng.uniform(-1, 1, (20, 6))
    names = ("joint_1", "joint_2", "joint_3", "joint_4", "joint_5", "joint_6")
    r = _load(text, tip="link_6")
    assert np.abs(r.fk(q) - yourdfpy_fk(text, names, q, "link_6", "base_link")).max() < FK_TOL
    r = _load(text, base="base_link", tip="tool0")
    assert np.abs(r.fk(q) - yourdfpy_fk(text, names, q, "tool0", "base_link")).max() < FK_TOL
    with pytest.raises(RobotFileError, match="not below"):
        _load(text, base="link_3", tip="base")
    with pytest.raises(RobotFileError, match="'nowhere' is not defined"):
        _load(text, tip="nowhere")
    with pytest.raises(FamilyError, match="has 5 revolute joints"):
        _load(text, base="link_1", tip="link_5b")


@needs_irb
def test_continuous_joint_has_no_limits():
    text = _irb_text().replace('<joint name="joint_1" type="revolute">',
                               '<joint name="joint_1" type="continuous">')
    text = text.replace('<limit effort="100" lower="-2.617" upper="2.617" velocity="2.3911"/>', "", 1)
    r = _load(text)
    assert (r.lower[0], r.upper[0]) == (-math.pi, math.pi)
    assert r.velocity is None  # joint_1 no longer gives one


# ---------------------------------------------------------------------------- generated robots
@pytest.mark.parametrize("extra_fixed", [False, True], ids=["plain", "extra_fixed"])
@pytest.mark.parametrize("style", STYLES)
@pytest.mark.parametrize("name", list(REFS))
def test_generated_urdf_fk(name, style, extra_fixed):
    ref = REFS[name]
    rng = np.random.default_rng([7, len(name), STYLES.index(style), extra_fixed])
    B = random_transform(rng)
    text = chain_urdf(ref, style, rng, extra_fixed=extra_fixed, world_T_base=B)
    robot = _load(text)
    q = rng.uniform(-math.pi, math.pi, (50, 6))
    assert np.abs(robot.fk(q) - ref.fk(q)).max() < FK_TOL
    T_urdf = yourdfpy_fk(text, robot.independent_joint_names, q[:8], "flange", "world")
    assert np.abs(robot.fk(q[:8]) - T_urdf).max() < FK_TOL
    np.testing.assert_array_equal(robot.lower, ref.lower)
    np.testing.assert_array_equal(robot.velocity, ref.velocity)
    assert robot.coupling == ref.coupling
    # the robot's own frames in the base link: base= drops the world -> base_link joint
    on_base = _load(text, base="base_link")
    assert np.abs(on_base.fk(q) - invert(B) @ ref.fk(q)).max() < FK_TOL


ROUND_TRIP = ["beta30_offsets", "beta40_irb_like", "paper_zero_offsets", "beta45_unequal"]


def test_wrist_twist_beyond_45_deg_is_refused_clearly():
    from ik7r.robot.family import MAX_BETA

    dh = np.array(REFS["beta45_unequal"].dh)
    b = math.radians(46.0)
    dh[4:7, 1] = np.sign(dh[4:7, 1]) * [b, 2 * b, b]
    with pytest.raises(ik7r.FamilyError, match=r"joint 5.*45\] deg; got 46 deg"):
        REFS["beta45_unequal"].replace(dh=dh)
    assert math.degrees(MAX_BETA) == pytest.approx(45.0)


@pytest.mark.parametrize("name", list(ROUND_TRIP))
def test_generated_ik_all_solutions_exact(name):
    ref = REFS[name]
    rng = np.random.default_rng(11)
    robot = _load(chain_urdf(ref, "random", rng, extra_fixed=True, world_T_base=random_transform(rng)))
    Q = rng.uniform(robot.lower, robot.upper, (60, 6))
    worst_p, worst_r, _ = _round_trip(robot, Q)
    assert worst_p <= robot.position_tolerance
    assert worst_r <= 1e-9


@pytest.mark.parametrize("name", list(ROUND_TRIP))
def test_generated_ik_all_is_complete(name):
    ref = REFS[name]
    rng = np.random.default_rng(12)
    robot = _load(chain_urdf(ref, "x", rng, world_T_base=random_transform(rng)))
    Q = rng.uniform(robot.lower, robot.upper, (60, 6))
    _, _, missed = _round_trip(robot, Q)
    assert missed == [], f"ik_all missed q for {len(missed)} of {len(Q)} poses"


# ---------------------------------------------------------------------------- errors
def _edit(text, old, new, count=1):
    assert old in text, old
    return text.replace(old, new, count)


IRB_OUT_OF_FAMILY = [
    ("prismatic", ('<joint name="joint_3" type="revolute">', '<joint name="joint_3" type="prismatic">'),
     r"joint 'joint_3' is prismatic"),
    ("no_mimic", ('<mimic joint="joint_5" multiplier="-1.0" offset="0"/>', ""), r"no <mimic> joint"),
    ("mimic_multiplier", ('multiplier="-1.0"', 'multiplier="-2.0"'), r"joint_5b.*multiplier -2"),
    ("mimic_same_way", ('multiplier="-1.0"', 'multiplier="1.0"'), r"'joint_5b'.*mirror.*multiplier -1"),
    ("mimic_wrong_joint", ('<mimic joint="joint_5"', '<mimic joint="joint_4"'),
     r"'joint_5b' mimics 'joint_4'.*'joint_5'"),
    ("not_intersecting", ('<origin rpy="0 0.6109 0" xyz="0.0693 0 0"/>',
                          '<origin rpy="0 0.6109 0" xyz="0.0693 0.02 0"/>'), r"joint_5.*intersect"),
    ("not_parallel", ('<origin rpy="0 0 0" xyz="0 0 1.200"/>', '<origin rpy="0.3 0 0" xyz="0 0 1.200"/>'),
     r"joint_3.*parallel"),
    ("nearly_parallel", ('<origin rpy="0 0 0" xyz="0 0 1.200"/>', '<origin rpy="1e-7 0 0" xyz="0 0 1.200"/>'),
     r"'joint_2' and 'joint_3' are almost but not exactly parallel"),
    ("not_perpendicular", ('<origin rpy="0 0 0" xyz="0.300 0 0.660"/>',
                           '<origin rpy="0.5 0 0" xyz="0.300 0 0.660"/>'), r"joint_2.*perpendicular"),
    ("wrist_not_mirror", ('<origin rpy="0 -1.2217 0" xyz=".106246 0 0.074394"/>',
                          '<origin rpy="0 -1.0 0" xyz=".106246 0 0.074394"/>'), r"mirror"),
    ("unequal_wrist_offsets", ('xyz=".106246 0 0.074394"', 'xyz=".156246 0 0.074394"'), r"d5 = d6"),
]


@needs_irb
@pytest.mark.parametrize("case", IRB_OUT_OF_FAMILY, ids=[c[0] for c in IRB_OUT_OF_FAMILY])
def test_out_of_family_urdf_gives_clear_error(case):
    _, (old, new), pattern = case
    text = _edit(_irb_text(), old, new)
    with pytest.raises(FamilyError, match=pattern) as info:
        _load(text)
    assert isinstance(info.value, ValueError)
    assert str(info.value).startswith("test.urdf")


@needs_irb
def test_wrong_number_of_joints():
    extra = ('<link name="link_7"/><joint name="joint_7" type="revolute"><parent link="tool0"/>'
             '<child link="link_7"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" velocity="1" effort="1"/>'
             "</joint></robot>")
    text = _edit(_irb_text(), "</robot>", extra)
    with pytest.raises(FamilyError, match=re.escape("has 8 revolute joints")):
        _load(text)
    deep = "".join(f'<link name="deep_{k}"/><joint name="deep_j{k}" type="fixed"><parent link="'
                   f'{"base" if k == 0 else f"deep_{k - 1}"}"/><child link="deep_{k}"/></joint>'
                   for k in range(12))
    text = _edit(_irb_text(), "</robot>", deep + "</robot>")
    with pytest.raises(FamilyError, match=r"base_link -> deep_11 has 0 revolute joints.*tip="):
        _load(text)
    assert _load(text, tip="tool0").joint_names[0] == "joint_1"

def _two_links(joint_type, inner=""):
    """A URDF with links a, b and one joint j of ``joint_type`` from a to b (``inner`` inside it)."""
    return (f"<robot><link name='a'/><link name='b'/><joint name='j' type='{joint_type}'>"
            f"<parent link='a'/><child link='b'/>{inner}</joint></robot>")


MALFORMED = [
    ("not_xml", "<robot name='x'><link name='a'></robot>", "not valid XML"),
    ("not_robot", "<model/>", "root element must be <robot>"),
    ("no_parent", "<robot><link name='a'/><link name='b'/><joint name='j' type='fixed'><child link='b'/>"
                  "</joint></robot>", "joint 'j': missing <parent"),
    ("unknown_link", "<robot><link name='a'/><joint name='j' type='fixed'><parent link='a'/><child link='b'/>"
                     "</joint></robot>", "refers to link 'b', which is not defined"),
    ("bad_xyz", _two_links("fixed", "<origin xyz='1 2'/>"), "<origin xyz> must be 3 finite numbers"),
    ("bad_type", _two_links("hinge"), "unknown type 'hinge'"),
    ("no_limit", _two_links("revolute"), "revolute joint needs <limit"),
    ("limits_reversed", _two_links("revolute", "<limit lower='1' upper='-1' velocity='1' effort='1'/>"),
     "lower limit 1 exceeds upper limit -1"),
    ("zero_axis", _two_links("continuous", "<axis xyz='0 0 0'/>"), "axis must not be zero"),
    ("two_roots", "<robot><link name='a'/><link name='b'/></robot>", "exactly one root link"),
    ("two_parents", "<robot><link name='a'/><link name='b'/><link name='c'/>"
                    "<joint name='j1' type='fixed'><parent link='a'/><child link='c'/></joint>"
                    "<joint name='j2' type='fixed'><parent link='b'/><child link='c'/></joint></robot>",
     "child of two joints"),
    ("bad_mimic", _two_links("continuous", "<mimic joint='k' multiplier='x'/>"),
     "'multiplier' must be a finite number"),
]


@pytest.mark.parametrize("case", MALFORMED, ids=[c[0] for c in MALFORMED])
def test_malformed_urdf_gives_clear_error(case):
    _, text, message = case
    with pytest.raises(RobotFileError, match=re.escape(message)) as info:
        _load(text)
    assert str(info.value).startswith("test.urdf")


def test_load_robot_urdf_file_errors(tmp_path):
    with pytest.raises(FileNotFoundError):
        ik7r.load_robot(tmp_path / "missing.urdf")
    bad = tmp_path / "bad.urdf"
    bad.write_text("<robot")
    with pytest.raises(RobotFileError, match=re.escape(str(bad))):
        ik7r.load_robot(bad)
    good = tmp_path / "good.urdf"
    good.write_text(chain_urdf(REFS["beta30_offsets"], "x", np.random.default_rng(0)))
    q = np.random.default_rng(1).uniform(-1, 1, (5, 6))
    assert np.abs(ik7r.load_robot(good).fk(q) - REFS["beta30_offsets"].fk(q)).max() < FK_TOL
    assert np.abs(ik7r.load_robot(str(good), tip="link_7").fk(q)
                  - yourdfpy_fk(good.read_text(), ik7r.load_robot(good).independent_joint_names, q, "link_7",
                                "world")).max() < FK_TOL
