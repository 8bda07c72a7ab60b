"""Validation at the boundary: small ``check_*`` functions that raise ``ValueError`` saying
what was expected and what came."""

from __future__ import annotations

import numpy as np

from .._typing import ArrayLike, Config

__all__ = [
    "ORTHONORMAL_TOL",
    "check_joints",
    "check_transforms",
    "check_config",
    "check_finite",
    "reduce_seeds",
    "transforms_status",
    "poses_status",
    "project_transforms",
]

#: Largest entry of ``|R^T R - I|`` (and of ``|bottom row - [0, 0, 0, 1]|``) accepted in a pose.
#: Accepted rotations are projected to the nearest proper rotation before solving, so poses
#: printed with 7 significant digits (as in the paper) can be used directly.
ORTHONORMAL_TOL = 1e-6


def _short(x) -> str:
    text = repr(x)
    return text if len(text) <= 80 else text[:77] + "..."


def check_finite(x: np.ndarray, name: str) -> None:
    """Raise ``ValueError`` if ``x`` holds NaN or infinity."""
    if not np.all(np.isfinite(x)):
        raise ValueError(f"{name} must be finite; got NaN or infinity")


def _real_array(x, name: str, shape: str) -> np.ndarray:
    """``x`` as a float array; complex numbers (even with zero imaginary parts) are refused
    with a ``ValueError`` instead of being cut to their real part (numpy's ComplexWarning)."""
    if isinstance(x, complex) or getattr(getattr(x, "dtype", None), "kind", None) == "c":
        raise ValueError(f"{name} must be real numbers of shape {shape}; got complex numbers")
    try:
        return np.asarray(x, dtype=float)
    except TypeError as exc:
        if "complex" in str(exc):
            raise ValueError(f"{name} must be real numbers of shape {shape}; got complex numbers") from None
        raise
    except ValueError:
        if isinstance(x, (list, tuple)) and np.asarray(x, dtype=object).size and any(
                isinstance(v, complex) for v in np.asarray(x, dtype=object).reshape(-1)):
            raise ValueError(f"{name} must be real numbers of shape {shape}; got complex numbers") from None
        raise


def check_joints(q: ArrayLike, name: str = "q", ndof: int = 6) -> np.ndarray:
    """``q`` as a float array of shape ``(..., ndof)``, finite (radians)."""
    if type(q) is np.ndarray and q.dtype == np.float64 and q.ndim and q.shape[-1] == ndof:
        check_finite(q, name)  # the common case, fast
        return q
    try:
        arr = _real_array(q, name, f"(..., {ndof})")
    except (TypeError, ValueError) as exc:
        if "complex" in str(exc):
            raise
        raise ValueError(f"{name} must be numbers of shape (..., {ndof}); got {_short(q)}") from exc
    if arr.ndim == 0 or arr.shape[-1] != ndof:
        raise ValueError(
            f"{name} must have shape (..., {ndof}) (joints [q1, q2, q3, q4, q5, q7] in rad); "
            f"got shape {arr.shape}"
        )
    check_finite(arr, name)
    return arr


def reduce_seeds(s: np.ndarray) -> np.ndarray:
    """Seeds (..., 6) with every joint beyond ``ik7r.robot.family.MAX_JOINT_ANGLE`` reduced modulo
    2 pi to (-pi, pi]: seeds are periodic, and such a value lies outside every joint's limits
    (the kernels' ``reduced_seed`` does the same, bit for bit)."""
    from ..robot.family import MAX_JOINT_ANGLE
    from .rotations import wrap_angle

    s = np.asarray(s, dtype=float)
    if np.all(np.abs(s) <= MAX_JOINT_ANGLE):
        return s
    return np.where(np.abs(s) <= MAX_JOINT_ANGLE, s, wrap_angle(s))


def _as_transforms(T, name: str) -> np.ndarray:
    try:
        arr = _real_array(T, name, "(..., 4, 4)")
    except (TypeError, ValueError) as exc:
        if "complex" in str(exc):
            raise
        raise ValueError(f"{name} must be numbers of shape (..., 4, 4); got {_short(T)}") from exc
    if arr.ndim < 2 or arr.shape[-2:] != (4, 4):
        raise ValueError(f"{name} must have shape (..., 4, 4) (homogeneous transforms); "
                         f"got shape {arr.shape}")
    return arr


