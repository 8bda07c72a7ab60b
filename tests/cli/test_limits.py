"""Bounded work: sizes estimated before allocating, refused above documented limits with a
message naming the size and the option that raises it; URDF loading linear in its size."""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest
from _run import assert_well_behaved, run_cli
from helpers import dh_product

import ik7r
from ik7r import limits
from ik7r.robot.urdf import robot_from_urdf_string


@pytest.mark.parametrize("argv, words", [
    (["paint", "raster", "--spacing", "1e-9"], ["raster passes", "--max-samples", "--spacing"]),
    (["paint", "raster", "--spacing", "1e-4"], ["8,000,001 raster passes", "--max-samples"]),
    (["paint", "raster", "--step", "1e-300"], ["raster path samples", "--step"]),
    (["paint", "raster", "--size", "1e308", "1e308"], ["raster passes"]),
    (["paint", "raster", "--rate", "1e9"], ["20,000,000,001 trajectory rows", "--max-rows", "--rate"]),
    (["paint", "raster", "--duration", "1e300"], ["trajectory rows", "--max-rows"]),
    (["paint", "raster", "--max-samples", "100"], ["path samples", "limit of 100", "--max-samples"]),
    (["paint", "raster", "--frames", "100000"], ["--frames must be 2..2000"]),
    (["batch", "--random", "100000000000000000000"], ["1e+20 poses", "--max-poses"]),
    (["batch", "--random", "4611686018427387904"], ["poses", "--max-poses"]),
    (["batch", "--random", "11", "--max-poses", "10"], ["11 poses exceed the limit of 10", "--max-poses"]),
    (["batch", "--random", "10", "--chunk", "1000000000"], ["--chunk", "GB of memory"]),
    (["bench", "--n", "1000000000"], ["--n", "limit"]),
])
def test_work_above_the_limits_is_refused_before_it_starts(argv, words, tmp_path):
    tracemalloc.start()
    try:
        code, out, err = run_cli(*argv, "--out" if argv[0] != "bench" else "--markdown",
                                 *([tmp_path / "o"] if argv[0] != "bench" else []))
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert_well_behaved(code, err)
    assert code == 2 and len(err.splitlines()) == 1
    for w in words:
        assert w in err, err
    assert peak < 50e6  # refused before allocating anything big
    assert not (tmp_path / "o").exists()


def test_raising_a_limit_lets_the_work_through(tmp_path):
    code, out, err = run_cli("batch", "--random", "10", "--max-poses", "10", "--out", tmp_path / "s")
    assert code == 0, err
    code, out, err = run_cli("paint", "raster", "--size", "100", "50", "--spacing", "50", "--no-plots",
                             "--max-samples", "200", "--max-rows", "2001", "--out", tmp_path / "p")
    assert code == 0, err


def test_library_limits_are_typed_errors():
    from ik7r.painting import raster_path

    with pytest.raises(limits.WorkLimitError, match="max-samples"):
        raster_path(spacing=1e-9)
    with pytest.raises(ValueError):
        raster_path(step=1e-12)
    assert len(raster_path(max_samples=10_000)) > 100
    with pytest.raises(limits.WorkLimitError, match="2,000"):
        limits.check_work("rows", 2001, 2000, "--x")
    with pytest.raises(limits.WorkLimitError):
        limits.check_work("rows", float("nan"), 2000, "--x")


def _chain_urdf(n: int, step: float = 1e-4) -> str:
    """The paper robot's URDF below a chain of ``n`` fixed joints, each ``step`` m up."""
    text = ik7r.load_robot().to_urdf()
    links = "".join(f'  <link name="c{k}"/>\n' for k in range(1, n + 1))
    joints = "".join(
        f'  <joint name="f{k}" type="fixed"><parent link="{"base_link" if k == 1 else f"c{k - 1}"}"/>'
        f'<child link="c{k}"/><origin xyz="0 0 {step!r}" rpy="0 0 0"/></joint>\n' for k in range(1, n + 1))
    text = text.replace('<parent link="base_link"/>', f'<parent link="c{n}"/>', 1)
    return text.replace("</robot>", links + joints + "</robot>")


def test_a_20000_link_urdf_loads_in_linear_work(monkeypatch):
    import ik7r.robot.urdf as U

    text = _chain_urdf(20_000)
    assert len(text) > 2_000_000
    calls = {"path": 0}
    real = U._path_to_root

    def counted(*a):
        calls["path"] += 1
        return real(*a)

    monkeypatch.setattr(U, "_path_to_root", counted)
    tracemalloc.start()
    try:
        robot = robot_from_urdf_string(text, source="chain.urdf")
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert calls["path"] == 1  # one root path (the tip's), not one per link: no quadratic work
    assert peak < 300e6  # was 1.6 GB
    q = np.random.default_rng(20).uniform(-1, 1, (8, 6))
    expected = np.array([dh_product(row) for row in q])  # the paper's model, independent of ik7r, mm
    expected[..., :3, 3] /= 1000.0
    expected[..., 2, 3] += 20_000 * 1e-4
    np.testing.assert_allclose(robot.fk(q), expected, atol=1e-9)


def test_a_20000_revolute_chain_is_refused_quickly_as_out_of_the_family():
    links = "".join(f'<link name="l{k}"/>' for k in range(20_001))
    joints = "".join(f'<joint name="j{k}" type="revolute"><parent link="l{k}"/><child link="l{k + 1}"/>'
                     f'<axis xyz="0 0 1"/><limit lower="-1" upper="1" velocity="1" effort="1"/></joint>'
                     for k in range(20_000))
    with pytest.raises(ik7r.FamilyError, match="20000 revolute joints"):
        robot_from_urdf_string(f'<robot name="long">{links}{joints}</robot>', source="long.urdf")


def test_a_fitting_tolerance_below_the_floor_is_refused(tmp_path):
    """``--tolerance 1e-13`` (mm) asked the joint-spline fit for about 2^10 times the IK samples
    of the default (minutes of work, found by the fuzz test); it is refused with the floor named,
    in the API and on the command line, and leaves no output."""
    from ik7r.painting import paint_raster
    from ik7r.painting.interpolate import MIN_TOLERANCE_MM

    robot = ik7r.load_robot()
    with pytest.raises(ValueError, match=r"tolerance must be at least 0\.0001 mm"):
        paint_raster(robot, duration=10.0, size=(100.0, 100.0), spacing=50.0, tolerance=1e-13)
    code, out, err = run_cli("paint", "raster", "--tolerance", "1e-13", "--no-plots", "--size", "100",
                             "100", "--spacing", "50", "--out", tmp_path / "o")
    assert_well_behaved(code, err)
    assert code in (1, 2) and len(err.splitlines()) == 1 and "at least 0.0001 mm" in err, err
    assert not (tmp_path / "o").exists()
    # the floor itself is accepted (the paper robot's raster meets it)
    result = paint_raster(robot, duration=10.0, size=(100.0, 100.0), spacing=50.0,
                          tolerance=MIN_TOLERANCE_MM)
    assert result.trajectory.max_deviation <= MIN_TOLERANCE_MM
