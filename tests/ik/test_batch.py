"""Chunked batches (ik7r.ik.chunked) and the ``ik7r batch`` command."""

from __future__ import annotations

import json

import numpy as np
import pytest

import ik7r
from ik7r.cli.app import main
from ik7r.ik.chunked import FromJoints, RandomPoses, solve_all_chunked, write_solutions


@pytest.fixture(scope="module")
def robot():
    return ik7r.load_robot()


@pytest.fixture(scope="module")
def joints():
    return np.random.default_rng(11).uniform(-np.pi, np.pi, (700, 6))


def _fk_ok(robot, q, T):
    Tq = robot.fk(q)
    dp = np.linalg.norm(Tq[:, :3, 3] - T[:, :3, 3], axis=1)
    dr = np.sqrt(0.5 * ((Tq[:, :3, :3] - T[:, :3, :3]) ** 2).sum(axis=(1, 2)))
    return (dp <= robot.position_tolerance) & (dr <= robot.rotation_tolerance)


def _found(sols, q):
    d = np.abs(np.mod(sols - q + np.pi, 2 * np.pi) - np.pi)
    return bool((d.max(axis=1) < 1e-6).any())


def _gather(chunks):
    chunks = list(chunks)
    starts = [c.start for c in chunks]
    assert starts == sorted(starts)
    return (np.concatenate([c.q for c in chunks]), np.concatenate([c.valid for c in chunks]),
            np.concatenate([c.count for c in chunks]), chunks)


