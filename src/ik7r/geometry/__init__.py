"""Geometry at the boundary: rotations and transforms, the Arm/Elbow/Wrist indicators, and the
``check_*`` validation every public function calls first (naming the shape expected and got).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from .._lazy import lazy_exports

_EXPORTS = {
    "rot_x": "rotations",
    "rot_z": "rotations",
    "dh_transform": "rotations",
    "rpy_to_matrix": "rotations",
    "matrix_to_rpy": "rotations",
    "quat_to_matrix": "rotations",
    "matrix_to_quat": "rotations",
    "transform": "rotations",
    "invert": "rotations",
    "wrap_angle": "rotations",
    "nearest_rotation": "rotations",
    "relative_rotvec": "rotations",
    "indicators": "configs",
    "config_number": "configs",
    "config_of_indicators": "configs",
    "describe_config": "configs",
    "ORTHONORMAL_TOL": "checks",
    "check_joints": "checks",
    "check_transforms": "checks",
    "check_config": "checks",
    "check_finite": "checks",
    "transforms_status": "checks",
    "poses_status": "checks",
    "reduce_seeds": "checks",
    "project_transforms": "checks",
}

if TYPE_CHECKING:  # the names, for type checkers and IDEs
    from .checks import (
        ORTHONORMAL_TOL,
        check_config,
        check_finite,
        check_joints,
        check_transforms,
        poses_status,
        project_transforms,
        reduce_seeds,
        transforms_status,
    )
    from .configs import config_number, config_of_indicators, describe_config, indicators
    from .rotations import (
        dh_transform,
        invert,
        matrix_to_quat,
        matrix_to_rpy,
        nearest_rotation,
        quat_to_matrix,
        relative_rotvec,
        rot_x,
        rot_z,
        rpy_to_matrix,
        transform,
        wrap_angle,
    )

__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, ('rotations', 'configs', 'checks'))
__all__ = [
    "ORTHONORMAL_TOL",
    "check_config",
    "check_finite",
    "check_joints",
    "check_transforms",
    "config_number",
    "config_of_indicators",
    "describe_config",
    "dh_transform",
    "indicators",
    "invert",
    "matrix_to_quat",
    "matrix_to_rpy",
    "nearest_rotation",
    "relative_rotvec",
    "reduce_seeds",
    "poses_status",
    "project_transforms",
    "quat_to_matrix",
    "rot_x",
    "rot_z",
    "rpy_to_matrix",
    "transform",
    "transforms_status",
    "wrap_angle",
]
