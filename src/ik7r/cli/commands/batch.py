"""``ik7r batch``: every solution of many poses (millions), in bounded memory, to files."""

from __future__ import annotations

import sys

from ...geometry.checks import ORTHONORMAL_TOL
from ...limits import MAX_CHUNK, MAX_POSES, check_work
from ..errors import CliError
from ._common import CLI_ORTHONORMAL_TOL, count, load_cli_robot, print_json


def add_parser(sub) -> None:
    p = sub.add_parser(
        "batch", help="every solution of many poses, streamed to .npy / .npz files",
        description="Solve every pose of a set (random joints, a .npy file of poses or of "
                    "joints) with the complete solver, chunk by chunk in bounded memory, and "
                    "write every solution: q (M, 6) rad and offsets (N + 1,): the solutions "
                    "of pose i are q[offsets[i]:offsets[i + 1]].")
    src = p.add_mutually_exclusive_group(required=True)
    src.add_argument("--random", type=count, metavar="N", help="N poses of uniformly random joints")
    src.add_argument("--poses", metavar="FILE.npy",
                     help="(N, 4, 4) world <- tool poses in the robot's length unit")
    src.add_argument("--joints", metavar="FILE.npy", help="(N, 6) joints in rad; solve their poses")
    p.add_argument("--seed", type=count, default=0, help="random seed for --random (default 0)")
    p.add_argument("--within-limits", action="store_true",
                   help="--random: draw the joints within the robot's limits")
    p.add_argument("--out", required=True, metavar="PATH",
                   help="output directory of .npy files (memory-mappable), or a .npz file")
    p.add_argument("--chunk", type=count, default=None, metavar="C",
                   help=f"poses per chunk (default 65536, at most {MAX_CHUNK}; about 1.6 kB of memory "
                        "per pose)")
    p.add_argument("--max-poses", type=count, default=MAX_POSES, metavar="N",
                   help=f"refuse more poses than this (default {MAX_POSES:,}; about 400 bytes of "
                        "output a pose)")
    p.add_argument("--progress", action="store_true",
                   help="draw the progress bar even when stderr is not a terminal")
    p.add_argument("--json", action="store_true", help="print the summary as JSON")
    p.set_defaults(run=run)


class _RoundedPoses:
    """The poses of a file, read chunk by chunk, with rotations rounded by other tools (an
    orthonormality error up to ``CLI_ORTHONORMAL_TOL``, beyond the API's strict one)
    projected onto the nearest rotation; worse rows are left as they are (marked invalid)."""

    def __init__(self, arr) -> None:
        self.arr = arr
        self.shape = arr.shape
        self.projected = 0
        self.worst = 0.0

    def __len__(self) -> int:
        return len(self.arr)

    def __getitem__(self, index: slice):
        import numpy as np

        from ...geometry.rotations import nearest_rotation

        T = np.array(self.arr[index], dtype=float)
        R = T[:, :3, :3]
        with np.errstate(all="ignore"):
            err = np.abs(np.swapaxes(R, 1, 2) @ R - np.eye(3)).max(axis=(1, 2))
            bottom = np.abs(T[:, 3] - (0.0, 0.0, 0.0, 1.0)).max(axis=1)
            fix = ((err > ORTHONORMAL_TOL) | (bottom > ORTHONORMAL_TOL)) & (err <= CLI_ORTHONORMAL_TOL) \
                & (bottom <= CLI_ORTHONORMAL_TOL) & (np.linalg.det(R) > 0)
        if fix.any():
            T[fix, :3, :3] = nearest_rotation(R[fix])
            T[fix, 3] = (0.0, 0.0, 0.0, 1.0)
            self.projected += int(fix.sum())
            self.worst = max(self.worst, float(err[fix].max()))
        return T


def _load_npy(path: str, shape_tail: tuple[int, ...], what: str):
    import zipfile

    import numpy as np

    try:
        with open(path, "rb") as fh:
            magic = fh.read(6)
    except FileNotFoundError as exc:
        raise CliError(f"{path}: no such file") from exc
    except IsADirectoryError as exc:
        raise CliError(f"{path}: is a directory; expected a .npy file") from exc
    except OSError as exc:
        raise CliError(f"{path}: cannot read ({exc.strerror})") from exc
    if magic[:4] == b"PK\x03\x04":  # an .npz archive: take its one array (or 'T' / 'q')
        arr = _from_npz(path, what)
    else:
        try:
            arr = np.load(path, mmap_mode="r", allow_pickle=False)
        except (OSError, ValueError, EOFError, zipfile.BadZipFile) as exc:
            raise CliError(f"{path}: not a .npy array file ({_short(exc)})") from exc
    if not isinstance(arr, np.ndarray):
        raise CliError(f"{path}: not a .npy array file")
    if arr.ndim != 1 + len(shape_tail) or tuple(arr.shape[1:]) != shape_tail:
        want = ", ".join(["N"] + [str(s) for s in shape_tail])
        raise CliError(f"{path}: {what} must have shape ({want}); got {arr.shape}")
    if arr.dtype.kind not in "fiu":
        raise CliError(f"{path}: {what} must be real numbers; got dtype {arr.dtype}")
    return arr


