"""The compiled kernels: pure functions over arrays, compiled by numba (see :mod:`.jit`).

Everything outside this package reaches the kernels through the names below (imported lazily:
importing a kernel module imports numba). Every kernel reads the robot through one flat
``float64`` parameter vector ``K`` whose fields :mod:`.params` names and packs.

========== ===========================================================================
module     what it computes
========== ===========================================================================
params     the layout of ``K`` and its packing from a robot
fk         DH chain, forward kinematics, frames, Jacobian, pose error, Newton polish
arm        the arm (joints 1-3) for a virtual wrist centre
wrist      the wrist (joints 4, 5, 7) and the theta5 <-> d map
poly       the residual polynomial, its certified root isolation, the Bernstein tables
complete   every solution of one pose: ``solve_into``, over the solver's stages
constants  the solver's tolerances, windows and grids; the layout of its work array
singular   where a pose lies relative to the singular sets (the solver's predicates)
answers    what is exact and what is one solution: accept, add, the output's passes
joints     a candidate's six joints from the arm's angles and the wrist
reduced    the exact model's reduced residual and its scans (deviating models)
candidates each arm branch at a root of the residual, its wrists, verified
gaps       the bend, shoulder and fold gaps the scans search
scans      the scans beside the polynomial: undecided brackets, shoulder set, fold
select     indicators, joint limits, nearest to a seed; fused single and batch calls
track      warm-started paths
film       paint film thickness per mesh vertex over gun poses (with occlusion)
validate   pose validation inside the compiled batch loops
bernstein  the Bernstein tables of the root isolation (plain numpy)
jit        the one place that knows numba
aot        the entry points compiled ahead of time into an extension module
========== ===========================================================================

The entry points named in :data:`.aot.SIGNATURES` come from the compiled extension module when
it is built and matches the sources (then numba is not imported), else from numba's JIT.
"""

from __future__ import annotations

import importlib
import sys

from .._lazy import lazy_exports

_MODULES = ("params",)
_EXPORTS = {
    "JIT_ENABLED": "jit",
    "fk_batch": "fk", "fk_user": "fk", "frames_batch": "fk", "jacobian": "fk", "chain": "fk",
    "residual": "fk", "user_angle": "fk", "pose_error": "fk", "solve6": "fk",
    "arm_ik": "arm",
    "d_of_theta5": "wrist", "theta5_of_cos_bend": "wrist", "wrist_ik": "wrist", "wrist_target": "wrist",
    "bernstein_tables": "bernstein",
    "frame07": "complete",
    "all_rows": "select", "config_rows": "select", "ik_all_one": "select", "ik_one": "select",
    "matches": "select",
    "count_within_limits": "select", "expand_within_limits": "select",
    "track_path": "track",
    "film_kernel": "film",
    "validate_pose": "validate", "validate_poses": "validate",
}

_jit_getattr, __dir__ = lazy_exports(__name__, _EXPORTS, _MODULES)


def __getattr__(name: str):
    aot = importlib.import_module(f"{__name__}.aot")  # (not "from . import": that asks __getattr__)
    if name in aot.SIGNATURES:
        compiled = aot.load()
        if compiled is not None:
            value = getattr(compiled, name)
            setattr(sys.modules[__name__], name, value)  # found directly from now on
            return value
    return _jit_getattr(name)

__all__ = [
    "bernstein_tables",
    "film_kernel",
    "JIT_ENABLED",
    "all_rows",
    "arm_ik",
    "chain",
    "config_rows",
    "count_within_limits",
    "d_of_theta5",
    "expand_within_limits",
    "fk_batch",
    "fk_user",
    "frame07",
    "frames_batch",
    "ik_all_one",
    "ik_one",
    "matches",
    "jacobian",
    "pose_error",
    "residual",
    "solve6",
    "theta5_of_cos_bend",
    "track_path",
    "user_angle",
    "validate_pose",
    "validate_poses",
    "wrist_ik",
    "wrist_target",
    "params",
]
