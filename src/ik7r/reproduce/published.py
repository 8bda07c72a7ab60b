"""The paper's published numbers, as printed (OCR slips corrected, see docs/method.md).

Everything here is data copied from the paper; nothing is computed. Angles in degrees,
lengths in mm, times in the units the paper uses (ms for Table 3, s for Table 5).
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "PAPER_PLATFORM",
    "PAPER_TABLE2",
    "PAPER_TABLE3",
    "PAPER_TABLE5",
    "PAPER_TRAJECTORY_TIME_S",
    "SIMULATION1_Q_DEG",
    "EQ11_Q_DEG",
    "SINGULAR_Q_DEG",
    "TABLE3_STARTS_DEG",
    "FIGURE6_ARMS",
]

#: The computer of the paper's timings.
PAPER_PLATFORM = "Pentium i7 2.8 GHz, 8 GB RAM, MATLAB"

#: Simulation 1's target joints ``[q1, q2, q3, q4, q5, q7]`` (deg).
SIMULATION1_Q_DEG = np.array([60.0, 60.0, 0.0, -30.0, 60.0, 30.0])

#: Table 2 as printed, rows = configurations 1..8, columns ``[q1, q2, q3, q4, q5, q7]`` (deg).
#: The OCR slips ``-I5.4359`` and ``- I 77.6485`` are -15.4359 and -177.6485; q2 = 207.5107 of
#: configurations 5 and 6 is printed outside (-180, 180] (it equals -152.4893 modulo 360).
PAPER_TABLE2 = np.array([
    [60.0000, 60.0000, 0.0000, -30.0000, 60.0000, 30.0000],
    [60.0000, 60.0000, 0.0000, -159.3775, -60.0000, 159.3775],
    [60.0360, -27.5107, 178.4662, -178.6218, 21.6300, -177.6485],
    [60.0360, -27.5107, 178.4662, 19.1657, -21.6300, -15.4359],
    [-119.9640, 207.5107, 1.5338, 1.3782, 21.6300, -177.6485],
    [-119.9640, 207.5107, 1.5338, -160.8343, -21.6300, -15.4359],
    [-120.0000, 120.0000, 180.0000, 150.0000, 60.0000, 30.0000],
    [-120.0000, 120.0000, 180.0000, 20.6225, -60.0000, 159.3775],
])

#: Table 3's Newton-Raphson initial values (deg).
TABLE3_STARTS_DEG = (
    (60.0, 60.0, 0.0, -30.0, 30.0, 30.0),
    (0.0, 60.0, 0.0, -30.0, 30.0, 30.0),
    (0.0, 60.0, 0.0, -30.0, 0.0, 30.0),
)

#: Table 3: computation time (ms) of the paper's method (random start) and of Newton-Raphson
#: from the three initial values; None is the printed "Failure".
PAPER_TABLE3 = {
    "paper": 65.0,
    TABLE3_STARTS_DEG[0]: 63.0,
    TABLE3_STARTS_DEG[1]: 104.0,
    TABLE3_STARTS_DEG[2]: None,
}

#: Simulation 2's singular targets (deg), theta_a1 and theta_a2.
SINGULAR_Q_DEG = (
    np.array([60.0, -30.0, 60.0, -30.0, 0.0, 30.0]),
    np.array([60.0, -30.0, 60.0, -30.0, 180.0, 30.0]),
)

#: Table 5: (average position error mm, maximum position error mm, average time s).
PAPER_TABLE5 = {
    "Randomly selected": (0.003, 0.01, 0.061),
    "Singular configuration 1": (0.009, 0.009, 0.043),
    "Singular configuration 2": (0.004, 0.004, 0.069),
}

#: Simulation 3: average time per trajectory point (s).
PAPER_TRAJECTORY_TIME_S = 0.009

#: Eq. (11)'s target: the independent joints (deg); the paper lists theta6 = -60 too.
EQ11_Q_DEG = np.array([30.0, 60.0, -60.0, -30.0, 60.0, 30.0])

#: Eq. (11) as printed (4, 4), mm.
EQ11_T = np.array([
    [0.371157, 0.540588, 0.754988, 567.728363],
    [0.157481, -0.837933, 0.522559, 343.242487],
    [0.915118, -0.075056, -0.396137, -183.093234],
    [0.0, 0.0, 0.0, 1.0],
])

#: Figure 6's panels: (label, Arm, Elbow) of the four arm configurations.
FIGURE6_ARMS = (("A", 1, 1), ("B", 1, 0), ("C", 0, 1), ("D", 0, 0))