def _short(exc) -> str:
    text = " ".join(str(exc).split())
    return text if len(text) <= 120 else text[:117] + "..."


def _from_npz(path: str, what: str):
    import zipfile

    import numpy as np

    try:
        with np.load(path, allow_pickle=False) as z:
            names = list(z.files)
            key = names[0] if len(names) == 1 else next((k for k in ("T", "poses", "q", "joints")
                                                          if k in names), None)
            if key is None:
                raise CliError(f"{path}: an .npz with several arrays {names}; give a .npy file of the "
                               f"{what}, or an .npz with one array")
            check_work(f"bytes in {path}:{key}", _npz_member_size(path, key), 4 << 30,
                       "a .npy file (memory-mapped, any size)")
            return z[key]
    except (OSError, ValueError, EOFError, KeyError, zipfile.BadZipFile) as exc:
        if isinstance(exc, ValueError) and "limit" in str(exc):
            raise CliError(str(exc)) from exc
        raise CliError(f"{path}: not a valid .npz archive ({_short(exc)})") from exc


def _npz_member_size(path: str, key: str) -> int:
    import zipfile

    with zipfile.ZipFile(path) as zf:
        return zf.getinfo(key + ".npy").file_size


def run(args) -> int:
    from ...ik.chunked import DEFAULT_CHUNK, FromJoints, RandomPoses, write_solutions
    from ...progress import Progress

    robot = load_cli_robot(args)
    chunk = DEFAULT_CHUNK if args.chunk is None else args.chunk
    if chunk < 1:
        raise CliError(f"--chunk must be a positive number of poses; got {chunk}")
    if chunk > MAX_CHUNK:
        raise CliError(f"--chunk {chunk} would need about {chunk * 1.6e3 / 1e9:.3g} GB of memory; "
                       f"at most {MAX_CHUNK} poses a chunk")
    try:
        if args.random is not None:
            check_work("poses", args.random, args.max_poses, "--max-poses")
            source = RandomPoses(robot, args.random, seed=args.seed, within_limits=args.within_limits)
            what = f"{args.random} random poses (seed {args.seed})"
        elif args.poses is not None:
            source = _RoundedPoses(_load_npy(args.poses, (4, 4), "poses"))
            check_work("poses", len(source), args.max_poses, "--max-poses")
            what = f"{len(source)} poses of {args.poses}"
        else:
            joints = _load_npy(args.joints, (6,), "joints")
            check_work("joint vectors", len(joints), args.max_poses, "--max-poses")
            source = FromJoints(robot, joints)
            what = f"the poses of {len(source)} joint vectors of {args.joints}"
    except ValueError as exc:
        raise CliError(str(exc)) from exc
    try:
        with Progress(len(source), "solving", force=args.progress) as bar:
            summary = write_solutions(robot, source, args.out, chunk=chunk, progress=bar,
                                      meta={"source": what})
    except ValueError as exc:
        raise CliError(str(exc)) from exc
    if isinstance(source, _RoundedPoses) and source.projected:
        print(f"note: {source.projected} poses of {args.poses} had rotations rounded beyond "
              f"{ORTHONORMAL_TOL:g} and were projected onto the nearest rotation (max |R^T R - I| "
              f"was {source.worst:.2e})", file=sys.stderr)
    if args.json:
        print_json({"robot": robot.name, "source": what, "poses": summary.poses,
                    "solutions": summary.solutions, "unreachable": summary.unreachable,
                    "invalid": summary.invalid, "max_count": summary.max_count,
                    "seconds": summary.seconds, "poses_per_second": summary.poses_per_second,
                    "out": str(summary.path)})
        return 0
    print(f"robot {robot.name}: {what}")
    print(f"  {summary.solutions} solutions ({summary.solutions / max(summary.poses, 1):.2f} per pose, "
          f"at most {summary.max_count}); {summary.unreachable} poses out of reach, "
          f"{summary.invalid} not valid transforms (NaN rows included)")
    print(f"  {summary.seconds:.2f} s, {summary.poses_per_second:,.0f} poses/s -> {summary.path}")
    return 0
