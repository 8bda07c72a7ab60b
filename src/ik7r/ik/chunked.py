"""Every solution of millions of poses in bounded memory: chunked :func:`ik7r.ik.solve.ik_all_batch`.

>>> import ik7r
>>> from ik7r.ik.chunked import RandomPoses, solve_all_chunked
>>> robot = ik7r.load_robot()
>>> total = 0
>>> for chunk in solve_all_chunked(robot, RandomPoses(robot, 10_000, seed=1), chunk=4096):
...     total += int(chunk.count.sum())          # chunk.q (n, K, 6), chunk.valid (n, K)

The poses come from a *pose source*: anything with ``len()`` whose slices ``source[a:b]`` are
(b - a, 4, 4) arrays: a numpy array, a memory-mapped ``.npy`` (``numpy.load(path,
mmap_mode="r")``), :class:`FromJoints` (the forward kinematics of joint vectors, computed chunk
by chunk) or :class:`RandomPoses` (random joints, reproducible, never held in memory at once).
Only one chunk of poses and its solutions are in memory at a time.

:func:`write_solutions` streams the solutions to disk in a compact layout (every solution
once, plus offsets), as a directory of ``.npy`` files or one ``.npz``; the command line's
``ik7r batch`` is built on it.
"""

from __future__ import annotations

import contextlib
import json
import os
import zipfile
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..geometry.checks import check_joints, pose_batch

if TYPE_CHECKING:
    from .._typing import PathLike
    from ..progress import Progress
    from ..robot.model import Robot

__all__ = [
    "ChunkResult",
    "FromJoints",
    "RandomPoses",
    "solve_all_chunked",
    "write_solutions",
    "BatchSummary",
    "DEFAULT_CHUNK",
]

#: Poses per chunk: about 13 MB of poses and 100 MB of solutions.
DEFAULT_CHUNK = 65536


@dataclass(frozen=True)
class FromJoints:
    """Poses ``robot.fk(q)`` of joint vectors ``q`` (N, 6) rad, computed slice by slice.

    ``q`` may be a memory-mapped array; it is read one chunk at a time.
    """

    robot: Robot
    q: np.ndarray

    def __post_init__(self) -> None:
        if np.ndim(self.q) != 2 or np.shape(self.q)[1] != 6:
            raise ValueError(f"joints must have shape (N, 6); got {np.shape(self.q)}")

    def __len__(self) -> int:
        return int(np.shape(self.q)[0])

    def joints(self, start: int, stop: int) -> np.ndarray:
        """The joint vectors ``[start, stop)`` (rad); rows may hold NaN (bad rows)."""
        q = self.q[start:stop]
        if np.iscomplexobj(q):
            check_joints(q, "joints")  # raises: complex joints are refused
        return np.asarray(q, dtype=float)

    def __getitem__(self, index: slice) -> np.ndarray:
        start, stop, _ = _bounds(index, len(self))
        return _fk_rows(self.robot, self.joints(start, stop))


def _fk_rows(robot, q: np.ndarray) -> np.ndarray:
    """``robot.fk`` of the finite rows of ``q`` (n, 6); rows with NaN or infinity give NaN poses
    (marked invalid, solved as no solution), so one bad row does not stop a batch."""
    good = np.all(np.isfinite(q), axis=1)
    if good.all():
        return robot.fk(q)
    T = np.full((len(q), 4, 4), np.nan)
    if good.any():
        T[good] = robot.fk(q[good])
    return T