def _kernel():
    global _VALIDATE
    if _VALIDATE is None:
        from .._kernels import validate_pose, validate_poses

        _VALIDATE = (validate_pose, validate_poses)
    return _VALIDATE


_VALIDATE = None


def _reason(T: np.ndarray) -> str:
    """Why the pose ``T`` (4, 4) was rejected (called for rejected poses only)."""
    if not np.all(np.isfinite(T)):
        return "NaN or infinity"
    if np.abs(T[3, :] - np.array([0.0, 0.0, 0.0, 1.0])).max() > ORTHONORMAL_TOL:
        return f"bottom row is {T[3].tolist()}, expected [0, 0, 0, 1]"
    R = T[:3, :3]
    orth = np.abs(R.T @ R - np.eye(3)).max()
    det = np.linalg.det(R)
    return (
        f"rotation is not proper orthonormal (max |R^T R - I| = {orth:.2e}, "
        f"det = {det:.6f}; expected within {ORTHONORMAL_TOL:g} and det = +1)"
    )


def poses_status(T: ArrayLike, name: str = "T") -> tuple[np.ndarray, np.ndarray]:
    """:func:`transforms_status` without the reasons (the fast form for big batches).

    Returns ``(T_clean, ok)``: ``T_clean`` a new C-contiguous array of the shape of ``T``
    (..., 4, 4), ``ok`` a boolean array of shape ``T.shape[:-2]``.
    """
    arr = _as_transforms(T, name)
    flat = np.ascontiguousarray(arr.reshape(-1, 4, 4))
    clean = np.empty(flat.shape)
    ok = np.empty(flat.shape[0], dtype=bool)
    poses_status_into(flat, clean, ok)
    return clean.reshape(arr.shape), ok.reshape(arr.shape[:-2])


def pose_batch(T: ArrayLike, name: str = "T") -> np.ndarray:
    """``T`` as a C-contiguous float array (N, 4, 4) (a copy only when it is not one already);
    the poses themselves are checked by :func:`poses_status_into`."""
    arr = _as_transforms(T, name)
    if arr.ndim != 3:
        raise ValueError(f"{name} must have shape (N, 4, 4); got {arr.shape}")
    return np.ascontiguousarray(arr)


def poses_status_into(flat: np.ndarray, clean: np.ndarray, ok: np.ndarray) -> None:
    """:func:`poses_status` of ``flat`` (N, 4, 4) (C-contiguous floats) into ``clean``
    (N, 4, 4) and ``ok`` (N,) bool: the batch functions run it chunk by chunk in their
    threads."""
    codes = np.empty(flat.shape[0], dtype=np.int8)
    _kernel()[1](flat, ORTHONORMAL_TOL, clean, codes)
    np.equal(codes, 0, out=ok)


def transforms_status(T: ArrayLike, name: str = "T") -> tuple[np.ndarray, np.ndarray, list[str]]:
    """Validate every pose of ``T`` (..., 4, 4) without raising on a bad pose.

    Returns ``(T_clean, ok, reasons)``: the poses with their rotations projected to the
    nearest rotation (bad poses replaced by the identity), a boolean mask of the good ones,
    and for each bad one a sentence saying why. Raises only when the shape is wrong.
    """
    arr = _as_transforms(T, name)
    clean, ok = poses_status(arr, name)
    flat = arr.reshape(-1, 4, 4)
    reasons = [""] * flat.shape[0]
    for i in np.flatnonzero(~ok.reshape(-1)):
        reasons[i] = _reason(flat[i])
    return clean, ok, reasons


