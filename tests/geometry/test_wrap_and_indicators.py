"""The one angle wrap and the one indicator rule, in every form they run in.

``ik7r.geometry.rotations.wrap`` and ``ik7r.geometry.configs.arm_elbow_wrist`` / ``number_of``
are written once and run three ways: numpy code calls them on arrays, the compiled kernels on
scalars (numba compiles the same functions), and the kernels in pure-Python mode
(``IK7R_JIT=0``) call them on Python floats. Each form is held against references written here
from the documented definitions alone: exact rational arithmetic (``fractions.Fraction``) for
the wrap, the paper's ranges and Appendix 3's table for the indicators.
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ik7r._kernels import JIT_ENABLED
from ik7r._kernels import constants as _constants
from ik7r._kernels import select as _select
from ik7r.geometry import config_number, indicators, wrap_angle
from ik7r.geometry.configs import arm_elbow_wrist, number_of
from ik7r.geometry.rotations import remainder_2pi, wrap

FLOAT_2PI = 2.0 * math.pi  # the float 2 pi the documented wrap reduces by
# 2 pi to 40 digits, for the distance to the true angle
TWO_PI_40 = Fraction("6.283185307179586476925286766559005768394")


def reference_wrap(x: float) -> float:
    """The documented wrap, from its definition: beyond 64 turns ``x`` less whole multiples of
    64 float 2 pi (toward zero, exactly); ``s = x + pi`` (one float addition); its remainder
    modulo the float 2 pi in (0, 2 pi] taken exactly (rationals) and rounded once to a float;
    minus pi (one float subtraction)."""
    if not math.isfinite(x):
        return math.nan
    period = Fraction(FLOAT_2PI)
    if abs(x) >= 64 * period:
        big = 64 * period
        x = float(Fraction(x) - math.trunc(Fraction(x) / big) * big)  # exact: a float remainder
    s = x + math.pi
    r = Fraction(s) - math.floor(Fraction(s) / period) * period  # in [0, 2 pi), exact
    if r == 0:
        r = period
    return float(r) - math.pi  # float(Fraction) rounds to nearest, ties to even


def reference_remainder(x: float) -> float:
    """``x`` minus the nearest multiple of the float 2 pi (ties to even), exactly (rationals)."""
    if not math.isfinite(x):
        return math.nan
    period = Fraction(FLOAT_2PI)
    r = Fraction(x) - round(Fraction(x) / period) * period
    assert Fraction(float(r)) == r
    return float(r)


def _ulps(x: float, n: int) -> float:
    for _ in range(abs(n)):
        x = math.nextafter(x, math.inf if n > 0 else -math.inf)
    return x


_SPECIAL = [0.0, -0.0, 5e-324, -5e-324, 1e-300, -1e-300, 1e300, -1e300, 1.7976931348623157e308,
            -1.7976931348623157e308, 5e18, 9.3e18, 4.2e8, -4.2e8, 2.0 ** 53, math.inf, -math.inf, math.nan]
_SPECIAL += [_ulps(c, n) for c in (math.pi, -math.pi, math.pi / 2, -math.pi / 2, 3 * math.pi)
             for n in range(-3, 4)]
_TURNS = (1, 2, 3, 9, 17, -5, -9, 2 ** 20 + 1, 2 ** 26, -2 ** 26 - 3)
_SPECIAL += [_ulps(k * FLOAT_2PI + off, n) for k in _TURNS
             for off in (0.0, math.pi, -math.pi) for n in (-2, -1, 0, 1, 2)]

#: hostile floats: anything (huge, tiny, subnormal, NaN, inf) and the hand-picked edges
hostile = st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.sampled_from(_SPECIAL),
                    st.integers(-2 ** 40, 2 ** 40).map(lambda k: k * FLOAT_2PI),
                    st.floats(-1e3, 1e3))


def _bits(x) -> int:
    return int(np.float64(x).view(np.int64))


def _same(a: float, b: float) -> bool:
    """The same float bit for bit (any NaN is the same NaN)."""
    return (math.isnan(a) and math.isnan(b)) or _bits(a) == _bits(b)


if JIT_ENABLED:
    import numba

    @numba.njit(cache=False)
    def _compiled_wrap(x):  # the kernels' form: wrap compiled into a numba function, on a scalar
        return _constants.wrap(x)

    @numba.njit(cache=False)
    def _compiled_remainder(x):
        return _constants.remainder_2pi(x)

    @numba.njit(cache=False)
    def _compiled_rule(q1, q3, q5):
        a, e, w = _select.arm_elbow_wrist(q1, q3, q5)
        return a, e, w, _select.number_of(a, e, w)
else:  # pragma: no cover - pure-Python kernels: the functions as they are
    _compiled_wrap = _constants.wrap
    _compiled_remainder = _constants.remainder_2pi

    def _compiled_rule(q1, q3, q5):
        a, e, w = _select.arm_elbow_wrist(q1, q3, q5)
        return a, e, w, _select.number_of(a, e, w)


def test_the_kernels_use_the_one_wrap_and_rule():
    assert _constants.wrap is wrap and _select.wrap is wrap and _constants.remainder_2pi is remainder_2pi
    assert _select.arm_elbow_wrist is arm_elbow_wrist and _select.number_of is number_of


@settings(max_examples=400, deadline=None)
@given(st.lists(hostile, min_size=1, max_size=8))
def test_wrap_is_the_documented_remainder_in_every_form(xs):
    want = [reference_wrap(x) for x in xs]
    with np.errstate(invalid="ignore"):
        arrays = wrap_angle(np.array(xs))              # numpy code, on an array
        scalars = [float(wrap_angle(x)) for x in xs]   # numpy code, one by one
        plain = [float(wrap(x)) for x in xs]           # the pure-Python kernels' call
    compiled = [float(_compiled_wrap(x)) for x in xs]  # the compiled kernels' call
    for x, w, a, s, p, c in zip(xs, want, arrays, scalars, plain, compiled):
        assert all(_same(v, w) for v in (a, s, p, c)), (x, w, a, s, p, c)
        if math.isfinite(x):
            assert -math.pi < w <= math.pi


@settings(max_examples=400, deadline=None)
@given(st.lists(hostile, min_size=1, max_size=8))
def test_remainder_is_exact_in_every_form(xs):
    """The reduction under the wrap and the indicators: no rounding at all (pi may come as -pi)."""
    with np.errstate(invalid="ignore"):
        arrays = remainder_2pi(np.array(xs))
        plain = [float(remainder_2pi(x)) for x in xs]
    for x, a, p in zip(xs, arrays, plain):
        want, c = reference_remainder(x), float(_compiled_remainder(x))
        assert _same(a, p) and _same(p, c), (x, a, p, c)
        assert _same(p, want) or (abs(p) == abs(want) == math.pi), (x, p, want)
        if math.isfinite(x):
            assert abs(p) <= math.pi
            assert math.remainder(x, FLOAT_2PI) == p or abs(p) == math.pi  # (== : -0.0 is 0.0)


@settings(max_examples=200, deadline=None)
@given(st.floats(-1e3, 1e3))
def test_wrap_is_within_rounding_of_the_true_angle(x):
    """Against 2 pi to 40 digits: off by the roundings of x + pi and - pi and the float 2 pi's
    drift (2.4e-16 rad a turn), modulo 2 pi (at the cut, -pi and pi are the same angle)."""
    w = wrap(x)
    turns = (Fraction(x) - Fraction(w)) / TWO_PI_40
    off = abs(turns - round(turns)) * TWO_PI_40
    assert off <= 2 * math.ulp(abs(x) + math.pi) + 2.5e-16 * (abs(x) / 6 + 1)


@settings(max_examples=300, deadline=None)
@given(hostile)
def test_wrap_is_the_angle_of_x(x):
    """Congruent to ``x`` modulo the float 2 pi within 3e-14 rad, however large ``x`` is (with
    ``numpy.mod(x + pi, 2 pi) - pi``, beyond 1e16 rad the pi added is lost: off by pi)."""
    if math.isfinite(x):
        d = math.remainder(float(wrap(x)) - reference_remainder(x), FLOAT_2PI)
        assert abs(d) <= 3e-14, (x, d)


def test_wrap_of_angles_below_64_turns_as_numpy_mod_gives_it():
    rng = np.random.default_rng(7)
    x = np.concatenate([rng.uniform(-7, 7, 20000), rng.uniform(-401, 401, 20000)])
    old = np.mod(x + np.pi, 2 * np.pi)
    old = np.where(old <= 0.0, old + 2 * np.pi, old) - np.pi  # the wrap as numpy code wrote it
    assert np.array_equal(wrap_angle(x).view(np.int64), old.view(np.int64))


# ---------------------------------------------------------------------------- indicators

#: the paper's Appendix 3: configuration -> (Arm, Elbow, Wrist)
APPENDIX3 = {1: (1, 1, 1), 2: (1, 1, 0), 3: (1, 0, 1), 4: (1, 0, 0),
             5: (0, 1, 1), 6: (0, 1, 0), 7: (0, 0, 1), 8: (0, 0, 0)}


def reference_indicators(q1: float, q3: float, q5: float) -> tuple[int, int, int]:
    """Section 3's ranges on the angles modulo 2 pi (exact): Arm when q1 in [-pi/2, pi/2), Elbow
    when q3 in [-pi/2, pi/2), Wrist when q5 in [0, pi); pi and -pi are one angle."""
    a, e, w = reference_remainder(q1), reference_remainder(q3), reference_remainder(q5)
    return int(-math.pi / 2 <= a < math.pi / 2), int(-math.pi / 2 <= e < math.pi / 2), int(0.0 <= w < math.pi)


def test_number_of_is_appendix_3():
    for number, triple in APPENDIX3.items():
        assert number_of(*triple) == number
        assert number_of(*(bool(v) for v in triple)) == number


@settings(max_examples=300, deadline=None)
@given(st.lists(st.tuples(hostile, hostile, hostile), min_size=1, max_size=6))
def test_indicators_in_every_form(rows):
    want = [reference_indicators(*r) for r in rows]
    q = np.zeros((len(rows), 6))
    q[:, [0, 2, 4]] = rows
    with np.errstate(invalid="ignore"):
        ind = indicators(q)                 # numpy code, on arrays
        num = config_number(q)
        plain = [tuple(int(v) for v in arm_elbow_wrist(*r)) for r in rows]   # pure-Python kernels
    for i, r in enumerate(rows):
        compiled = _compiled_rule(*r)       # compiled kernels
        kernel_number = _select.config_number(q[i])
        assert tuple(ind[i]) == want[i] == plain[i] == tuple(int(v) for v in compiled[:3]), r
        assert num[i] == compiled[3] == kernel_number == {v: k for k, v in APPENDIX3.items()}[want[i]], r


@settings(max_examples=300, deadline=None)
@given(st.tuples(hostile, hostile, hostile))
def test_matches_keeps_its_boundary_rule_on_top_of_the_one_rule(r):
    """``matches`` says yes to a solution's own indicators always, and to another triple only on
    a boundary: q1 or q3 within BOUNDARY_TOL of +-pi/2, a straight wrist (within SINGULAR_WRIST of
    0) or a fully bent one (within FOLDED_WRIST of pi)."""
    if not all(math.isfinite(v) for v in r):
        return
    q = np.zeros(6)
    q[[0, 2, 4]] = r
    own = reference_indicators(*r)
    a, e, w = (reference_wrap(v) for v in r)
    tol, singular, folded = _select.BOUNDARY_TOL, _select.SINGULAR_WRIST, _select.FOLDED_WRIST
    free = (abs(abs(a) - math.pi / 2) <= tol, abs(abs(e) - math.pi / 2) <= tol,
            abs(w) < singular or math.pi - abs(w) < folded)
    for triple in APPENDIX3.values():
        expected = all(t == o or f for t, o, f in zip(triple, own, free))
        assert bool(_select.matches(q, *triple)) == expected, (r, triple)


PURE = r"""
import json, sys
import numpy as np
from ik7r._kernels import JIT_ENABLED, constants, select
assert not JIT_ENABLED and "numba" not in sys.modules
xs = json.loads(sys.argv[1])
out = []
for x in xs:
    q = np.array([x, 0.0, x / 3, 0.0, -x, 0.0])
    seed = np.empty(6)
    select.reduced_seed(np.full(6, x), seed)
    out.append([float(constants.wrap(x)).hex(), float(seed[0]).hex(), int(select.config_number(q)),
                bool(select.matches(q, 1, 0, 1))])
