"""Atomic, honest outputs: complete files or none, manifests last, nothing left behind by a
failed or interrupted run (errors, SIGINT, SIGTERM, a full disk)."""

from __future__ import annotations

import errno
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from _run import assert_well_behaved, run_cli

from ik7r import outputs
from ik7r.outputs import OutputDir, OutputError, atomic_file


def _tree(root: Path) -> list[str]:
    """Every entry below ``root`` (hidden ones too), relative."""
    return sorted(str(p.relative_to(root)) for p in root.rglob("*")) if root.exists() else []


# ---------------------------------------------------------------- the machinery itself
def test_atomic_file_is_complete_or_absent(tmp_path):
    f = tmp_path / "a.txt"
    f.write_text("old")
    with pytest.raises(RuntimeError):
        with atomic_file(f) as fh:
            fh.write("half")
            raise RuntimeError("boom")
    assert f.read_text() == "old" and _tree(tmp_path) == ["a.txt"]
    with atomic_file(f) as fh:
        fh.write("new")
    assert f.read_text() == "new" and _tree(tmp_path) == ["a.txt"]
    assert (f.stat().st_mode & 0o777) == 0o666 & ~_umask()


def _umask() -> int:
    m = os.umask(0)
    os.umask(m)
    return m


def test_atomic_path_gives_a_writer_a_file_name_and_publishes_it(tmp_path):
    target = tmp_path / "program.mod"
    with outputs.atomic_path(target) as tmp:
        assert isinstance(tmp, Path) and tmp.parent == tmp_path and tmp != target
        tmp.write_text("MODULE m\nENDMODULE\n")  # a writer that opens the name itself
        assert not target.exists()
    assert target.read_text() == "MODULE m\nENDMODULE\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["program.mod"]
    with pytest.raises(RuntimeError), outputs.atomic_path(tmp_path / "other.mod") as tmp:
        tmp.write_text("half")
        raise RuntimeError("writer failed")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["program.mod"]


def test_output_dir_publishes_the_manifest_last(tmp_path, monkeypatch):
    order = []
    real = os.replace
    monkeypatch.setattr(outputs.os, "replace", lambda a, b: (order.append(Path(b).name), real(a, b)))
    with OutputDir(tmp_path / "run", manifest="meta.json") as out:
        for name in ("meta.json", "z.npy", "a.npy"):
            (out.path / name).write_text(name)
        assert _tree(tmp_path / "run") == [out.path.name] + [f"{out.path.name}/{n}" for n in
                                                             ("a.npy", "meta.json", "z.npy")]
    assert order[-1] == "meta.json" and sorted(order) == ["a.npy", "meta.json", "z.npy"]
    assert _tree(tmp_path / "run") == ["a.npy", "meta.json", "z.npy"]


def test_a_new_run_removes_the_old_manifest_first_and_stale_files_at_the_end(tmp_path):
    run = tmp_path / "run"
    run.mkdir()
    for name in ("q.npy", "joints.npy", "meta.json", "mine.txt"):
        (run / name).write_text("old " + name)
    stage = OutputDir(run, manifest="meta.json", owned=("q.npy", "joints.npy"))
    with stage as out:
        assert not (run / "meta.json").exists()  # the old run no longer looks complete
        (out.path / "q.npy").write_text("new")
        (out.path / "meta.json").write_text("new")
    assert (run / "q.npy").read_text() == "new" and (run / "meta.json").read_text() == "new"
    assert not (run / "joints.npy").exists()  # the old run's, not this one's
    assert (run / "mine.txt").read_text() == "old mine.txt"  # not ours: untouched


@pytest.mark.parametrize("exc", [RuntimeError("boom"), KeyboardInterrupt(), outputs.Terminated(15),
                                 OSError(errno.ENOSPC, "No space left on device")])
def test_a_failed_run_leaves_nothing_behind(tmp_path, exc):
    with pytest.raises(type(exc) if not isinstance(exc, OSError) else OutputError):
        with OutputDir(tmp_path / "new", manifest="meta.json") as out:
            (out.path / "q.npy").write_text("partial")
            raise exc
    assert _tree(tmp_path) == []  # the directory it created is gone too
    old = tmp_path / "old"
    old.mkdir()
    (old / "q.npy").write_text("old")
    (old / "meta.json").write_text("old")
    with pytest.raises(type(exc) if not isinstance(exc, OSError) else OutputError):
        with OutputDir(old, manifest="meta.json") as out:
            (out.path / "q.npy").write_text("partial")
            raise exc
    assert _tree(old) == ["q.npy"] and (old / "q.npy").read_text() == "old"


