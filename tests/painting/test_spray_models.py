"""Gun models, files, the projection formula and stripe calibration, against independent references."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from ik7r.errors import GunFileError
from ik7r.painting.spray import (
    Gun,
    fit_stripe,
    gun_from_toml,
    gun_to_toml,
    load_gun,
    load_stripe_csv,
    plane_rate,
    stroke_profile,
    surface_rate,
)

GUNS = [
    Gun("gaussian", 200.0, 100.0, {"sigma": 30.0}),
    Gun("beta", 200.0, 80.0, {"radius": 90.0, "beta": 2.5}),
    Gun("double-beta", 200.0, 120.0, {"a": 120.0, "b": 50.0, "beta1": 2.0, "beta2": 3.0}),
]


def _plane_reference(gun, x, y):
    """The plane models written from the issue's formulas, one point at a time."""
    p, q0 = gun.params, gun.peak_rate
    if gun.model == "gaussian":
        r2 = x * x + y * y
        return q0 * math.exp(-r2 / (2 * p["sigma"] ** 2)) if r2 <= (5 * p["sigma"]) ** 2 else 0.0
    if gun.model == "beta":
        w = 1 - (x * x + y * y) / p["radius"] ** 2
        return q0 * w ** (p["beta"] - 1) if w > 0 else 0.0
    u = 1 - y * y / p["a"] ** 2  # a along the tool's y, b along its x
    if u <= 0:
        return 0.0
    w = 1 - x * x / (p["b"] ** 2 * u)
    return q0 * u ** (p["beta1"] - 1) * w ** (p["beta2"] - 1) if w > 0 else 0.0


@pytest.mark.parametrize("gun", GUNS, ids=lambda g: g.model)
def test_plane_rate_matches_the_formulas(gun):
    rng = np.random.default_rng(1)
    pts = rng.uniform(-1.2 * gun.reach, 1.2 * gun.reach, (300, 2))
    ref = np.array([_plane_reference(gun, x, y) for x, y in pts])
    np.testing.assert_allclose(plane_rate(gun, pts[:, 0], pts[:, 1]), ref, rtol=1e-12, atol=1e-12)
    assert plane_rate(gun, 0.0, 0.0) == pytest.approx(gun.peak_rate)


@pytest.mark.parametrize("gun", GUNS, ids=lambda g: g.model)
def test_stroke_profile_closed_forms_against_quadrature(gun):
    speed = 400.0
    along = gun.params.get("b", gun.reach)
    top = gun.params.get("a", gun.reach) if gun.model != "gaussian" else 4 * 30
    for y in np.linspace(0, 0.98 * top, 9):
        if gun.model == "gaussian":  # the closed form is the uncut Gaussian's
            s = gun.params["sigma"]

            def f(x, y=y, s=s):
                return gun.peak_rate * math.exp(-(x * x + y * y) / (2 * s * s))

            num = quad(f, -np.inf, np.inf)[0] / speed
        else:
            num = quad(lambda x, y=y: _plane_reference(gun, x, y), -along, along, limit=200,
                       epsabs=1e-10)[0] / speed
        assert stroke_profile(gun, y, speed) == pytest.approx(num, rel=1e-6, abs=1e-9 * gun.peak_rate)


@pytest.mark.parametrize("gun", GUNS, ids=lambda g: g.model)
def test_projection_on_the_reference_plane_equals_the_plane_model(gun):
    # a plane perpendicular to the gun at h0: alpha = gamma and d = h0 / cos(gamma)
    rng = np.random.default_rng(2)
    xy = rng.uniform(-gun.reach, gun.reach, (200, 2))
    P = np.column_stack([xy, np.full(len(xy), gun.standoff)])
    N = np.tile([0.0, 0.0, -1.0], (len(xy), 1))  # facing the gun
    np.testing.assert_allclose(surface_rate(gun, P, N), plane_rate(gun, xy[:, 0], xy[:, 1]), rtol=1e-12,
                               atol=1e-12)
    assert np.all(surface_rate(gun, P, -N) == 0)  # facing away
    assert np.all(surface_rate(gun, -P, N) == 0)  # behind the gun


def test_projection_formula_on_a_tilted_plane():
    gun = GUNS[0]
    rng = np.random.default_rng(3)
    for _ in range(50):
        P = rng.uniform([-80, -80, 150], [80, 80, 300])
        n = rng.normal(size=3)
        n[2] = -abs(n[2]) - 0.3
        n /= np.linalg.norm(n)
        d = np.linalg.norm(P)
        gamma = math.acos(P[2] / d)
        alpha = math.acos(-n @ P / d)
        r = gun.standoff * math.tan(gamma)
        phi = math.atan2(P[1], P[0])
        ref = _plane_reference(gun, r * math.cos(phi), r * math.sin(phi)) * (gun.standoff / d) ** 2 \
            * math.cos(alpha) / math.cos(gamma) ** 3
        assert surface_rate(gun, P, n) == pytest.approx(ref, rel=1e-10, abs=1e-12)


