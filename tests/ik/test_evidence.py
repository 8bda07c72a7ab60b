"""Issue 12, item 9: evidence that ``ik_all`` is complete at the singular sets and over the range.

Three kinds of evidence, none of which uses ik7r's code to judge ik7r:

* the solution *sets* at the singular sets against :mod:`reference_ik`, an independent solver
  (numpy and scipy, the DH table as written; see its docstring): every reference solution is
  among ``ik_all``'s answers, and every answer meets the pose on the reference's forward
  kinematics;
* property tests (hypothesis) over random family members, exact and rounded like a published
  datasheet (lengths to 1 mm, angles to 0.01 deg, which makes the wrist deviate from the
  mirror), at random and singular-set joints: the source joint vector is among the answers,
  every answer meets the pose, no two answers are one;
* a round-trip count over 100,000 IRB 5400 poses (``ik_all_batch``).

Where the solver still misses (issue 12 items 3 and 4: models that deviate from the family,
the IRB 5400 first), the test is an ``xfail(strict=False)`` naming the item and the count
measured, so that it passes (XPASS) once the fix is merged.
"""

from __future__ import annotations

import functools

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from reference_ik import KINDS, among, exact, family_member, reference_fk, reference_ik, singular_joints

import ik7r
from ik7r.robot import Robot


def _wrap(x):
    return np.pi - np.mod(np.pi - np.asarray(x), 2 * np.pi)


def _robot(name: str) -> Robot:
    """The robots of the set comparisons: the paper's, the IRB 5400 (a published model), and
    generated members (seeded): with shoulder, elbow and lateral offsets; without lateral
    offset and rounded like a datasheet; and with the family's largest twist, 45 deg."""
    if name in ("paper", "irb5400"):
        return ik7r.load_robot(name)
    rng = np.random.default_rng({"offsets": 11, "rounded": 12, "beta45": 13}[name])
    if name == "offsets":
        return Robot(name=name, dh=family_member(rng))
    if name == "rounded":
        return Robot(name=name, dh=family_member(rng, lateral=False, rounded=True))
    return Robot(name=name, dh=family_member(rng, beta_deg=45.0, lateral=False))


def _has_lateral(robot) -> bool:
    return abs(robot.dh[1, 2] + robot.dh[2, 2]) > 0.0


def duplicates(robot, sols) -> int:
    """Pairs of answers that are one solution by ik7r's documented rule: closer than 1e-5 rad in
    every joint, or both at a straight wrist (abs(q5) < 1e-9) with the same q1, q2, q3 and
    ``s4 q4 + s7 q7`` within 1e-5."""
    n = 0
    s4, s7 = robot.joint_sign[3], robot.joint_sign[6]
    for i in range(len(sols)):
        for j in range(i):
            d = np.abs(_wrap(sols[i] - sols[j]))
            if d.max() < 1e-5:
                n += 1
            elif abs(sols[i][4]) < 1e-9 and abs(sols[j][4]) < 1e-9:
                tot = abs(_wrap(s4 * (sols[i][3] - sols[j][3]) + s7 * (sols[i][5] - sols[j][5])))
                n += max(d[[0, 1, 2, 4]].max(), tot) < 1e-5
    return n


# ---------------------------------------------------------------- solution sets against the reference
#: (robot, kind) -> the reason the set comparison is expected to fail today, with the count of
#: poses (of _SET_POSES) measured on this branch.
_DEV = "issue 12 items 3-4 open (models that deviate from the family): "
_SET_OPEN: dict[tuple[str, str], str] = {
    ("irb5400", "bent"): _DEV + "1 reference solution missed in 1 of 3 poses: the answer at the "
                         "fully bent wrist is q5 = 180 deg - 1e-5 (q4 6e-6 off), exact, a shadow of the "
                         "reference's q5 = 180 deg beyond among's 1e-6 (the two wrist solutions within "
                         "1e-5 are one)",
}

_SET_POSES = 3
_SET_CASES = [(r, k) for r in ("paper", "irb5400", "offsets", "rounded", "beta45")
              for k in KINDS + ("random",) if not (r == "offsets" and k.endswith("shoulder"))]
# (the lateral offset's shoulder set, the cylinder of radius b, last: the cases' seeds follow the list)
_SET_CASES += [("offsets", "shoulder"), ("offsets", "near_shoulder")]


def _set_param(r, k):
    if (r, k) in _SET_OPEN:
        return pytest.param(r, k, marks=pytest.mark.xfail(strict=False, reason=_SET_OPEN[(r, k)]))
    return pytest.param(r, k)


