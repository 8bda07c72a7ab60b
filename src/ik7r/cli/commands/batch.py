"""``ik7r batch``: every solution of many poses (millions), in bounded memory, to files."""

from __future__ import annotations

from ..errors import CliError
from ._common import load_cli_robot, print_json


def add_parser(sub) -> None:
    p = sub.add_parser(
        "batch", help="every solution of many poses, streamed to .npy / .npz files",
        description="Solve every pose of a set (random joints, a .npy file of poses or of "
                    "joints) with the complete solver, chunk by chunk in bounded memory, and "
                    "write every solution: q (M, 6) rad and offsets (N + 1,): the solutions "
                    "of pose i are q[offsets[i]:offsets[i + 1]].")
    src = p.add_mutually_exclusive_group(required=True)
    src.add_argument("--random", type=int, metavar="N", help="N poses of uniformly random joints")
    src.add_argument("--poses", metavar="FILE.npy",
                     help="(N, 4, 4) world <- tool poses in the robot's length unit")
    src.add_argument("--joints", metavar="FILE.npy", help="(N, 6) joints in rad; solve their poses")
    p.add_argument("--seed", type=int, default=0, help="random seed for --random (default 0)")
    p.add_argument("--within-limits", action="store_true",
                   help="--random: draw the joints within the robot's limits")
    p.add_argument("--out", required=True, metavar="PATH",
                   help="output directory of .npy files (memory-mappable), or a .npz file")
    p.add_argument("--chunk", type=int, default=None, metavar="C",
                   help="poses per chunk (default 65536; about 1.6 kB of memory per pose)")
    p.add_argument("--progress", action="store_true",
                   help="draw the progress bar even when stderr is not a terminal")
    p.add_argument("--json", action="store_true", help="print the summary as JSON")
    p.set_defaults(run=run)


def _load_npy(path: str, shape_tail: tuple[int, ...], what: str):
    import numpy as np

    try:
        arr = np.load(path, mmap_mode="r", allow_pickle=False)
    except FileNotFoundError as exc:
        raise CliError(f"{path}: no such file") from exc
    except (OSError, ValueError) as exc:
        raise CliError(f"{path}: not a .npy array file ({exc})") from exc
    if arr.ndim != 1 + len(shape_tail) or tuple(arr.shape[1:]) != shape_tail:
        want = ", ".join(["N"] + [str(s) for s in shape_tail])
        raise CliError(f"{path}: {what} must have shape ({want}); got {arr.shape}")
    if arr.dtype.kind not in "fiu":
        raise CliError(f"{path}: {what} must be numbers; got dtype {arr.dtype}")
    return arr


def run(args) -> int:
    from ...ik.chunked import DEFAULT_CHUNK, FromJoints, RandomPoses, write_solutions
    from ...progress import Progress

    robot = load_cli_robot(args)
    chunk = DEFAULT_CHUNK if args.chunk is None else args.chunk
    if chunk < 1:
        raise CliError(f"--chunk must be a positive number of poses; got {chunk}")
    if args.random is not None:
        if args.random < 0:
            raise CliError(f"--random takes a non-negative number of poses; got {args.random}")
        if args.seed < 0:
            raise CliError(f"--seed must be non-negative; got {args.seed}")
        source = RandomPoses(robot, args.random, seed=args.seed, within_limits=args.within_limits)
        what = f"{args.random} random poses (seed {args.seed})"
    elif args.poses is not None:
        source = _load_npy(args.poses, (4, 4), "poses")
        what = f"{len(source)} poses of {args.poses}"
    else:
        try:
            source = FromJoints(robot, _load_npy(args.joints, (6,), "joints"))
        except ValueError as exc:
            raise CliError(str(exc)) from exc
        what = f"the poses of {len(source)} joint vectors of {args.joints}"
    try:
        with Progress(len(source), "solving", force=args.progress) as bar:
            summary = write_solutions(robot, source, args.out, chunk=chunk, progress=bar,
                                      meta={"source": what})
    except (OSError, ValueError) as exc:
        raise CliError(str(exc)) from exc
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
          f"{summary.invalid} not valid transforms")
    print(f"  {summary.seconds:.2f} s, {summary.poses_per_second:,.0f} poses/s -> {summary.path}")
    return 0
