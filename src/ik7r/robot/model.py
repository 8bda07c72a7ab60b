"""The robot: an immutable description of a family member and its kinematics.

``Robot`` is a frozen dataclass. Its methods are thin: they validate at the boundary, then
call the pure compiled kernels (:mod:`ik7r._kernels.fk`, :mod:`ik7r._kernels.complete`) with the robot's
parameter vector, which is built once per robot and cached.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np

from .._kernels import params as L
from .._typing import ArrayLike, Config
from ..geometry.checks import check_joints
from .family import MAX_JOINT_ANGLE, Family, check_placement, family_of

if TYPE_CHECKING:
    from ..ik.paper import PaperResult
    from ..ik.path import PathIK, PoseAt

__all__ = ["Robot"]

DEFAULT_JOINT_NAMES = tuple(f"joint_{i}" for i in range(1, 8))
#: Names of the six independent joints ``[q1, q2, q3, q4, q5, q7]``, as printed in reports.
JOINT_LABELS = ("q1", "q2", "q3", "q4", "q5", "q7")


_MODULES: dict = {}


def _lazy(name: str):
    """The submodule ``ik7r.<name>``, imported on first use (kept out of import time, and out
    of every call: a function-level import costs about a microsecond)."""
    mod = _MODULES.get(name)
    if mod is None:
        import importlib

        mod = _MODULES[name] = importlib.import_module(f"ik7r.{name}")
    return mod


def _frozen(x, shape, name) -> np.ndarray:
    arr = np.array(x, dtype=float)
    if arr.shape != shape:
        raise ValueError(f"{name} must have shape {shape}; got {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite; got {arr.tolist()}")
    arr.setflags(write=False)
    return arr


@dataclass(frozen=True, eq=False)
class Robot:
    """A 7R 6-DOF robot with a coupled hollow wrist (immutable).

    Parameters
    ----------
    name : str
        Name of the robot.
    dh : array_like, shape (7, 4)
        Craig's modified DH rows ``(a_{i-1}, alpha_{i-1}, d_i, theta_offset_i)``: lengths in
        ``unit``, angles in rad. The DH angle of joint i is ``sign_i * q_i + theta_offset_i``.
    unit : str
        Length unit of ``dh``, ``base`` and ``tool`` (``"mm"`` for the paper robot, ``"m"``
        for URDF robots).
    lower, upper : array_like, shape (6,)
        Joint limits of the independent joints ``[q1, q2, q3, q4, q5, q7]`` (rad), within
        +-``ik7r.robot.family.MAX_JOINT_ANGLE`` (100 rad; see docs/guide/ranges.md for every range).
    velocity, acceleration : array_like, shape (6,), optional
        Joint speed (rad/s) and acceleration (rad/s^2) limits.
    coupling : (float, float)
        ``q6 = coupling[0] * q5 + coupling[1]`` (joint 6 mirrors joint 5).
    joint_sign : array_like, shape (7,)
        +1 or -1 per joint (the joint turns about +z or -z of its DH frame).
    base : array_like, shape (4, 4)
        World <- frame 0 transform.
    tool : array_like, shape (4, 4)
        Frame 7 <- tool (TCP) transform.
    joint_names : tuple of 7 str
        Names of the seven joints (the sixth is the coupled one).
    """

    name: str
    dh: np.ndarray
    unit: str = "mm"
    lower: np.ndarray = field(default_factory=lambda: np.full(6, -np.pi))
    upper: np.ndarray = field(default_factory=lambda: np.full(6, np.pi))
    velocity: np.ndarray | None = None
    acceleration: np.ndarray | None = None
    coupling: tuple[float, float] = (-1.0, 0.0)
    joint_sign: np.ndarray = field(default_factory=lambda: np.ones(7))
    base: np.ndarray = field(default_factory=lambda: np.eye(4))
    tool: np.ndarray = field(default_factory=lambda: np.eye(4))
    joint_names: tuple[str, ...] = DEFAULT_JOINT_NAMES
    description: str = ""

    def __post_init__(self) -> None:
        put = object.__setattr__
        put(self, "dh", _frozen(self.dh, (7, 4), "dh"))
        for key in ("lower", "upper"):
            lim = np.array(getattr(self, key), dtype=float)
            if lim.shape == (6,) and not np.all(np.abs(lim) <= MAX_JOINT_ANGLE):  # (NaN too)
                raise ValueError(
                    f"{key} limits must be finite and within +-MAX_JOINT_ANGLE = {MAX_JOINT_ANGLE:g} rad "
                    f"({math.degrees(MAX_JOINT_ANGLE):.6g} deg, {MAX_JOINT_ANGLE / (2 * math.pi):.3g} turns: "
                    f"beyond it float spacing cannot meet the tolerance); got {lim.tolist()}")
        put(self, "lower", _frozen(self.lower, (6,), "lower"))
        put(self, "upper", _frozen(self.upper, (6,), "upper"))
        if np.any(self.lower > self.upper):
            raise ValueError(f"lower limits must not exceed upper limits; got {self.lower} > {self.upper}")
        for key in ("velocity", "acceleration"):
            val = getattr(self, key)
            if val is not None:
                arr = _frozen(val, (6,), key)
                if np.any(arr <= 0):
                    raise ValueError(f"{key} limits must be positive; got {arr.tolist()}")
                put(self, key, arr)
        sign = _frozen(self.joint_sign, (7,), "joint_sign")
        if not np.all(np.abs(sign) == 1.0):
            raise ValueError(f"joint_sign must hold +1 or -1; got {sign.tolist()}")
        put(self, "joint_sign", sign)
        for key in ("base", "tool"):
            T = _frozen(getattr(self, key), (4, 4), key)
            R = T[:3, :3]
            if (np.abs(R.T @ R - np.eye(3)).max() > 1e-9 or np.linalg.det(R) <= 0
                    or np.abs(T[3] - (0, 0, 0, 1)).max() > 0):
                raise ValueError(f"{key} must be a rigid transform (proper rotation within 1e-9)")
            put(self, key, T)
        c = tuple(float(x) for x in self.coupling)
        if len(c) != 2 or not all(math.isfinite(x) for x in c):
            raise ValueError(f"coupling must be (multiplier, offset); got {self.coupling!r}")
        put(self, "coupling", c)
        names = tuple(str(n) for n in self.joint_names)
        if len(names) != 7:
            raise ValueError(f"joint_names must name 7 joints; got {len(names)}")
        put(self, "joint_names", names)
        put(self, "unit", str(self.unit))
        # raises FamilyError (a ValueError) naming the joint that is not of the family
        fam = family_of(self.dh, self.joint_sign, self.coupling, names)
        put(self, "_family", fam)
        for key in ("base", "tool"):
            check_placement(getattr(self, key), fam.scale, key)

    # ------------------------------------------------------------------ description
    @property
    def family(self) -> Family:
        """The nominal (idealised) family parameters the solvers work with."""
        return self._family  # type: ignore[attr-defined]

    @property
    def independent_joint_names(self) -> tuple[str, ...]:
        """Names of the six independent joints ``[q1, q2, q3, q4, q5, q7]``."""
        n = self.joint_names
        return (n[0], n[1], n[2], n[3], n[4], n[6])

    def replace(self, **changes: Any) -> Robot:
        """A copy with some fields changed (``dataclasses.replace``)."""
        from dataclasses import replace

        return replace(self, **changes)

    def with_tool(self, T_flange_tool: ArrayLike) -> Robot:
        """A copy whose tool (TCP) is ``T_flange_tool`` (4, 4), frame 7 <- tool."""
        return self.replace(tool=np.asarray(T_flange_tool, dtype=float))

    def with_base(self, T_world_base: ArrayLike) -> Robot:
        """A copy whose base is ``T_world_base`` (4, 4), world <- frame 0."""
        return self.replace(base=np.asarray(T_world_base, dtype=float))

    def to_toml(self) -> str:
        """The robot as the text of a TOML robot file (see :func:`ik7r.robot.writers.robot_to_toml`)."""
        from .writers import robot_to_toml

        return robot_to_toml(self)

    def to_urdf(self) -> str:
        """The robot as the text of a URDF with a ``<mimic>`` joint (see :mod:`ik7r.robot.urdf`)."""
        from .writers import robot_to_urdf

        return robot_to_urdf(self)

    def __repr__(self) -> str:
        return f"Robot(name={self.name!r}, unit={self.unit!r})"

    # ------------------------------------------------------------------ kernels
    @cached_property
    def kernel_params(self) -> np.ndarray:
        """The flat parameter vector of :mod:`ik7r._kernels.params` (read-only)."""
        return L.pack(self)

    @property
    def position_tolerance(self) -> float:
        """Largest position residual a returned solution may have (robot length unit)."""
        return float(self.kernel_params[L.POS_TOL])

    @property
    def rotation_tolerance(self) -> float:
        """Largest rotation residual a returned solution may have (rad)."""
        return float(self.kernel_params[L.ROT_TOL])

    # ------------------------------------------------------------------ kinematics
    def fk(self, q: ArrayLike) -> np.ndarray:
        """Forward kinematics.

        Parameters
        ----------
        q : array_like, shape (..., 6)
            Independent joints ``[q1, q2, q3, q4, q5, q7]`` (rad); ``q6 = -q5`` is implied.

        Returns
        -------
        T_world_tool : ndarray, shape (..., 4, 4)
            Pose of the tool in the world frame (robot length unit).
        """
        q = check_joints(q)
        flat = np.ascontiguousarray(q.reshape(-1, 6))
        out = np.empty((flat.shape[0], 4, 4))
        _lazy("_kernels").fk_batch(flat, self.kernel_params, out)
        return out.reshape(q.shape[:-1] + (4, 4))

    def frames(self, q: ArrayLike) -> np.ndarray:
        """World frames of every link: ``(..., 9, 4, 4)``: frame 0 (base), frames 1..7, tool."""
        from .._kernels import frames_batch

        q = check_joints(q)
        flat = np.ascontiguousarray(q.reshape(-1, 6))
        out = np.empty((flat.shape[0], 9, 4, 4))
        frames_batch(flat, self.kernel_params, out)
        return out.reshape(q.shape[:-1] + (9, 4, 4))

    def jacobian(self, q: ArrayLike) -> np.ndarray:
        """Geometric Jacobian ``(..., 6, 6)`` of the tool in world coordinates (linear rows
        first, robot length unit per rad; then angular), joint 6 folded into column 5."""
        from .._kernels import jacobian as _jac

        q = check_joints(q)
        flat = np.ascontiguousarray(q.reshape(-1, 6))
        out = np.empty((flat.shape[0], 6, 6))
        J = np.empty((6, 6))
        for i in range(flat.shape[0]):  # small helper; not on a hot path
            _jac(flat[i], self.kernel_params, J)
            out[i] = J
        return out.reshape(q.shape[:-1] + (6, 6))

    # ------------------------------------------------------------------ configurations
    @staticmethod
    def indicators(q: ArrayLike) -> np.ndarray:
        """The paper's (Arm, Elbow, Wrist) indicators of joints ``q`` (..., 6) -> (..., 3) int.

        Arm = 1 when ``q1`` is in [-pi/2, pi/2), Elbow = 1 when ``q3`` is in [-pi/2, pi/2),
        Wrist = 1 when ``q5`` is in [0, pi) (angles taken modulo 2 pi).
        """
        from ..geometry.configs import indicators

        return indicators(check_joints(q))

    @staticmethod
    def config_of(q: ArrayLike) -> np.ndarray:
        """Configuration number 1..8 (the paper's Appendix 3) of joints ``q`` (..., 6)."""
        from ..geometry.configs import config_number

        return config_number(check_joints(q))

    # ------------------------------------------------------------------ inverse kinematics
    def ik_all(self, T: ArrayLike, *, within_limits: bool = False,
               seed: ArrayLike | None = None) -> np.ndarray:
        """Every distinct solution of one pose ``(M, 6)``; see :func:`ik7r.ik.solve.ik_all`."""
        return _lazy("ik.solve").ik_all(self, T, within_limits=within_limits, seed=seed)

    def ik(self, T: ArrayLike, config: Config = 1, seed: ArrayLike | None = None, *,
           within_limits: bool = False) -> np.ndarray:
        """The solution in one configuration ``(6,)``; see :func:`ik7r.ik.solve.ik`."""
        return _lazy("ik.solve").ik(self, T, config, seed=seed, within_limits=within_limits)

    def ik_batch(self, T: ArrayLike, config: Config = 1, seed: ArrayLike | None = None, *,
                 within_limits: bool = False) -> tuple[np.ndarray, np.ndarray]:
        """``(q (N, 6), ok (N,))`` for poses ``(N, 4, 4)``; see :func:`ik7r.ik.solve.ik_batch`."""
        return _lazy("ik.solve").ik_batch(self, T, config, seed=seed, within_limits=within_limits)

    def ik_all_batch(self, T: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """``(q (N, K, 6), valid (N, K))``; see :func:`ik7r.ik.solve.ik_all_batch`."""
        return _lazy("ik.solve").ik_all_batch(self, T)

    def ik_path(self, T: ArrayLike, config: Config = 1, *, seed: ArrayLike | None = None,
                within_limits: bool = False, max_step: float = 0.2, keep: str = "config",
                pose_at: PoseAt | None = None, u: ArrayLike | None = None,
                max_depth: int = 12, progress: bool = False) -> PathIK:  # 12: DEFAULT_MAX_DEPTH
        """Warm-started IK along a path ``(N, 4, 4)``, the one path follower (also the branch
        follower painting uses: ``keep``, ``pose_at``, ``u``); see :func:`ik7r.ik.path.ik_path`."""
        from ..ik.path import ik_path

        return ik_path(self, T, config, seed=seed, within_limits=within_limits, max_step=max_step,
                       keep=keep, pose_at=pose_at, u=u, max_depth=max_depth, progress=progress)

    def ik_paper(self, T: ArrayLike, config: Config = 1, theta5_start: float | None = None,
                 **kwargs: Any) -> PaperResult:
        """The paper's fixed-point iteration (Figure 5); see :func:`ik7r.ik.paper.ik_paper`."""
        from ..ik.paper import ik_paper

        return ik_paper(self, T, config, theta5_start=theta5_start, **kwargs)