@pytest.mark.parametrize(("name", "kind"), [_set_param(r, k) for r, k in _SET_CASES])
def test_solution_set_against_reference(name, kind):
    """Every solution the reference finds is among ``ik_all``'s answers (and the source is), and
    every answer meets the pose on the reference's forward kinematics. The reference must find
    the source itself on the exact family members; on models that deviate (the IRB 5400, the
    rounded member) it is also started from the source, since next to the singular sets their
    exact solutions can lie beyond its idealised scans' nets (see reference_ik)."""
    robot = _robot(name)
    rng = np.random.default_rng(1209 + _SET_CASES.index((name, kind)))
    Q = (rng.uniform(-np.pi, np.pi, (_SET_POSES, 6)) if kind == "random"
         else singular_joints(robot, rng, kind, _SET_POSES))
    deviating = name in ("irb5400", "rounded")
    poses_missed, sols_missed = 0, 0
    for q in Q:
        T = reference_fk(robot, q)
        sols = robot.ik_all(T)
        ref = reference_ik(robot, T, extra_starts=q[None] if deviating else None)
        dp, dr, ok = exact(robot, sols, T)
        assert ok.all(), (q.tolist(), dp.max(), dr.max())
        assert among(robot, ref, q, T), ("the reference missed its source", q.tolist())
        missed = sum(not among(robot, sols, r, T) for r in ref)
        poses_missed += missed > 0
        sols_missed += missed
    assert (poses_missed, sols_missed) == (0, 0), \
        f"{sols_missed} reference solutions missed in {poses_missed} poses"


# ---------------------------------------------------------------- property tests over family members
def _check_round_trip(robot, q):
    """The source q is among ik_all's answers of its own pose, every answer meets the pose on
    the reference's forward kinematics, and no two answers are one. Returns whether the source
    was found (the other two are asserted)."""
    T = reference_fk(robot, q)
    sols = robot.ik_all(T)
    dp, dr, ok = exact(robot, sols, T)
    assert ok.all(), (q.tolist(), dp.max(), dr.max())
    assert duplicates(robot, sols) == 0, q.tolist()
    return among(robot, sols, q, T)


_MEMBER = dict(seed=st.integers(0, 2**32 - 1), kind=st.sampled_from(KINDS + ("random",)),
               lateral=st.booleans())


def _member_sources_missed(name, seed, kind, lateral, **member):
    """Two sources on a random family member (``member``: :func:`family_member`'s options), at
    random joints or on the singular set ``kind``: those not among their pose's answers."""
    rng = np.random.default_rng(seed)
    robot = Robot(name=name, dh=family_member(rng, lateral=lateral, **member))
    Q = rng.uniform(-np.pi, np.pi, (2, 6)) if kind == "random" else singular_joints(robot, rng, kind, 2)
    return [q.tolist() for q in Q if not _check_round_trip(robot, q)]


@settings(max_examples=30, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(beta=st.one_of(st.just(None), st.just(45.0)), **_MEMBER)
def test_family_members_round_trip(seed, kind, lateral, beta):
    """Exact family members (twists (-beta, 2 beta, -beta), beta in [15, 45] deg or 45 deg, any
    offsets), joints at random or on a singular set: two sources each."""
    assert _member_sources_missed("member", seed, kind, lateral, beta_deg=beta) == []


@settings(max_examples=30, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(**_MEMBER)
def test_rounded_members_round_trip(seed, kind, lateral):
    """Family members rounded like a published datasheet (lengths to 1 mm, angles to 0.01 deg:
    the wrist deviates from the mirror by up to 0.01 deg), joints at random or on a singular set
    (of the unrounded geometry): two sources each."""
    assert _member_sources_missed("rounded", seed, kind, lateral, rounded=True) == []


# ---------------------------------------------------------------- 100,000 IRB 5400 poses
@functools.cache
def _irb5400_100k(n=100_000, seed=120900):
    """Sources uniform in [-pi, pi]^6 made into poses by the reference's forward kinematics,
    solved by ``ik_all_batch`` once for the two tests below: (missed sources, answers, whether
    every answer meets its pose on the reference's forward kinematics, the worst position error,
    examples of missed sources)."""
    robot = ik7r.load_robot("irb5400")
    rng = np.random.default_rng(seed)
    Q = rng.uniform(-np.pi, np.pi, (n, 6))
    T = reference_fk(robot, Q)
    S, valid = robot.ik_all_batch(T)
    near = np.full(n, np.inf)
    for k in range(S.shape[1]):  # column by column: small temporaries
        d = np.abs(_wrap(S[:, k] - Q)).max(axis=1)
        near = np.where(valid[:, k], np.minimum(near, d), near)
    missed = [i for i in np.flatnonzero(near > 1e-6) if not among(robot, S[i][valid[i]], Q[i], T[i])]
    rows = np.repeat(np.arange(n), valid.sum(axis=1))
    dp, dr, ok = exact(robot, S[valid], T[rows])
    return (len(missed), int(valid.sum()), bool(ok.all()), float(dp.max()),
            [Q[i].tolist() for i in missed[:3]])


def test_irb5400_100k_answers_are_exact():
    """100,000 IRB 5400 poses: every answer of ``ik_all_batch`` meets its pose to the robot's
    tolerance on the reference's own forward kinematics, and there are at least as many answers
    as poses (each pose was made from a joint vector)."""
    _, answers, all_exact, worst, _ = _irb5400_100k()
    assert answers >= 100_000
    assert all_exact, f"an answer misses its pose by {worst:.3g} mm"


def test_irb5400_100k_round_trip():
    """100,000 IRB 5400 sources uniform in [-pi, pi]^6: every source is among its pose's answers
    (1 missed before the straight-wrist scan's second sheet at the shoulder set, 4 before the near
    misses of each shoulder branch and the exact shoulder scan, 28 before the exact-model scans)."""
    missed, _, _, worst, examples = _irb5400_100k()
    assert missed == 0, f"{missed} of 100,000 sources missed (worst answer error {worst:.3g} mm): {examples}"