def check_transforms(T: ArrayLike, name: str = "T") -> np.ndarray:
    """``T`` as valid poses ``(..., 4, 4)``: finite, bottom row ``[0, 0, 0, 1]`` and a proper
    orthonormal rotation within :data:`ORTHONORMAL_TOL` (then projected to the nearest rotation).
    """
    if (type(T) is np.ndarray and T.shape == (4, 4) and T.dtype == np.float64
            and T.flags.c_contiguous):
        # one pose: the common case, without the batch machinery
        clean = np.empty((4, 4))
        if _kernel()[0](T, ORTHONORMAL_TOL, clean, np.empty((3, 3))) == 0:
            return clean
        raise ValueError(f"{name}: {_reason(T)}")
    clean, ok = poses_status(T, name)
    if not np.all(ok):
        flat = _as_transforms(T, name).reshape(-1, 4, 4)
        first = int(np.flatnonzero(~ok.reshape(-1))[0])
        where = f" (pose {first})" if clean.ndim > 2 else ""
        raise ValueError(f"{name}{where}: {_reason(flat[first])}")
    return clean


def project_transforms(T: ArrayLike, tol: float = 1e-3, name: str = "T") -> tuple[np.ndarray, float, float]:
    """Poses whose rotations are *nearly* orthonormal, projected onto the nearest rotations.

    The explicit, lenient form of :func:`check_transforms` (which accepts only
    :data:`ORTHONORMAL_TOL`): for rotations typed or exported with few decimals (four decimals
    give errors up to about 1e-4). Each rotation ``R`` is replaced by the nearest proper
    rotation (:func:`ik7r.geometry.rotations.nearest_rotation`, the Frobenius norm's), the bottom
    row by ``[0, 0, 0, 1]``.

    Parameters
    ----------
    T : array_like, shape (..., 4, 4)
    tol : float
        Largest accepted entry of ``|R^T R - I|`` (and of the bottom row's deviation).
    name : str
        For messages.

    Returns
    -------
    T_projected : ndarray, shape (..., 4, 4)
    error : float
        The largest ``|R^T R - I|`` entry found.
    moved : float
        The largest change of an entry of ``T`` made by the projection.

    Raises
    ------
    ValueError
        NaN or infinity, an error above ``tol``, or ``det R < 0`` (a reflection).

    Examples
    --------
    >>> import numpy as np
    >>> R = np.round([[0.36, -0.48, 0.8], [0.8, 0.6, 0.0], [-0.48, 0.64, 0.6]], 4)
    >>> T, err, moved = project_transforms(np.block([[R, np.zeros((3, 1))], [np.zeros((1, 3)), 1]]))
    >>> bool(np.allclose(T[:3, :3].T @ T[:3, :3], np.eye(3), atol=1e-14)), err < 1e-3
    (True, True)
    """
    arr = np.array(_as_transforms(T, name), dtype=float)
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite; got NaN or infinity")
    R = arr[..., :3, :3]
    gram = np.abs(np.swapaxes(R, -1, -2) @ R - np.eye(3)).max(initial=0.0)
    bottom = np.abs(arr[..., 3, :] - np.array([0.0, 0.0, 0.0, 1.0])).max(initial=0.0)
    err = float(max(gram, bottom))
    det = np.linalg.det(R)
    if err > tol or np.any(det <= 0):
        raise ValueError(f"{name}: rotation is not proper orthonormal (max |R^T R - I| = {gram:.2e}, "
                         f"bottom row off by {bottom:.2e}, det = {float(np.min(det)):.6f}; expected within "
                         f"{tol:g} and det = +1)")
    from .rotations import nearest_rotation

    out = arr.copy()
    out[..., :3, :3] = nearest_rotation(R)
    out[..., 3, :] = (0.0, 0.0, 0.0, 1.0)
    moved = float(np.abs(out - arr).max(initial=0.0))
    return out, err, moved


def check_config(config: Config) -> tuple[int, int, int]:
    """``config`` (1..8, or ``(arm, elbow, wrist)`` with each 0 or 1) -> ``(arm, elbow, wrist)``.

    Numbering of the paper's Appendix 3: ``config = 1 + 4 (1 - arm) + 2 (1 - elbow) + (1 - wrist)``.
    """
    if type(config) is int and 1 <= config <= 8:  # the common case, fast
        return _INDICATORS[config]
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


_INDICATORS = {c: (1 - ((c - 1) >> 2), 1 - (((c - 1) >> 1) & 1), 1 - ((c - 1) & 1)) for c in range(1, 9)}
