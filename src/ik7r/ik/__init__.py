"""Inverse kinematics: the complete certified solver (:mod:`.solve`), warm-started paths
(:mod:`.path`), big batches in chunks (:mod:`.chunked`), the paper's iteration (:mod:`.paper`)
and the Jacobian-based baselines (:mod:`.numeric`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from .._lazy import lazy_exports

_EXPORTS = {
    "ik_all": "solve",
    "ik": "solve",
    "ik_batch": "solve",
    "ik_all_batch": "solve",
    "MAX_SOLUTIONS": "solve",
    "MAX_WITHIN_LIMITS_ROWS": "solve",
    "num_threads": "solve",
    "threads_for": "solve",
    "PathIK": "path",
    "Lost": "path",
    "ik_path": "path",
    "follow": "path",
    "ChunkResult": "chunked",
    "FromJoints": "chunked",
    "RandomPoses": "chunked",
    "solve_all_chunked": "chunked",
    "write_solutions": "chunked",
    "BatchSummary": "chunked",
    "DEFAULT_CHUNK": "chunked",
    "PaperResult": "paper",
    "ik_paper": "paper",
    "NumericResult": "numeric",
    "newton_raphson": "numeric",
    "damped_least_squares": "numeric",
    "manipulability": "numeric",
}

if TYPE_CHECKING:  # the names, for type checkers and IDEs
    from .chunked import (
        DEFAULT_CHUNK,
        BatchSummary,
        ChunkResult,
        FromJoints,
        RandomPoses,
        solve_all_chunked,
        write_solutions,
    )
    from .numeric import NumericResult, damped_least_squares, manipulability, newton_raphson
    from .paper import PaperResult, ik_paper
    from .path import Lost, PathIK, follow, ik_path
    from .solve import (
        MAX_SOLUTIONS,
        MAX_WITHIN_LIMITS_ROWS,
        ik,
        ik_all,
        ik_all_batch,
        ik_batch,
        num_threads,
        threads_for,
    )

__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, ('solve', 'path', 'chunked', 'paper', 'numeric'))
__all__ = [
    "BatchSummary",
    "ChunkResult",
    "DEFAULT_CHUNK",
    "FromJoints",
    "Lost",
    "MAX_SOLUTIONS",
    "MAX_WITHIN_LIMITS_ROWS",
    "NumericResult",
    "PaperResult",
    "PathIK",
    "RandomPoses",
    "damped_least_squares",
    "follow",
    "ik",
    "ik_all",
    "ik_all_batch",
    "ik_batch",
    "ik_paper",
    "ik_path",
    "manipulability",
    "newton_raphson",
    "num_threads",
    "solve_all_chunked",
    "threads_for",
    "write_solutions",
]
