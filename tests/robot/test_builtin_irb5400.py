"""The built-in ABB IRB 5400 (mm; rounded published numbers, a slightly asymmetric wrist):
every ik_all solution exact on the model as written, and nothing missed (no file needed)."""

import numpy as np
import pytest

import ik7r
from ik7r.geometry.rotations import wrap_angle


@pytest.fixture(scope="module")
def irb():
    return ik7r.load_robot("irb5400")


def test_irb5400_is_not_exactly_ideal(irb):
    assert irb.unit == "mm"
    assert irb.family.deviation > 0  # the rounded numbers: polishing is needed
    assert abs(irb.family.a1) == pytest.approx(300.0) and abs(irb.family.a3) == pytest.approx(186.0)


@pytest.mark.parametrize("seed", [0, 1])
def test_irb5400_round_trip_complete_and_exact(irb, seed):
    rng = np.random.default_rng(seed)
    Q = rng.uniform(irb.lower, irb.upper, (200, 6))
    counts = []
    for q in Q:
        T = irb.fk(q)
        sols = irb.ik_all(T)
        F = irb.fk(sols)
        assert np.linalg.norm(F[:, :3, 3] - T[:3, 3], axis=1).max() <= irb.position_tolerance
        assert np.abs(F[:, :3, :3] - T[:3, :3]).max() <= 1e-11
        assert np.abs(wrap_angle(sols - q)).max(axis=1).min() < 1e-7, q.tolist()
        d = np.abs(wrap_angle(sols[:, None] - sols[None])).max(axis=-1) + np.eye(len(sols))
        assert d.min() > 1e-7
        counts.append(len(sols))
    assert min(counts) >= 1


def test_irb5400_ik_within_limits_nearest_seed(irb):
    rng = np.random.default_rng(4)
    for q in rng.uniform(irb.lower, irb.upper, (20, 6)):
        T = irb.fk(q)
        got = irb.ik(T, int(irb.config_of(q)), seed=q, within_limits=True)
        assert np.abs(got - q).max() < 1e-7