print(json.dumps(out))
"""


def test_pure_python_kernels_give_the_compiled_bits():
    """``IK7R_JIT=0`` (numba not imported): the kernels' wrap, seed reduction, configuration
    number and boundary rule give what the compiled kernels give, bit for bit."""
    xs = [x for x in _SPECIAL if math.isfinite(x)] + list(np.random.default_rng(3).uniform(-400, 400, 40))
    env = dict(os.environ, IK7R_JIT="0")
    p = subprocess.run([sys.executable, "-c", PURE, json.dumps(xs)], capture_output=True, text=True,
                       env=env, timeout=300)
    assert p.returncode == 0, p.stderr
    pure = json.loads(p.stdout.strip().splitlines()[-1])
    for x, (w, s, number, m) in zip(xs, pure):
        q = np.array([x, 0.0, x / 3, 0.0, -x, 0.0])
        seed = np.empty(6)
        _select.reduced_seed(np.full(6, x), seed)
        assert float.fromhex(w) == reference_wrap(x) and _same(float.fromhex(w), _compiled_wrap(x)), x
        assert _same(float.fromhex(s), seed[0]), x
        assert number == _select.config_number(q) == int(config_number(q)), x
        assert m == bool(_select.matches(q, 1, 0, 1)), x


@pytest.mark.parametrize("x", [math.pi, -math.pi, 1e300, -1e300, 5e18])
def test_seed_reduction_is_the_one_wrap(x):
    """Seeds beyond MAX_JOINT_ANGLE are reduced by the one wrap, in Python and in the kernels."""
    from ik7r.geometry import reduce_seeds
    from ik7r.robot.family import MAX_JOINT_ANGLE

    s = np.full(6, x)
    out = np.empty(6)
    _select.reduced_seed(s, out)
    want = reference_wrap(x) if abs(x) > MAX_JOINT_ANGLE else x
    assert _same(out[0], want) and _same(reduce_seeds(s)[0], want)
