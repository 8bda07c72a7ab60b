"""The robot: the immutable model, the family it belongs to, robot files (TOML) and URDF.

============ ===================================================================
module       what it holds
============ ===================================================================
model        :class:`Robot`, the frozen dataclass every solver takes
family       what the 7R coupled-wrist family is; its nominal (idealised) parameters
files        TOML robot files, the built-in robots (``data/``), unit conversion
urdf         URDF import (``<mimic>`` joints)
writers      TOML and URDF export (``Robot.to_toml``, ``Robot.to_urdf``)
============ ===================================================================
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from .._lazy import lazy_exports

_EXPORTS = {
    "Robot": "model",
    "load_robot": "files",
    "robot_from_toml": "files",
    "robot_to_toml": "writers",
    "robot_in_unit": "files",
    "BUILTIN_ROBOTS": "files",
    "robot_from_urdf": "urdf",
    "robot_from_urdf_string": "urdf",
    "robot_to_urdf": "writers",
    "UrdfChain": "urdf",
    "read_chain": "urdf",
    "PARALLEL_TOL": "urdf",
    "FK_CHECK_TOL": "urdf",
    "family_of": "family",
    "Family": "family",
    "ANGLE_TOL": "family",
    "LENGTH_TOL": "family",
    "MAX_BETA": "family",
    "MIN_SIZE": "family",
    "MIN_RELATIVE_TOLERANCE": "family",
    "MIN_LINK_RATIO": "family",
    "MAX_ANGLE_PARAMETER": "family",
    "MAX_JOINT_ANGLE": "family",
    "frame_dh": "family",
    "DEFAULT_JOINT_NAMES": "model",
}

if TYPE_CHECKING:  # the names, for type checkers and IDEs
    from .family import (
        ANGLE_TOL,
        LENGTH_TOL,
        MAX_ANGLE_PARAMETER,
        MAX_BETA,
        MAX_JOINT_ANGLE,
        MIN_LINK_RATIO,
        MIN_RELATIVE_TOLERANCE,
        MIN_SIZE,
        Family,
        family_of,
        frame_dh,
    )
    from .files import BUILTIN_ROBOTS, load_robot, robot_from_toml, robot_in_unit
    from .model import DEFAULT_JOINT_NAMES, Robot
    from .urdf import (
        FK_CHECK_TOL,
        PARALLEL_TOL,
        UrdfChain,
        read_chain,
        robot_from_urdf,
        robot_from_urdf_string,
    )
    from .writers import robot_to_toml, robot_to_urdf

__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, ('model', 'family', 'files', 'urdf', 'writers'))
__all__ = [
    "ANGLE_TOL",
    "BUILTIN_ROBOTS",
    "DEFAULT_JOINT_NAMES",
    "FK_CHECK_TOL",
    "Family",
    "LENGTH_TOL",
    "MAX_ANGLE_PARAMETER",
    "MAX_BETA",
    "MAX_JOINT_ANGLE",
    "MIN_LINK_RATIO",
    "MIN_RELATIVE_TOLERANCE",
    "MIN_SIZE",
    "PARALLEL_TOL",
    "Robot",
    "UrdfChain",
    "family_of",
    "frame_dh",
    "load_robot",
    "read_chain",
    "robot_from_toml",
    "robot_from_urdf",
    "robot_from_urdf_string",
    "robot_in_unit",
    "robot_to_toml",
    "robot_to_urdf",
]