def test_gun_files_round_trip_and_units():
    for name in ("bell", "beta", "fan"):
        g = load_gun(name)
        back = gun_from_toml(gun_to_toml(g))
        assert back == g
    g = load_gun("bell").in_unit("m")
    assert g.standoff == pytest.approx(0.2) and g.params["sigma"] == pytest.approx(0.03)
    assert g.peak_rate == 100.0  # um/s: not a length


@pytest.mark.parametrize("text, words", [
    ('model = "cone"\nstandoff = 200\npeak_rate = 1\n', "model"),
    ('model = "gaussian"\nstandoff = 200\npeak_rate = 1\n', "sigma"),
    ('model = "gaussian"\nstandoff = 200\npeak_rate = 1\nsigma = -3\n', "sigma"),
    ('model = "gaussian"\nstandoff = 200\npeak_rate = 1\nsigma = 3\nradius = 4\n', "radius"),
    ('model = "beta"\nstandoff = 200\npeak_rate = 1\nradius = 90\nbeta = 0.5\n', "beta"),
    ('model = "gaussian"\nstandoff = "far"\npeak_rate = 1\nsigma = 3\n', "standoff"),
    ("this is = = not toml", "TOML"),
])
def test_bad_gun_files_name_the_file(tmp_path, text, words):
    fp = tmp_path / "mygun.toml"
    fp.write_text(text)
    with pytest.raises(GunFileError) as exc:
        load_gun(fp)
    assert "mygun.toml" in str(exc.value) and words in str(exc.value)
    with pytest.raises(FileNotFoundError):
        load_gun(tmp_path / "missing.toml")


def _synthetic_stripe(gun, speed, y, rng, noise):
    """Film across a stroke by quadrature of the plane model (not the closed form)."""
    along = gun.params.get("b", gun.reach)
    T = np.array([quad(lambda x, yy=yy: _plane_reference(gun, x, yy), -along, along, limit=200)[0]
                  for yy in y]) / speed
    return T + noise * T.max() * rng.normal(size=len(T))


@pytest.mark.parametrize("gun", GUNS, ids=lambda g: g.model)
def test_calibration_recovers_known_parameters(gun, tmp_path):
    rng = np.random.default_rng(4)
    speed, shift = 300.0, 4.0
    y = np.linspace(-1.3 * gun.params.get("a", gun.reach), 1.3 * gun.params.get("a", gun.reach), 121)
    T = _synthetic_stripe(gun, speed, y - shift, rng, 0.0)
    extra = {"b": gun.params["b"], "beta2": gun.params["beta2"]} if gun.model == "double-beta" else {}
    fit = fit_stripe(y, T, model=gun.model, speed=speed, standoff=gun.standoff, **extra)
    assert fit.centre == pytest.approx(shift, abs=1e-3)
    assert fit.gun.peak_rate == pytest.approx(gun.peak_rate, rel=1e-4)
    for k, v in gun.params.items():
        assert fit.gun.params[k] == pytest.approx(v, rel=1e-4), k
    assert fit.rms_relative < 1e-5
    # with 1 % noise the parameters are still within a few percent, and the residual shows the noise
    Tn = _synthetic_stripe(gun, speed, y - shift, rng, 0.01)
    fit = fit_stripe(y, Tn, model=gun.model, speed=speed, standoff=gun.standoff, **extra)
    assert 0.005 < fit.rms_relative < 0.02
    for k, v in gun.params.items():
        assert fit.gun.params[k] == pytest.approx(v, rel=0.05), k
    # the CSV reader
    fp = tmp_path / "stripe.csv"
    fp.write_text("offset,thickness_um\n" + "\n".join(f"{a},{b}" for a, b in zip(y, T)))
    yy, tt = load_stripe_csv(fp)
    np.testing.assert_allclose(yy, y)
    np.testing.assert_allclose(tt, T)


def test_double_beta_fit_needs_b_and_beta2():
    y = np.linspace(-100, 100, 21)
    with pytest.raises(ValueError, match="b and beta2"):
        fit_stripe(y, np.exp(-y ** 2 / 2000), model="double-beta", speed=100.0, standoff=200.0)