def test_a_file_where_the_directory_should_be_is_an_error(tmp_path):
    f = tmp_path / "f"
    f.write_text("x")
    code, out, err = run_cli("batch", "--random", "10", "--out", f)
    assert code == 2 and "not a directory" in err and f.read_text() == "x"
    for argv in (["paint", "raster", "--no-plots", "--out", f], ["reproduce", "--quick", "--out", f],
                 ["demo", "--out", f]):
        code, out, err = run_cli(*argv)
        assert_well_behaved(code, err)
        assert code == 2 and str(f) in err and f.read_text() == "x"


# ---------------------------------------------------------------- the commands
def test_batch_output_is_complete_and_memory_mappable(tmp_path):
    code, out, err = run_cli("batch", "--random", "300", "--seed", "3", "--out", tmp_path / "s",
                             "--chunk", "64")
    assert code == 0, err
    q = np.load(tmp_path / "s" / "q.npy", mmap_mode="r")
    off = np.load(tmp_path / "s" / "offsets.npy", mmap_mode="r")
    meta = json.loads((tmp_path / "s" / "meta.json").read_text())
    assert off.dtype == np.int64 and off.shape == (301,) and off[-1] == len(q) == meta["solutions"]
    assert np.all(np.diff(off) >= 0)
    assert _tree(tmp_path / "s") == ["joints.npy", "meta.json", "offsets.npy", "q.npy"]


def test_interrupted_reproduce_over_an_old_output_leaves_no_old_report(tmp_path, monkeypatch):
    import ik7r.reproduce.run as R

    out = tmp_path / "rep"
    out.mkdir()
    (out / "report.md").write_text("seed 2016")
    (out / "table2.csv").write_text("old")

    def interrupted(*a, **k):
        raise KeyboardInterrupt

    monkeypatch.setattr(R, "write_table5", interrupted)
    code, _, err = run_cli("reproduce", "--quick", "--seed", "7", "--out", out)
    assert code == 130 and err.strip() == "interrupted"
    assert _tree(out) == ["table2.csv"] and (out / "table2.csv").read_text() == "old"


def test_failed_paint_run_leaves_nothing_that_looks_complete(tmp_path, monkeypatch):
    import ik7r.painting as P

    out = tmp_path / "p"
    assert run_cli("paint", "raster", "--no-plots", "--out", out)[0] == 0
    assert _tree(out) == ["report.txt", "trajectory.csv"]

    def full(*a, **k):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(P, "write_trajectory_csv", full)
    code, _, err = run_cli("paint", "raster", "--no-plots", "--out", out)
    assert code == 2 and "no space left" in err and len(err.splitlines()) == 1
    assert "report.txt" not in _tree(out)  # the old report is gone: the directory is not a result
    assert not [p for p in _tree(out) if p.startswith(".")]


def test_infeasible_paint_run_leaves_its_report_only(tmp_path):
    out = tmp_path / "p"
    assert run_cli("paint", "raster", "--no-plots", "--out", out)[0] == 0
    f = tmp_path / "far.csv"
    f.write_text("x,y,z\n" + "".join(f"{1500 + 50 * k},0,200\n" for k in range(23)))
    code, _, err = run_cli("paint", "path", f, "--no-plots", "--out", out)
    assert code == 1 and "report" in err
    assert _tree(out) == ["report.txt"]  # no trajectory of an older run beside it
    assert "out of reach" in (out / "report.txt").read_text()


def test_export_and_bench_json_write_atomically(tmp_path, monkeypatch):
    f = tmp_path / "r.toml"
    assert run_cli("export", "--format", "toml", "--out", f)[0] == 0
    import ik7r

    assert ik7r.load_robot(f).name == "paper"
    code, _, err = run_cli("export", "--format", "urdf", "--out", tmp_path / "missing" / "r.urdf")
    assert code == 2 and "cannot write" in err and len(err.splitlines()) == 1
    assert not (tmp_path / "missing").exists()


# ---------------------------------------------------------------- a full disk
@pytest.fixture
def small_disk(tmp_path):
    """A 256 kB tmpfs when this machine lets us mount one (root), else None."""
    mnt = tmp_path / "small"
    mnt.mkdir()
    if os.geteuid() != 0 or os.environ.get("IK7R_TEST_SIMULATE_ENOSPC"):
        yield None
        return
    ok = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=256k", "tmpfs", str(mnt)],
                        capture_output=True).returncode == 0
    try:
        yield mnt if ok else None
    finally:
        if ok:
            subprocess.run(["umount", str(mnt)], capture_output=True)