@pytest.mark.parametrize("chunk", [1, 128, 699, 5000])
def test_chunks_equal_the_whole_batch_and_satisfy_fk(robot, joints, chunk):
    T = robot.fk(joints)
    n = len(T)
    q_all, valid_all = robot.ik_all_batch(T)
    q, valid, count, chunks = _gather(solve_all_chunked(robot, T, chunk=chunk))
    assert len(chunks) == -(-n // chunk)
    assert np.array_equal(valid, valid_all)
    assert np.array_equal(q[valid], q_all[valid_all])
    assert np.isnan(q[~valid]).all()
    assert np.array_equal(count, valid.sum(axis=1))
    idx = np.nonzero(valid)
    assert _fk_ok(robot, q[idx], T[idx[0]]).all()
    for i in range(n):
        assert _found(q[i][valid[i]], joints[i]), i


def test_sources_give_the_same_solutions(robot, joints, tmp_path):
    T = robot.fk(joints[:200])
    path = tmp_path / "poses.npy"
    np.save(path, T)
    mm = np.load(path, mmap_mode="r")
    ref = _gather(solve_all_chunked(robot, T, chunk=64))
    for src in (mm, FromJoints(robot, joints[:200])):
        q, valid, _, chunks = _gather(solve_all_chunked(robot, src, chunk=64))
        assert np.array_equal(valid, ref[1])
        assert np.array_equal(q[valid], ref[0][ref[1]])
    assert np.array_equal(np.concatenate([c.joints for c in chunks]), joints[:200])


def test_start_and_stop(robot, joints):
    T = robot.fk(joints[:100])
    whole = _gather(solve_all_chunked(robot, T, chunk=30))
    part = _gather(solve_all_chunked(robot, T, chunk=30, start=25, stop=70))
    assert part[3][0].start == 25 and part[3][-1].stop == 70
    assert np.array_equal(part[1], whole[1][25:70])


def test_random_poses_do_not_depend_on_the_chunking(robot):
    src = RandomPoses(robot, 200_000, seed=5)
    a = src.joints(65_000, 66_000)  # across a block boundary
    b = np.concatenate([src.joints(65_000, 65_536), src.joints(65_536, 66_000)])
    assert np.array_equal(a, b)
    assert not np.array_equal(a, RandomPoses(robot, 200_000, seed=6).joints(65_000, 66_000))
    assert np.array_equal(src[65_000:65_010], robot.fk(a[:10]))
    inside = RandomPoses(robot, 1000, seed=1, within_limits=True).joints(0, 1000)
    assert (inside >= robot.lower).all() and (inside <= robot.upper).all()


def test_invalid_poses_have_no_solution(robot, joints):
    T = robot.fk(joints[:10])
    T[2, 0, 0] = np.nan
    T[5, :3, :3] *= 1.1
    chunks = list(solve_all_chunked(robot, T, chunk=4))
    count = np.concatenate([c.count for c in chunks])
    assert count[2] == 0 and count[5] == 0
    assert (np.delete(count, [2, 5]) > 0).all()


def test_bad_arguments(robot, joints):
    with pytest.raises(ValueError, match="chunk"):
        next(solve_all_chunked(robot, robot.fk(joints[:3]), chunk=0))
    with pytest.raises(ValueError, match=r"\(N, 4, 4\)"):
        next(solve_all_chunked(robot, np.zeros((3, 3, 3))))
    with pytest.raises(ValueError, match=r"\(N, 6\)"):
        FromJoints(robot, np.zeros((3, 5)))
    with pytest.raises(ValueError):
        RandomPoses(robot, -1)


def _check_written(robot, q, offsets, joints, n):
    assert offsets.shape == (n + 1,) and offsets[0] == 0 and offsets[-1] == len(q)
    assert (np.diff(offsets) >= 0).all()
    T = robot.fk(joints)
    owner = np.repeat(np.arange(n), np.diff(offsets))
    assert _fk_ok(robot, q, T[owner]).all()
    for i in range(n):
        assert _found(q[offsets[i]:offsets[i + 1]], joints[i]), i


@pytest.mark.parametrize("name", ["out_dir", "out.npz"])
def test_write_solutions(robot, tmp_path, name):
    src = RandomPoses(robot, 300, seed=2)
    out = tmp_path / name
    summary = write_solutions(robot, src, out, chunk=70)
    if name.endswith(".npz"):
        data = np.load(out)
        q, offsets, jts = data["q"], data["offsets"], data["joints"]
        meta = json.loads(bytes(data["meta.json"]))
        assert not list(tmp_path.glob(".ik7r-batch-*"))  # the work folder is gone
    else:
        q = np.load(out / "q.npy", mmap_mode="r")
        offsets = np.load(out / "offsets.npy")
        jts = np.load(out / "joints.npy")
        meta = json.loads((out / "meta.json").read_text())
    assert np.array_equal(jts, src.joints(0, 300))
    _check_written(robot, np.asarray(q), offsets, jts, 300)
    assert summary.poses == 300 and summary.solutions == len(q) == meta["solutions"]
    assert summary.max_count == np.diff(offsets).max()


def test_cli_batch_random_and_poses(robot, tmp_path, capsys):
    out = tmp_path / "r"
    assert main(["batch", "--random", "250", "--seed", "4", "--out", str(out), "--chunk", "100"]) == 0
    q, offsets, jts = (np.load(out / f) for f in ("q.npy", "offsets.npy", "joints.npy"))
    _check_written(robot, q, offsets, jts, 250)
    assert "250 random poses" in capsys.readouterr().out

    poses = tmp_path / "poses.npy"
    np.save(poses, robot.fk(jts[:50]))
    assert main(["batch", "--poses", str(poses), "--out", str(tmp_path / "p.npz"), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    data = np.load(tmp_path / "p.npz")
    assert "joints" not in data.files
    assert summary["poses"] == 50 and summary["solutions"] == len(data["q"])
    _check_written(robot, data["q"], data["offsets"], jts[:50], 50)

    jfile = tmp_path / "joints.npy"
    np.save(jfile, jts[:20])
    assert main(["batch", "--joints", str(jfile), "--out", str(tmp_path / "j")]) == 0
    assert np.array_equal(np.load(tmp_path / "j" / "joints.npy"), jts[:20])


def test_cli_batch_progress_bar(tmp_path, capsys):
    assert main(["batch", "--random", "30", "--out", str(tmp_path / "x"), "--progress"]) == 0
    assert "30/30" in capsys.readouterr().err


@pytest.fixture()
def bad_files(tmp_path):
    np.save(tmp_path / "wrong_shape.npy", np.zeros((5, 3, 3)))
    np.save(tmp_path / "strings.npy", np.array([["a"] * 6] * 2))
    (tmp_path / "not_npy.npy").write_text("hello")
    (tmp_path / "a_file").write_text("x")
    return tmp_path


@pytest.mark.parametrize("args", [
    ["--random", "10"],                                     # no --out
    ["--out", "X"],                                         # no source
    ["--random", "10", "--poses", "P", "--out", "X"],       # two sources
    ["--random", "-1", "--out", "X"],
    ["--random", "10", "--seed", "-3", "--out", "X"],
    ["--random", "10", "--chunk", "0", "--out", "X"],
    ["--poses", "{d}/missing.npy", "--out", "X"],
    ["--poses", "{d}/wrong_shape.npy", "--out", "X"],
    ["--poses", "{d}/not_npy.npy", "--out", "X"],
    ["--joints", "{d}/wrong_shape.npy", "--out", "X"],
    ["--joints", "{d}/strings.npy", "--out", "X"],
    ["--random", "10", "--out", "{d}/a_file"],              # output is a file, not a directory
])
def test_cli_batch_bad_input_exits_2(bad_files, args, capsys):
    args = [a.replace("{d}", str(bad_files)).replace("X", str(bad_files / "out")) for a in args]
    assert main(["batch", *args]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error:") and len(err.strip().splitlines()) == 1
