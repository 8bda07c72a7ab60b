"""Layout of the flat parameter vector the compiled kernels read.

A :class:`~ik7r.robot.model.Robot` is immutable; its kernels receive one ``float64`` vector
(built once per robot by :func:`ik7r.robot.model.Robot.kernel_params`) so that every kernel has
the same short signature. The offsets below name the fields of that vector.
"""

from __future__ import annotations

import math

import numpy as np

from ..geometry.rotations import invert
from ..robot.family import ROTATION_TOLERANCE

# exact model (used by forward kinematics, the Jacobian and polishing)
DH = 0  # 7 rows x (a_{i-1}, alpha_{i-1}, d_i, theta_offset_i), row-major
SIGN = 28  # 7 joint signs: theta_dh_i = sign_i * q_i + theta_offset_i
MIMIC = 35  # q6 = MIMIC[0] * q5 + MIMIC[1]
BASE = 37  # 4x4 world <- frame 0
BASE_INV = 53
TOOL = 69  # 4x4 frame 7 <- tool
TOOL_INV = 85

# fields of the DH block the kernels read by name (row i-1 of joint i: DH + 4 (i - 1) + column)
THETA_OFFSET1 = DH + 3  # theta_offset of joint 1
THETA_OFFSET4 = DH + 15
THETA_OFFSET6 = DH + 23
THETA_OFFSET7 = DH + 27

# nominal family parameters (used by the virtual-wrist solvers)
NOM = 101
A1 = NOM + 0  # shoulder offset a1
A2 = NOM + 1  # upper arm a2
A3 = NOM + 2  # elbow offset a3
B = NOM + 3  # lateral offset d2 + d3
D1 = NOM + 4  # base height d1
D4 = NOM + 5  # forearm d4
EPS1 = NOM + 6  # sign of alpha1 (+-90 deg)
EPS3 = NOM + 7  # sign of alpha3 (+-90 deg)
BETA = NOM + 8  # wrist half twist: alphas (-beta, 2 beta, -beta)
DW = NOM + 9  # wrist offsets d5 = d6
D7 = NOM + 10  # flange offset d7
KW = NOM + 11  # dw * cos(beta): the virtual offset d at theta5 = 0
DMIN = NOM + 12  # search interval for d
DMAX = NOM + 13
SB = NOM + 14  # sin(beta)
DEVIATION = NOM + 15  # largest difference between the nominal and the exact DH table
PRODUCT = NOM + 16  # 1.0 when the residual needs both shoulder branches (offsets)
SCALE = NOM + 17  # characteristic length (for relative tolerances)
POS_TOL = NOM + 18  # accepted position residual, robot length unit
ROT_TOL = NOM + 19  # accepted rotation residual, rad
NCHEB = NOM + 20  # degree of the residual polynomial (8 or 16)
DEVIATION_EFFECT = NOM + 21  # how far the deviation moves a pose at most, in tolerances
WRIST_EFFECT = NOM + 22  # the wrist's share of it: 0 where the straight wrist is a circle

LIMITS = NOM + 24  # lower (6) then upper (6), rad, independent joints
NDH = LIMITS + 12  # the nominal (idealised) DH table, same layout as DH
TRIG = NDH + 28  # cos, sin of each alpha_{i-1}: 7 pairs for DH, then 7 pairs for NDH
NOMINAL_TRIG = TRIG + 14  # the nominal table's 7 pairs
OFFSET_TRIG = TRIG + 28  # cos, sin of each theta_offset_i of the DH table: 7 pairs
BASE_SIZE = OFFSET_TRIG + 14

# models between the nominal and the exact one (a homotopy for polishing deviating models):
# HOMOTOPY_STEPS full parameter vectors of BASE_SIZE follow, the k-th with the DH table
# nominal + t_k (exact - nominal), t_k = (k + 1) / (HOMOTOPY_STEPS + 1)
HOMOTOPY = BASE_SIZE
HOMOTOPY_STEPS = 3
SIZE = BASE_SIZE * (1 + HOMOTOPY_STEPS)

# most solutions one pose can have with this formulation (see ik7r._kernels.complete)
MAX_SOLUTIONS = 32


def pack(robot) -> np.ndarray:
    """The parameter vector ``K`` of ``robot`` (read-only ``float64``, ``SIZE`` long)."""
    f = robot.family
    dh = f.dh  # the table in the solvers' frames (the same robot: ik7r.robot.family.frame_dh)
    K = np.zeros(BASE_SIZE)
    K[DH:DH + 28] = dh.reshape(-1)
    K[SIGN:SIGN + 7] = robot.joint_sign
    K[MIMIC:MIMIC + 2] = robot.coupling[0], f.coupling_offset
    K[BASE:BASE + 16] = robot.base.reshape(-1)
    K[BASE_INV:BASE_INV + 16] = invert(robot.base).reshape(-1)
    K[TOOL:TOOL + 16] = robot.tool.reshape(-1)
    K[TOOL_INV:TOOL_INV + 16] = invert(robot.tool).reshape(-1)
    K[A1], K[A2], K[A3], K[B] = f.a1, f.a2, f.a3, f.b
    K[D1], K[D4], K[EPS1], K[EPS3] = f.d1, f.d4, f.eps1, f.eps3
    K[BETA], K[DW], K[D7], K[KW] = f.beta, f.dw, f.d7, f.kw
    K[DMIN], K[DMAX] = f.d_range
    K[SB] = math.sin(f.beta)
    K[DEVIATION] = f.deviation
    K[PRODUCT] = 0.0 if f.zero_offsets else 1.0
    K[SCALE] = f.scale
    K[POS_TOL] = f.position_tolerance
    K[ROT_TOL] = ROTATION_TOLERANCE
    K[NCHEB] = 8 if f.zero_offsets else 16
    K[DEVIATION_EFFECT] = f.deviation_effect
    K[WRIST_EFFECT] = f.wrist_effect
    K[LIMITS:LIMITS + 6] = robot.lower
    K[LIMITS + 6:LIMITS + 12] = robot.upper
    K[NDH:NDH + 28] = f.nominal_dh.reshape(-1)
    for t, table in enumerate((dh, f.nominal_dh)):  # cos, sin of every twist
        K[TRIG + 14 * t:TRIG + 14 * (t + 1):2] = np.cos(table[:, 1])
        K[TRIG + 14 * t + 1:TRIG + 14 * (t + 1):2] = np.sin(table[:, 1])
    K[OFFSET_TRIG:OFFSET_TRIG + 14:2] = np.cos(dh[:, 3])
    K[OFFSET_TRIG + 1:OFFSET_TRIG + 14:2] = np.sin(dh[:, 3])
    steps = []
    for k in range(HOMOTOPY_STEPS):  # models on the way from the nominal to the exact one
        t = (k + 1) / (HOMOTOPY_STEPS + 1)
        Kt = K.copy()
        dh_t = f.nominal_dh + t * (dh - f.nominal_dh)
        Kt[DH:DH + 28] = dh_t.reshape(-1)
        Kt[TRIG:TRIG + 14:2] = np.cos(dh_t[:, 1])
        Kt[TRIG + 1:TRIG + 14:2] = np.sin(dh_t[:, 1])
        Kt[OFFSET_TRIG:OFFSET_TRIG + 14:2] = np.cos(dh_t[:, 3])
        Kt[OFFSET_TRIG + 1:OFFSET_TRIG + 14:2] = np.sin(dh_t[:, 3])
        steps.append(Kt)
    K = np.concatenate([K, *steps])
    K.setflags(write=False)
    return K