@pytest.mark.parametrize("out", ["sols", "sols.npz"])
def test_full_disk_batch_gives_exit_2_and_leaves_nothing(small_disk, tmp_path, monkeypatch, out):
    if small_disk is None:  # simulated: the disk fills up at the third write
        import ik7r.ik.chunked as B

        calls = {"n": 0}
        real = B._NpyAppender.append

        def append(self, a):
            calls["n"] += 1
            if calls["n"] > 2:
                raise OSError(errno.ENOSPC, "No space left on device")
            real(self, a)

        monkeypatch.setattr(B._NpyAppender, "append", append)
        root = tmp_path / "disk"
        root.mkdir()
        code, stdout, err = run_cli("batch", "--random", "5000", "--chunk", "1000", "--out", root / out)
    else:
        root = small_disk
        # a subprocess: the real thing, with its real exit status (a bus error would be -7)
        p = subprocess.run([sys.executable, "-m", "ik7r", "batch", "--random", "20000", "--out", root / out],
                           capture_output=True, text=True, timeout=600)
        code, err = p.returncode, p.stderr
    assert code == 2, err
    assert len(err.splitlines()) == 1 and "no space left" in err
    assert _tree(root) == []


def test_full_disk_paint_and_reproduce(small_disk, tmp_path, monkeypatch):
    if small_disk is None:
        pytest.skip("needs a small tmpfs (root); the simulated case is test_failed_paint_run_...")
    for argv in (["paint", "raster", "--no-animation"], ["reproduce", "--quick"]):
        code, _, err = run_cli(*argv, "--out", small_disk / "o")
        assert code == 2 and "no space left" in err and len(err.splitlines()) == 1
        assert _tree(small_disk) == []


# ---------------------------------------------------------------- signals
def _start_batch(out: Path) -> subprocess.Popen:
    env = dict(os.environ, IK7R_NUM_THREADS="1")
    return subprocess.Popen([sys.executable, "-m", "ik7r", "batch", "--random", "50000000", "--chunk",
                             "2048", "--max-poses", "50000000", "--out", str(out)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)


def _wait_for_data(root: Path, proc: subprocess.Popen) -> None:
    """Until some solutions are on disk (the run is well under way)."""
    deadline = time.monotonic() + 300  # a hang guard, not a timing assertion
    while time.monotonic() < deadline and proc.poll() is None:
        sizes = [p.stat().st_size for p in root.rglob("q.npy") if p.is_file()]
        if sizes and max(sizes) > 1 << 20:
            return
        time.sleep(0.2)
    raise AssertionError(f"the batch did not start writing (status {proc.poll()})")


@pytest.mark.parametrize("sig, status", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
@pytest.mark.parametrize("out", ["sols", "sols.npz"])
def test_interrupted_batch_leaves_nothing_that_looks_complete(tmp_path, sig, status, out):
    root = tmp_path / "area"
    root.mkdir()
    target = root / out
    if out == "sols":  # a finished run already there
        assert run_cli("batch", "--random", "100", "--out", target)[0] == 0
        assert (target / "meta.json").exists()
    proc = _start_batch(target)
    _wait_for_data(root, proc)
    proc.send_signal(sig)
    stdout, err = proc.communicate(timeout=120)
    assert proc.returncode == status, err
    assert len(err.splitlines()) == 1 and ("interrupted" in err or "terminated" in err)
    left = _tree(root)
    assert not [p for p in left if Path(p).name.startswith(".")], left  # no hidden leftovers
    assert not [p for p in left if p.endswith("meta.json") or p.endswith(".npz")], left
    if out == "sols":  # the old run's data stays, without its manifest; none of the new run's
        assert sorted(left) == ["sols", "sols/joints.npy", "sols/offsets.npy", "sols/q.npy"]
        assert len(np.load(target / "offsets.npy")) == 101
    else:
        assert left == []


def test_failed_paint_mesh_run_leaves_nothing_that_looks_complete(tmp_path, monkeypatch):
    import ik7r.painting.view as W

    out = tmp_path / "m"
    out.mkdir()
    (out / "report.json").write_text("{}")  # an older run's
    (out / "report.txt").write_text("old")

    def full(*a, **k):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(W, "write_thickness_csv", full)
    code, _, err = run_cli("paint", "mesh", "panel", "--speed", "200", "--no-plots", "--out", out)
    assert code == 2 and "no space left" in err and len(err.splitlines()) == 1
    assert _tree(out) == []  # old reports removed, nothing new, nothing hidden
    (out / "thickness.csv").write_text("old")
    code, _, err = run_cli("paint", "mesh", "panel", "--speed", "5000", "--no-plots", "--out", out)
    assert code == 1 and "report" in err
    assert _tree(out) == ["report.txt"]  # an infeasible run: its report alone


def test_gun_fit_writes_atomically(tmp_path):
    code, _, err = run_cli("gun", "fit", tmp_path / "missing.csv", "--model", "gaussian", "--speed", "500",
                           "--standoff", "200", "--out", tmp_path / "g.toml")
    assert_well_behaved(code, err)
    assert code == 2 and _tree(tmp_path) == []
