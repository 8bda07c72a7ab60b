"""The random-member hunt of issue 12: sources that ``ik_all`` misses on random family members.

Public API and the tests' independent reference only. For a seed, draws MEMBERS random members
(``reference_ik.family_member(rounded=True)``: lengths to 1 mm and angles to 0.01 deg as a
datasheet gives them, which leaves most members deviating from the idealised family; a third
of them at the 45 deg twist unless ``--beta``, half with lateral offsets unless ``--lateral``),
then for each POSES joint vectors of each kind (uniform, and ``reference_ik.singular_joints``'s singular
sets; the shoulder set only without lateral offset unless ``--lateral-shoulder``, which places
the centre on or beside the cylinder of radius b where a lateral arm's shoulder branches meet),
makes the poses by forward kinematics and
checks each source among the answers (``reference_ik.among``, 1e-6 rad). A source not among
them is printed on one line (``m`` when no answer is within DUP_TOL = 1e-5 rad in every joint,
a miss; ``d`` when one is, one solution by the solver's documented rule; ``v`` when none is
but the path of least pose error from the source to one of its three nearest answers meets the
pose all along: a point of that answer's valley beyond ``among``'s reach of 1e-2 rad, where the
shoulder set and a nearly straight wrist meet and the pose is met along a valley longer than
the solver's MERGE_WINDOW; ``r`` when ``ik_all`` raised, counted a miss) with its member's DH table
and its joints, ready to be made a test.
The counts of misses and of such valley points end the output.

``--frames``: each member is also written in other frames, as a URDF or a datasheet may give it
(random joint signs, theta offsets, the coupling that keeps theta6 = -theta5, a random base and
tool); ``--frames mirror`` also flips the signs of lengths and twists the family allows (a1, a2,
a3, d4, d5 = d6, d7, beta): a mirrored robot, placed on its singular sets by the reference all the
same. The case line then carries the robot's signs, coupling, base and tool.

``--deviate F``: each member also deviates from the idealised family by up to F (0 .. 1) of what
the loader accepts (``ik7r.robot.family.ANGLE_TOL`` and ``LENGTH_TOL``): every twist it checks, the
offsets a4 .. a6 that must vanish, d5 and d6 apart, and the mirror offset of theta5 + theta6,
each drawn uniformly within its share of the limit (so that the table still loads).

``--kinds fold_axis`` (not among the defaults): the wrist within 1e-2 of fully bent and the
approach within 3e-2 rad of axis 1 (``reference_ik.singular_joints``); with ``--beta 45`` axes 1,
4 and 7 are then (nearly) parallel.

Run: ``python benchmarks/hunt.py SEED [MEMBERS] [POSES] [--kinds k1,k2] [--lateral] [--lateral-shoulder]
[--beta mix|random|DEG] [--frames [mirror]] [--deviate F [--deviate-only C1,C2]]``
(docs/guide/edges.md has the counts of earlier hunts: the all-kinds hunt is the defaults; the
stretched-elbow one ``--kinds stretched --lateral --beta random`` with 100 members and 400 poses).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from ik7r.geometry import quat_to_matrix, transform
from ik7r.robot import Robot
from ik7r.robot.family import ANGLE_TOL, LENGTH_TOL

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from reference_ik import KINDS, among, family_member, least_error_path_meets, singular_joints  # noqa: E402

#: Two answers closer than this (rad, every joint) are one solution (the solver's DUP_TOL).
DUP_TOL = 1e-5
#: A source farther than that is checked for a path of least pose error to its this many nearest answers.
VALLEY_NEAREST = 3


def _wrap(x):
    return np.pi - np.mod(np.pi - np.asarray(x), 2 * np.pi)


def _rigid(rng, reach: float) -> np.ndarray:
    """A random rigid transform (4, 4): a uniform rotation (a normal quaternion), a translation
    within +-reach."""
    R = quat_to_matrix(rng.normal(size=4))
    return transform(R, rng.uniform(-reach, reach, 3))


def _framed(rng, dh: np.ndarray, name: str, mirror: bool) -> Robot:
    """The member ``dh`` with random joint signs, theta offsets, base and tool (the coupling set
    so that theta6 = -theta5 still); ``mirror``: each allowed sign of a length or of beta flipped
    with probability 1/2 first."""
    dh = np.array(dh, float)
    if mirror:
        for i, j in ((1, 0), (2, 0), (3, 0), (3, 2), (6, 2)):
            dh[i, j] *= rng.choice([-1.0, 1.0])
        dh[4:6, 2] *= rng.choice([-1.0, 1.0])
        dh[4:7, 1] *= rng.choice([-1.0, 1.0])
    sign = rng.choice([-1.0, 1.0], 7)
    dh[:, 3] = np.round(rng.uniform(-180.0, 180.0, 7), 2) * np.pi / 180.0
    coupling = (-sign[4] * sign[5], -(dh[4, 3] + dh[5, 3]) * sign[5])
    return Robot(name=name, dh=dh, joint_sign=sign, coupling=coupling,
                 base=_rigid(rng, 1000.0), tool=_rigid(rng, 300.0))


#: The parameter classes ``--deviate`` draws (``--deviate-only`` picks some).
DEVIATIONS = ("arm_twists", "wrist_twists", "wrist_offsets", "wrist_lengths", "mirror_offset")


def _deviated(rng, dh: np.ndarray, f: float, only=DEVIATIONS) -> np.ndarray:
    """The member ``dh`` deviating from the idealised family by up to ``f`` of the loader's limits
    (see ``--deviate``): the arm's twists by up to f ANGLE_TOL / 2, the wrist's by up to
    f ANGLE_TOL / 3 each (the mirror's test compares them with one another), a4 .. a6 by up to
    f LENGTH_TOL size / 2, d5 and d6 by up to f LENGTH_TOL size / 4 each, theta5's offset by up to
    f ANGLE_TOL / 2."""
    dh = np.array(dh, float)
    size = np.abs(dh[1:4, 0]).sum() + np.abs(dh[3:7, 2]).sum()
    u = {k: rng.uniform(-f, f, n) for k, n in zip(DEVIATIONS, (3, 3, 3, 2, 1))}  # (the same draws
    u = {k: (v if k in only else 0.0 * v) for k, v in u.items()}  # whichever classes deviate)
    dh[1:4, 1] += u["arm_twists"] * ANGLE_TOL / 2
    dh[4:7, 1] += u["wrist_twists"] * ANGLE_TOL / 3
    dh[4:7, 0] += u["wrist_offsets"] * LENGTH_TOL * size / 2
    dh[4:6, 2] += u["wrist_lengths"] * LENGTH_TOL * size / 4
    dh[4, 3] += u["mirror_offset"][0] * ANGLE_TOL / 2
    return dh


def _one_by_one(robot: Robot, T: np.ndarray):
    """``ik_all`` pose by pose: answers and all-True masks, None where it raised."""
    S, V = [], []
    for t in T:
        try:
            sols = robot.ik_all(t)
        except RuntimeError:
            sols = None
        S.append(sols)
        V.append(None if sols is None else np.ones(len(sols), bool))
    return S, V


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("seed", type=int)
    ap.add_argument("members", type=int, nargs="?", default=40)
    ap.add_argument("poses", type=int, nargs="?", default=300)
    ap.add_argument("--kinds", default=",".join(("uniform",) + KINDS))
    ap.add_argument("--lateral", action="store_true", help="every member with lateral offsets")
    ap.add_argument("--lateral-shoulder", action="store_true",
                    help="the shoulder kinds on members with lateral offsets too (the cylinder of radius b)")
    ap.add_argument("--frames", nargs="?", const="frames", default="",
                    help="write each member in random frames ('mirror': flip allowed signs too)")
    ap.add_argument("--deviate", type=float, default=0.0,
                    help="deviate each member by up to this fraction (0 .. 1) of the loader's limits")
    ap.add_argument("--deviate-only", default=",".join(DEVIATIONS),
                    help=f"the classes --deviate draws, of {','.join(DEVIATIONS)}")
    ap.add_argument("--beta", default="mix",
                    help="'mix' (a third at 45 deg), 'random' (15 .. 45 deg) or a twist in deg")
    args = ap.parse_args(argv)
    rng = np.random.default_rng(args.seed)
    missed = valleys = 0
    for m in range(args.members):
        lateral = True if args.lateral else bool(rng.integers(0, 2))
        beta = {"mix": 45.0 if m % 3 == 0 else None, "random": None}.get(args.beta)
        beta = float(args.beta) if args.beta not in ("mix", "random") else beta
        dh = family_member(rng, beta_deg=beta, lateral=lateral, rounded=True)
        if args.deviate:
            dh = _deviated(rng, dh, args.deviate, args.deviate_only.split(","))
        robot = _framed(rng, dh, f"member{m}", args.frames == "mirror") if args.frames else \
            Robot(name=f"member{m}", dh=dh)
        frames = (f" sign={robot.joint_sign.tolist()} coupling={list(robot.coupling)} "
                  f"base={robot.base.tolist()} tool={robot.tool.tolist()}") if args.frames else ""
        for kind in args.kinds.split(","):
            if kind in ("shoulder", "near_shoulder") and lateral and not args.lateral_shoulder:
                continue
            Q = (rng.uniform(-np.pi, np.pi, (args.poses, 6)) if kind == "uniform"
                 else singular_joints(robot, rng, kind, args.poses))
            T = robot.fk(Q)
            try:
                S, V = robot.ik_all_batch(T)
            except RuntimeError:  # a full output: find the pose, one by one
                S, V = _one_by_one(robot, T)
            for i in range(len(Q)):
                if S[i] is None:
                    missed += 1
                    print(f"r seed={args.seed} member={m} kind={kind} raised dh={robot.dh.tolist()}{frames} "
                          f"q={Q[i].tolist()}", flush=True)
                    continue
                sols = S[i][V[i]]
                if among(robot, sols, Q[i], T[i], tol=1e-6):
                    continue
                d = np.abs(_wrap(sols - Q[i])).max(axis=1) if len(sols) else np.full(1, np.inf)
                near = d.min()
                tag = "d" if near <= DUP_TOL else "m"
                if tag == "m" and len(sols) and any(
                        least_error_path_meets(robot, T[i], Q[i], sols[k], steps=80)
                        for k in np.argsort(d)[:VALLEY_NEAREST]):
                    tag = "v"
                missed += tag == "m"
                valleys += tag == "v"
                print(f"{tag} near={near:.2e} seed={args.seed} member={m} "
                      f"kind={kind} answers={len(sols)} dh={robot.dh.tolist()}{frames} q={Q[i].tolist()}",
                      flush=True)
    print(f"seed {args.seed}: {missed} sources missed, {valleys} in an answer's valley beyond among's reach")
    return 1 if missed else 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
