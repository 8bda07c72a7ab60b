"""Work limits: every command estimates its work before allocating and refuses what exceeds
these, naming the size and the option that raises the limit.

=============================  ==================  ==========================================
limit                          default             raised by
=============================  ==================  ==========================================
:data:`MAX_POSES`              1,000,000,000       ``ik7r batch --max-poses N``
:data:`MAX_CHUNK`              1,048,576 poses     (fixed: about 1.7 GB of working memory)
:data:`MAX_PATH_SAMPLES`       1,000,000           ``ik7r paint ... --max-samples N``
:data:`MAX_TRAJECTORY_ROWS`    1,000,000           ``ik7r paint ... --max-rows N``
:data:`MAX_FRAMES`             2,000               (fixed: animation frames)
:data:`MAX_BENCH_POSES`        10,000,000          (fixed: ``ik7r bench --n``)
:data:`MAX_ROBOT_FILE_BYTES`   64 MiB              ``load_robot(..., max_bytes=N)``
:data:`MAX_PATH_FILE_BYTES`    1 GiB               ``load_path_csv(..., max_bytes=N)``
=============================  ==================  ==========================================
"""

from __future__ import annotations

import contextlib
import contextvars
import math

from .errors import Ik7rError

__all__ = ["rows_estimate", "limit", "raised",
           "MAX_POSES", "MAX_CHUNK", "MAX_PATH_SAMPLES", "MAX_TRAJECTORY_ROWS", "MAX_FRAMES",
           "MAX_BENCH_POSES", "MAX_ROBOT_FILE_BYTES", "MAX_PATH_FILE_BYTES", "WorkLimitError",
           "check_work"]

#: Poses of one ``ik7r batch`` run (about 400 bytes of output each: 400 GB at the limit).
MAX_POSES = 1_000_000_000
#: Poses per chunk of a batch (about 1.6 kB of working memory each).
MAX_CHUNK = 1 << 20
#: Samples of a painting path (a raster's passes and turns, or the rows of a CSV path).
MAX_PATH_SAMPLES = 1_000_000
#: Rows of a painting trajectory (duration times ``--rate``; 25 numbers each).
MAX_TRAJECTORY_ROWS = 1_000_000
#: Frames of a painting animation.
MAX_FRAMES = 2_000
#: Poses of a benchmark batch (``ik7r bench --n``).
MAX_BENCH_POSES = 10_000_000
#: Size of a robot file (TOML or URDF); real ones are a few kB, a 20,000-link URDF 2 MB.
MAX_ROBOT_FILE_BYTES = 64 << 20
#: Size of a path CSV file.
MAX_PATH_FILE_BYTES = 1 << 30


class WorkLimitError(Ik7rError, ValueError):
    """The work asked for exceeds a documented limit; the message names the size, the limit
    and the option that raises it."""


def check_work(what: str, size: float, limit: int, raise_with: str) -> None:
    """Raise :class:`WorkLimitError` when ``size`` (an estimate, may be a float) exceeds ``limit``.

    >>> check_work("path samples", 1200, MAX_PATH_SAMPLES, "--max-samples")
    >>> check_work("path samples", 8e11, MAX_PATH_SAMPLES, "--max-samples")
    Traceback (most recent call last):
    ...
    ik7r.limits.WorkLimitError: 800,000,000,000 path samples exceed the limit of 1,000,000 (raise it with --max-samples)
    """  # noqa: E501 (a message is one line)
    if not size <= limit:  # NaN counts as too big
        integral = isinstance(size, int) or (isinstance(size, float) and size.is_integer())
        shown = f"{int(size):,}" if integral and size < 1e15 else f"{float(size):.3g}"
        raise WorkLimitError(f"{shown} {what} exceed the limit of {limit:,} (raise it with {raise_with})")


def rows_estimate(duration: float, rate: float) -> float:
    """Rows of a trajectory of ``duration`` s sampled at ``rate`` Hz (a float: inf when absurd)."""
    x = duration * rate
    return float(math.floor(x + 1e-9) + 1) if math.isfinite(x) else math.inf


_RAISED: contextvars.ContextVar[dict | None] = contextvars.ContextVar("ik7r_limits", default=None)


def limit(name: str) -> int:
    """The limit ``name`` (e.g. ``"MAX_TRAJECTORY_ROWS"``) in force: the module's default, or the
    value set by an enclosing :func:`raised`."""
    return (_RAISED.get() or {}).get(name, globals()[name])


@contextlib.contextmanager
def raised(**limits: int):
    """Inside the block the named limits are the given values (the command line's ``--max-rows``
    reaches the library's checks this way; other threads and contexts are not affected).

    >>> with raised(MAX_TRAJECTORY_ROWS=5):
    ...     limit("MAX_TRAJECTORY_ROWS")
    5
    """
    for name in limits:
        if name not in __all__:
            raise ValueError(f"unknown limit {name!r}")
    token = _RAISED.set({**(_RAISED.get() or {}), **limits})
    try:
        yield
    finally:
        _RAISED.reset(token)
