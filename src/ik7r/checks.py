"""Validation at the boundary: small ``check_*`` functions that raise ``ValueError`` saying
what was expected and what came."""

from __future__ import annotations

import numpy as np

from .rotations import nearest_rotation

__all__ = [
    "ORTHONORMAL_TOL",
    "check_joints",
    "check_transforms",
    "check_config",
    "check_finite",
    "transforms_status",
]

#: Largest entry of ``|R^T R - I|`` (and of ``|bottom row - [0, 0, 0, 1]|``) accepted in a pose.
#: Accepted rotations are projected to the nearest proper rotation before solving, so poses
#: printed with 7 significant digits (as in the paper) can be used directly.
ORTHONORMAL_TOL = 1e-6


def check_finite(x: np.ndarray, name: str) -> None:
    """Raise ``ValueError`` if ``x`` holds NaN or infinity."""
    if not np.all(np.isfinite(x)):
        raise ValueError(f"{name} must be finite; got NaN or infinity")


def check_joints(q, name: str = "q", ndof: int = 6) -> np.ndarray:
    """``q`` as a float array of shape ``(..., ndof)``, finite (radians)."""
    try:
        arr = np.asarray(q, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} must be numbers of shape (..., {ndof}); got {q!r}") from exc
    if arr.ndim == 0 or arr.shape[-1] != ndof:
        raise ValueError(
            f"{name} must have shape (..., {ndof}) (joints [q1, q2, q3, q4, q5, q7] in rad); "
            f"got shape {arr.shape}"
        )
    check_finite(arr, name)
    return arr


def _as_transforms(T, name: str) -> np.ndarray:
    try:
        arr = np.asarray(T, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} must be numbers of shape (..., 4, 4); got {T!r}") from exc
    if arr.ndim < 2 or arr.shape[-2:] != (4, 4):
        raise ValueError(f"{name} must have shape (..., 4, 4) (homogeneous transforms); "
                         f"got shape {arr.shape}")
    return arr


def transforms_status(T, name: str = "T") -> tuple[np.ndarray, np.ndarray, list[str]]:
    """Validate every pose of ``T`` (..., 4, 4) without raising on a bad pose.

    Returns ``(T_clean, ok, reasons)``: the poses with their rotations projected to the
    nearest rotation (bad poses replaced by the identity), a boolean mask of the good ones,
    and for each bad one a sentence saying why. Raises only when the shape is wrong.
    """
    arr = _as_transforms(T, name)
    flat = arr.reshape(-1, 4, 4)
    ok = np.all(np.isfinite(flat), axis=(1, 2))
    reasons = ["" if good else "NaN or infinity" for good in ok]
    clean = np.where(ok[:, None, None], flat, np.eye(4))
    R = clean[:, :3, :3]
    orth = np.abs(np.swapaxes(R, 1, 2) @ R - np.eye(3)).max(axis=(1, 2))
    det = np.linalg.det(R)
    bottom = np.abs(clean[:, 3, :] - np.array([0.0, 0.0, 0.0, 1.0])).max(axis=1)
    for i in np.flatnonzero(ok):
        if bottom[i] > ORTHONORMAL_TOL:
            reasons[i] = f"bottom row is {flat[i, 3].tolist()}, expected [0, 0, 0, 1]"
        elif orth[i] > ORTHONORMAL_TOL or det[i] <= 0:
            reasons[i] = (
                f"rotation is not proper orthonormal (max |R^T R - I| = {orth[i]:.2e}, "
                f"det = {det[i]:.6f}; expected within {ORTHONORMAL_TOL:g} and det = +1)"
            )
    ok = np.array([r == "" for r in reasons], dtype=bool)
    clean = np.where(ok[:, None, None], clean, np.eye(4))
    clean[:, :3, :3] = nearest_rotation(clean[:, :3, :3])
    clean[:, 3, :] = (0.0, 0.0, 0.0, 1.0)
    return clean.reshape(arr.shape), ok.reshape(arr.shape[:-2]), reasons


def check_transforms(T, name: str = "T") -> np.ndarray:
    """``T`` as valid poses ``(..., 4, 4)``: finite, bottom row ``[0, 0, 0, 1]`` and a proper
    orthonormal rotation within :data:`ORTHONORMAL_TOL` (then projected to the nearest rotation).
    """
    clean, ok, reasons = transforms_status(T, name)
    if not np.all(ok):
        first = int(np.flatnonzero(~ok.reshape(-1))[0])
        where = f" (pose {first})" if clean.ndim > 2 else ""
        raise ValueError(f"{name}{where}: {reasons[first]}")
    return clean


def check_config(config) -> tuple[int, int, int]:
    """``config`` (1..8, or ``(arm, elbow, wrist)`` with each 0 or 1) -> ``(arm, elbow, wrist)``.

    Numbering of the paper's Appendix 3: ``config = 1 + 4 (1 - arm) + 2 (1 - elbow) + (1 - wrist)``.
    """
    if isinstance(config, (tuple, list)) and len(config) == 3:
        vals = []
        for v in config:
            if isinstance(v, (bool, np.bool_)) or not isinstance(v, (int, np.integer)) or v not in (0, 1):
                raise ValueError(f"config (arm, elbow, wrist) must hold 0 or 1 each; got {config!r}")
            vals.append(int(v))
        return vals[0], vals[1], vals[2]
    if isinstance(config, (bool, np.bool_)) or not isinstance(config, (int, np.integer)):
        raise ValueError(f"config must be an integer 1..8 or (arm, elbow, wrist); got {config!r}")
    if not 1 <= int(config) <= 8:
        raise ValueError(f"config must be 1..8 (the paper's Appendix 3); got {config}")
    c = int(config) - 1
    return 1 - (c >> 2), 1 - ((c >> 1) & 1), 1 - (c & 1)
