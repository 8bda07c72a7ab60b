"""Round trips and hostile input (hypothesis): gun files, parts, gun poses."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ik7r.errors import GunFileError
from ik7r.painting.film import poses_from_samples
from ik7r.painting.parts import Part
from ik7r.painting.spray import MODELS, Gun, gun_from_toml, gun_to_toml

pos = st.floats(min_value=1e-3, max_value=1e4, allow_nan=False)
expo = st.floats(min_value=1.0 + 1e-6, max_value=20.0, allow_nan=False)


@st.composite
def guns(draw):
    model = draw(st.sampled_from(list(MODELS)))
    params = {k: draw(expo if k.startswith("beta") else pos) for k in MODELS[model]}
    return Gun(model, draw(pos), draw(pos), params, draw(st.sampled_from(["mm", "m", "cm", "in"])),
               draw(st.text(alphabet="abcdefgh -_", min_size=1, max_size=12)))


@settings(max_examples=60, deadline=None)
@given(guns())
def test_gun_toml_round_trip(gun):
    assert gun_from_toml(gun_to_toml(gun)) == gun
    back = gun.in_unit("mm").in_unit(gun.unit)
    assert back.standoff == pytest.approx(gun.standoff, rel=1e-12)


@settings(max_examples=60, deadline=None)
@given(st.sampled_from(["standoff", "peak_rate", "sigma"]),
       st.one_of(st.floats(max_value=0.0), st.just(math.nan), st.just(math.inf), st.text(max_size=5)))
def test_bad_gun_values_are_refused(key, value):
    fields = {"model": '"gaussian"', "standoff": "200", "peak_rate": "100", "sigma": "30"}
    fields[key] = repr(value) if isinstance(value, str) else ("nan" if math.isnan(value) else
                                                               "inf" if math.isinf(value) else repr(value))
    text = "\n".join(f"{k} = {v}" for k, v in fields.items())
    with pytest.raises(GunFileError, match="hostile.toml"):
        gun_from_toml(text, source="hostile.toml")


@settings(max_examples=40, deadline=None)
@given(st.integers(min_value=0, max_value=5), st.sampled_from([math.nan, math.inf, -math.inf]))
def test_parts_refuse_non_finite_vertices(i, bad):
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [2, 0, 0], [2, 1, 0]], dtype=float)
    V[i, i % 3] = bad
    with pytest.raises(ValueError, match="finite"):
        Part(V, np.array([[0, 1, 2], [1, 3, 2]]), np.eye(4))


def test_parts_refuse_bad_faces():
    V = np.eye(3)
    bad = (np.array([[0, 1, 3]]), np.array([[0, 1]]), np.zeros((0, 3), dtype=int), np.array([[0.0, 1, 2]]))
    for F in bad:
        with pytest.raises(ValueError, match="face"):
            Part(V, F, np.eye(4))


def test_gun_poses_are_validated():
    T = np.stack([np.eye(4)] * 3)
    with pytest.raises(ValueError, match="increasing"):
        poses_from_samples([0.0, 1.0, 1.0], T)
    with pytest.raises(ValueError, match="shape"):
        poses_from_samples([0.0, 1.0, 2.0], T, [True])
    with pytest.raises(ValueError):
        poses_from_samples([0.0, 1.0], T)