@dataclass(frozen=True)
class RandomPoses:
    """``n`` poses of uniformly random joints, reproducible from ``seed``.

    Joints are uniform in [-pi, pi) (or within the robot's joint limits with
    ``within_limits``). Joints are drawn in fixed blocks of :attr:`BLOCK` (block k from
    ``numpy.random.default_rng([seed, k])``), so a pose does not depend on the chunking.
    """

    robot: Robot
    n: int
    seed: int = 0
    within_limits: bool = False

    BLOCK = 65536

    def __post_init__(self) -> None:
        if int(self.n) < 0:
            raise ValueError(f"the number of poses must be non-negative; got {self.n}")
        if int(self.seed) < 0:
            raise ValueError(f"seed must be a non-negative integer; got {self.seed}")

    def __len__(self) -> int:
        return int(self.n)

    def _block(self, k: int) -> np.ndarray:
        rng = np.random.default_rng([int(self.seed), k])
        m = min(self.BLOCK, len(self) - k * self.BLOCK)
        if self.within_limits:
            lo, hi = np.asarray(self.robot.lower), np.asarray(self.robot.upper)
            return lo + (hi - lo) * rng.random((m, 6))
        return rng.uniform(-np.pi, np.pi, (m, 6))

    def joints(self, start: int, stop: int) -> np.ndarray:
        """The joint vectors ``[start, stop)`` (rad)."""
        start, stop = max(0, start), min(len(self), stop)
        if stop <= start:
            return np.empty((0, 6))
        blocks = [self._block(k) for k in range(start // self.BLOCK, (stop - 1) // self.BLOCK + 1)]
        q = np.concatenate(blocks)
        first = (start // self.BLOCK) * self.BLOCK
        return q[start - first: stop - first]

    def __getitem__(self, index: slice) -> np.ndarray:
        start, stop, _ = _bounds(index, len(self))
        return _fk_rows(self.robot, self.joints(start, stop))


def _bounds(index, n: int) -> tuple[int, int, int]:
    if not isinstance(index, slice):
        raise TypeError(f"pose sources are sliced (source[a:b]); got {index!r}")
    start, stop, step = index.indices(n)
    if step != 1:
        raise ValueError("pose sources are sliced with step 1")
    return start, max(start, stop), step


@dataclass(frozen=True)
class ChunkResult:
    """The solutions of one chunk of poses.

    Attributes
    ----------
    start : int
        Index of the chunk's first pose in the source.
    T : ndarray, shape (n, 4, 4)
        The chunk's poses as given.
    q : ndarray, shape (n, K, 6)
        Every solution (rad), NaN-padded; ``K = MAX_SOLUTIONS``.
    valid : ndarray, shape (n, K), bool
    count : ndarray, shape (n,), int
        Number of solutions of each pose (the valid entries come first).
    joints : ndarray, shape (n, 6) or None
        The joints the poses were made from (:class:`FromJoints`, :class:`RandomPoses`).
    """

    start: int
    T: np.ndarray
    q: np.ndarray
    valid: np.ndarray
    count: np.ndarray
    joints: np.ndarray | None = None

    @property
    def stop(self) -> int:
        """Index after the chunk's last pose."""
        return self.start + len(self.count)


def solve_all_chunked(robot: Robot, poses: np.ndarray | RandomPoses | FromJoints, *,
                      chunk: int = DEFAULT_CHUNK, start: int = 0,
                      stop: int | None = None) -> Iterator[ChunkResult]:
    """Every solution of every pose of ``poses``, one chunk at a time.

    Parameters
    ----------
    robot : Robot
    poses : pose source
        An array (N, 4, 4) (a memory-mapped ``.npy`` is read chunk by chunk), a
        :class:`FromJoints` or a :class:`RandomPoses`.
    chunk : int
        Poses per chunk (memory use is about 1.6 kB per pose of the chunk).
    start, stop : int
        Solve only the poses ``[start, stop)``.

    Yields
    ------
    ChunkResult
        In order; the union of the chunks equals ``robot.ik_all_batch`` of all the poses.
        A pose that is not a valid transform (NaN, not orthonormal) has no solution.
    """
    from .solve import ik_all_batch

    chunk = int(chunk)
    if chunk < 1:
        raise ValueError(f"chunk must be a positive number of poses; got {chunk}")
    n = len(poses)
    shape = getattr(poses, "shape", None)
    if shape is not None and tuple(shape[1:]) != (4, 4):
        raise ValueError(f"poses must have shape (N, 4, 4); got {tuple(shape)}")
    stop = n if stop is None else min(int(stop), n)
    for a in range(max(0, int(start)), stop, chunk):
        b = min(a + chunk, stop)
        joints = poses.joints(a, b) if hasattr(poses, "joints") else None
        T = _fk_rows(robot, joints) if joints is not None else pose_batch(poses[a:b], "poses")
        q, valid = ik_all_batch(robot, T)
        yield ChunkResult(start=a, T=T, q=q, valid=valid, count=valid.sum(axis=1), joints=joints)


# ---------------------------------------------------------------------- writing to disk
_HEADER_BYTES = 128  # fixed .npy header size, so the shape can be written at the end


def _npy_header(shape: tuple[int, ...], descr: str) -> bytes:
    d = f"{{'descr': {descr!r}, 'fortran_order': False, 'shape': {tuple(shape)!r}, }}"
    body = d.encode("latin1")
    pad = _HEADER_BYTES - 10 - len(body) - 1
    if pad < 0:  # pragma: no cover - shapes here are at most two numbers
        raise ValueError(f"shape {shape} too long for the header")
    return b"\x93NUMPY\x01\x00" + (_HEADER_BYTES - 10).to_bytes(2, "little") + body + b" " * pad + b"\n"


class _NpyAppender:
    """Append rows to a ``.npy`` file of unknown length; the header is fixed at close."""

    def __init__(self, path: Path, row_shape: tuple[int, ...], dtype) -> None:
        self.path = path
        self.row_shape = tuple(row_shape)
        self.dtype = np.dtype(dtype)
        self.rows = 0
        self._f = open(path, "wb")  # closed in close()
        self._f.write(_npy_header((0,) + self.row_shape, self.dtype.str))

    def append(self, a: np.ndarray) -> None:
        a = np.ascontiguousarray(a, dtype=self.dtype)
        if a.shape[1:] != self.row_shape:  # pragma: no cover - internal use
            raise ValueError(f"rows of shape {self.row_shape} expected; got {a.shape[1:]}")
        self._f.write(a.tobytes())
        self.rows += a.shape[0]

    def close(self) -> None:
        """Write the final header and close (flushed to disk)."""
        self._f.seek(0)
        self._f.write(_npy_header((self.rows,) + self.row_shape, self.dtype.str))
        self._f.flush()
        with contextlib.suppress(OSError):
            os.fsync(self._f.fileno())
        self._f.close()

    def abandon(self) -> None:
        """Close without completing (the caller removes the file)."""
        with contextlib.suppress(OSError):
            self._f.close()


@dataclass(frozen=True)
class BatchSummary:
    """What :func:`write_solutions` did.

    ``poses`` solved, ``solutions`` written, ``unreachable`` poses without a solution,
    ``invalid`` poses that were not valid transforms, ``seconds`` of wall time, ``path``.
    ``max_count`` is the most solutions of one pose.
    """

    poses: int
    solutions: int
    unreachable: int
    invalid: int
    max_count: int
    seconds: float
    path: Path

    @property
    def poses_per_second(self) -> float:
        return self.poses / self.seconds if self.seconds > 0 else float("inf")


def write_solutions(robot: Robot, poses: np.ndarray | RandomPoses | FromJoints, out: PathLike, *,
                    chunk: int = DEFAULT_CHUNK, progress: Progress | None = None,
                    meta: dict | None = None) -> BatchSummary:
    """Solve every pose of ``poses`` and stream the solutions to ``out``, in bounded memory.

    Parameters
    ----------
    robot : Robot
    poses : pose source
        See :func:`solve_all_chunked`.
    out : str or Path
        A directory (created; existing files of the same names are replaced), or a file
        ending in ``.npz``, written atomically (:mod:`ik7r.outputs`): the files are staged and
        published when complete, ``meta.json`` last (an old one is removed first); an error
        or an interrupt leaves no partial file and nothing hidden. Either holds:

        ``q`` : (M, 6) float64
            Every solution (rad), pose after pose, each pose's sorted as ``ik_all_batch``.
        ``offsets`` : (N + 1,) int64
            The solutions of pose i are ``q[offsets[i]:offsets[i + 1]]``.
        ``joints`` : (N, 6) float64
            Only for :class:`RandomPoses` / :class:`FromJoints`: the joints of each pose.

        and ``meta.json`` (robot, unit, counts, time). The ``.npy`` files of a directory can be
        opened with ``numpy.load(..., mmap_mode="r")``.
    chunk : int
        Poses per chunk.
    progress : ik7r.progress.Progress, optional
        Advanced by the number of poses of each chunk.
    meta : dict, optional
        Extra entries for ``meta.json``.
    """
    import time

    from ..outputs import OutputDir, atomic_file

    out = Path(out)
    as_npz = out.suffix == ".npz"
    if as_npz:
        if out.is_dir():
            raise ValueError(f"{out} is a directory; a .npz output must be a file")
        # the .npy files are staged in a hidden directory beside the archive, removed in any case
        out.parent.mkdir(parents=True, exist_ok=True)
        stage = OutputDir(out.parent / f".{out.name}.ik7r-parts", manifest="meta.json")
    else:
        if out.exists() and not out.is_dir():
            raise ValueError(f"{out} exists and is not a directory")
        stage = OutputDir(out, manifest="meta.json", owned=("q.npy", "offsets.npy", "joints.npy"))
    n = len(poses)
    started = time.perf_counter()
    with stage:
        folder = stage.path
        assert folder is not None  # set by OutputDir.__enter__
        total, unreachable, invalid, max_count = _stream_solutions(robot, poses, folder, chunk, progress)
        seconds = time.perf_counter() - started
        summary = BatchSummary(poses=n, solutions=total, unreachable=unreachable - invalid,
                               invalid=invalid, max_count=max_count, seconds=seconds, path=out)
        info = {"robot": getattr(robot, "name", ""), "unit": getattr(robot, "unit", ""), "poses": n,
                "solutions": total, "unreachable": summary.unreachable, "invalid": invalid,
                "max_count": max_count, "seconds": seconds,
                "layout": "solutions of pose i are q[offsets[i]:offsets[i + 1]] (rad)"}
        info.update(meta or {})
        with atomic_file(folder / "meta.json") as fh:
            fh.write(json.dumps(info, indent=2))
        if as_npz:
            with atomic_file(out, "wb") as fh, zipfile.ZipFile(
                    fh, "w", compression=zipfile.ZIP_STORED, allowZip64=True) as zf:
                for name in ("q.npy", "offsets.npy", "joints.npy", "meta.json"):
                    f = folder / name
                    if f.exists():
                        zf.write(f, arcname=name)  # streamed, not loaded
            for f in list(folder.iterdir()):  # nothing to publish beside the archive
                f.unlink()
    if as_npz:
        with contextlib.suppress(OSError):
            stage.target.rmdir()
    return summary


def _stream_solutions(robot, poses, folder: Path, chunk: int, progress) -> tuple[int, int, int, int]:
    """Solve chunk by chunk, appending to ``folder``'s q.npy, offsets.npy (and joints.npy)."""
    q_file = _NpyAppender(folder / "q.npy", (6,), np.float64)
    j_file = _NpyAppender(folder / "joints.npy", (6,), np.float64) if hasattr(poses, "joints") else None
    # offsets are appended too (never a memory map: a full disk must be an error, not SIGBUS)
    o_file = _NpyAppender(folder / "offsets.npy", (), np.int64)
    o_file.append(np.zeros(1, dtype=np.int64))
    total = unreachable = invalid = max_count = 0
    try:
        for res in solve_all_chunked(robot, poses, chunk=chunk):
            q_file.append(res.q[res.valid])
            if j_file is not None and res.joints is not None:
                j_file.append(res.joints)
            o_file.append(total + np.cumsum(res.count))
            total += int(res.count.sum())
            zero = res.count == 0
            unreachable += int(zero.sum())
            if zero.any():
                invalid += int((~_valid_poses(res.T[zero])).sum())
            if len(res.count):
                max_count = max(max_count, int(res.count.max()))
            if progress is not None:
                progress.advance(len(res.count))
    except BaseException:
        for f in (q_file, j_file, o_file):
            if f is not None:
                f.abandon()
        raise
    for f in (q_file, j_file, o_file):
        if f is not None:
            f.close()
    return total, unreachable, invalid, max_count


def _valid_poses(T: np.ndarray) -> np.ndarray:
    from ..geometry.checks import poses_status

    return poses_status(T)[1]
