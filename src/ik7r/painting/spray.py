"""Spray guns: the deposition models, gun files, the projection onto a surface, stripe fitting.

A gun sprays along its tool +z from the TCP (the gun tip). Its **plane model** ``q(x, y)`` is
the film growth rate (um/s) on a plane perpendicular to the gun axis at the reference standoff
``h0``, ``(x, y)`` along the tool's x and y axes, ``r = sqrt(x^2 + y^2)``:

``gaussian``      ``q = peak_rate exp(-r^2 / (2 sigma^2))``
``beta``          ``q = peak_rate (1 - r^2/radius^2)^(beta - 1)`` for ``r <= radius``
``double-beta``   ``q = peak_rate (1 - y^2/a^2)^(beta1 - 1) (1 - x^2 / (b^2 (1 - y^2/a^2)))^(beta2 - 1)``
                  inside the ellipse (``a`` along the tool's y: a fan across the travel)

Any surface point ``s`` receives (:func:`surface_rate`, conserving the flux per solid angle)
``q_s = q(h0 X/Z, h0 Y/Z) (h0/d)^2 cos(alpha) / cos(gamma)^3`` where ``(X, Y, Z)`` is ``s`` in
the tool frame, ``d = |s|``, ``gamma`` the ray's angle to the gun axis (``cos gamma = Z/d``)
and ``alpha`` its angle to the surface normal; nothing when ``cos(alpha) <= 0`` (the surface
faces away) or ``Z <= 0``. Occlusion by the part is the film integrator's job
(:mod:`ik7r.painting.film`).

A gun file (TOML)::

    name = "example gun"
    unit = "mm"            # length unit of the keys below
    model = "gaussian"     # "gaussian", "beta" or "double-beta"
    standoff = 200         # reference standoff h0
    peak_rate = 100        # um/s at the centre, on the plane at h0
    sigma = 30             # gaussian
    # radius = 90, beta = 2.5                 beta
    # a = 120, b = 50, beta1 = 2, beta2 = 3   double-beta
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path as FilePath

import numpy as np

from ..errors import GunFileError
from ..units import unit_scale

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

__all__ = ["Gun", "MODELS", "BUILTIN_GUNS", "load_gun", "gun_from_toml", "gun_to_toml", "plane_rate",
           "surface_rate", "stroke_profile", "fit_stripe", "StripeFit", "load_stripe_csv", "DEFAULT_GUN"]

#: Model name -> its shape parameters (lengths first).
MODELS = {"gaussian": ("sigma",), "beta": ("radius", "beta"), "double-beta": ("a", "b", "beta1", "beta2")}
_LENGTHS = {"sigma", "radius", "a", "b"}
#: Built-in gun names -> files in the package data (``ik7r/painting/data/guns``).
BUILTIN_GUNS = {"bell": "bell.toml", "beta": "beta.toml", "fan": "fan.toml"}
#: The gun ``ik7r paint mesh`` uses by default.
DEFAULT_GUN = "bell"
#: Gaussian patterns are cut at this many sigma (the rate there is 3.7e-6 of the peak).
GAUSS_CUT = 5.0


@dataclass(frozen=True)
class Gun:
    """A spray gun: model, reference standoff, peak rate and shape parameters (immutable).

    Attributes
    ----------
    model : str
        ``"gaussian"``, ``"beta"`` or ``"double-beta"``.
    standoff : float
        Reference standoff ``h0`` (``unit``).
    peak_rate : float
        Growth rate at the centre on the plane at ``h0`` (um/s).
    params : dict
        The model's shape parameters (lengths in ``unit``): ``sigma``; ``radius, beta``;
        ``a, b, beta1, beta2``.
    unit : str
    name : str
    """

    model: str
    standoff: float
    peak_rate: float
    params: dict = field(default_factory=dict)
    unit: str = "mm"
    name: str = "gun"

    def __post_init__(self) -> None:
        if self.model not in MODELS:
            raise ValueError(f"gun model must be one of {', '.join(MODELS)}; got {self.model!r}")
        unit_scale(self.unit, "mm")
        for key, val in (("standoff", self.standoff), ("peak_rate", self.peak_rate)):
            if not (isinstance(val, (int, float)) and math.isfinite(val) and val > 0):
                raise ValueError(f"gun {key} must be a positive number; got {val!r}")
        need = MODELS[self.model]
        extra = set(self.params) - set(need)
        missing = [k for k in need if k not in self.params]
        if missing or extra:
            raise ValueError(f"a {self.model} gun takes {', '.join(need)}; "
                             f"missing {missing}, unexpected {sorted(extra)}")
        p = {k: float(self.params[k]) for k in need}
        for k, v in p.items():
            low = 1.0 if k.startswith("beta") else 0.0
            if not (math.isfinite(v) and v > low):
                raise ValueError(f"gun parameter {k} must be a number > {low:g}; got {v!r}")
        object.__setattr__(self, "params", p)
        object.__setattr__(self, "standoff", float(self.standoff))
        object.__setattr__(self, "peak_rate", float(self.peak_rate))

    def in_unit(self, unit: str) -> Gun:
        """The same gun with its lengths in ``unit``."""
        s = unit_scale(self.unit, unit)
        p = {k: v * s if k in _LENGTHS else v for k, v in self.params.items()}
        return Gun(self.model, self.standoff * s, self.peak_rate, p, unit, self.name)

    @property
    def reach(self) -> float:
        """Largest distance from the axis with a non-zero rate on the plane at ``h0`` (gaussian:
        :data:`GAUSS_CUT` sigma)."""
        p = self.params
        return {"gaussian": lambda: GAUSS_CUT * p["sigma"], "beta": lambda: p["radius"],
                "double-beta": lambda: max(p["a"], p["b"])}[self.model]()

    @property
    def width(self) -> float:
        """The pattern's smallest length scale (sigma, radius, min(a, b)): the film step rule's."""
        p = self.params
        return {"gaussian": p.get("sigma"), "beta": p.get("radius"),
                "double-beta": min(p.get("a", 0), p.get("b", 0))}[self.model]

    def kernel_params(self) -> np.ndarray:
        """``[model id, h0, peak, p1, p2, p3, p4]`` for the compiled film kernel."""
        p = list(self.params.values()) + [0.0] * (4 - len(self.params))
        return np.array([list(MODELS).index(self.model), self.standoff, self.peak_rate, *p])

    def describe(self) -> str:
        ps = ", ".join(f"{k} {v:g}{' ' + self.unit if k in _LENGTHS else ''}" for k, v in self.params.items())
        return (f"{self.name}: {self.model}, standoff {self.standoff:g} {self.unit}, peak rate "
                f"{self.peak_rate:g} um/s, {ps}")


# ----------------------------------------------------------------------------- files
def gun_from_toml(text: str, *, source: str = "<string>") -> Gun:
    """A gun from TOML text (see the module docstring); ``GunFileError`` naming ``source``."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise GunFileError(f"{source}: not valid TOML ({exc})") from exc
    model = data.get("model")
    if model not in MODELS:
        raise GunFileError(f"{source}: model must be one of {', '.join(MODELS)}; got {model!r}")
    known = {"name", "unit", "model", "standoff", "peak_rate", *MODELS[model]}
    unknown = sorted(set(data) - known)
    if unknown:
        raise GunFileError(f"{source}: unknown keys {unknown} for a {model} gun; expected "
                           f"{', '.join(sorted(known))}")
    for key in ("standoff", "peak_rate", *MODELS[model]):
        if key not in data:
            raise GunFileError(f"{source}: missing key {key!r} (a {model} gun needs standoff, peak_rate, "
                               f"{', '.join(MODELS[model])})")
        if not isinstance(data[key], (int, float)) or isinstance(data[key], bool):
            raise GunFileError(f"{source}: {key} must be a number; got {data[key]!r}")
    try:
        return Gun(model, data["standoff"], data["peak_rate"], {k: data[k] for k in MODELS[model]},
                   str(data.get("unit", "mm")), str(data.get("name", FilePath(source).stem)))
    except ValueError as exc:
        raise GunFileError(f"{source}: {exc}") from exc


def gun_to_toml(gun: Gun, *, comment: str = "") -> str:
    """The TOML text of ``gun`` (read back by :func:`gun_from_toml`)."""
    lines = [f"# {c}" for c in comment.splitlines()] if comment else []
    lines += [f'name = "{gun.name}"', f'unit = "{gun.unit}"', f'model = "{gun.model}"',
              f"standoff = {gun.standoff!r}", f"peak_rate = {gun.peak_rate!r}"]
    lines += [f"{k} = {v!r}" for k, v in gun.params.items()]
    return "\n".join(lines) + "\n"


def load_gun(source=DEFAULT_GUN) -> Gun:
    """A gun from a built-in name (:data:`BUILTIN_GUNS`) or a TOML file.

    Raises ``FileNotFoundError`` (no such file) or ``GunFileError`` (malformed; names the file).
    """
    if isinstance(source, Gun):
        return source
    if isinstance(source, str) and source in BUILTIN_GUNS:
        text = (resources.files("ik7r.painting") / "data" / "guns" / BUILTIN_GUNS[source]).read_text()
        return gun_from_toml(text, source=f"built-in gun {source!r}")
    fp = FilePath(source)
    if not fp.is_file():
        raise FileNotFoundError(f"no such gun file: {fp} (built-in guns: {', '.join(BUILTIN_GUNS)})")
    try:
        text = fp.read_text()
    except (OSError, UnicodeDecodeError) as exc:
        raise GunFileError(f"{fp}: cannot read ({exc})") from exc
    return gun_from_toml(text, source=str(fp))


# ----------------------------------------------------------------------------- models
def plane_rate(gun: Gun, x, y) -> np.ndarray:
    """The plane model ``q(x, y)`` (um/s) at tool-frame coordinates on the plane at ``h0``."""
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    p, q0 = gun.params, gun.peak_rate
    if gun.model == "gaussian":
        r2 = x * x + y * y
        return np.where(r2 <= (GAUSS_CUT * p["sigma"]) ** 2, q0 * np.exp(-r2 / (2 * p["sigma"] ** 2)), 0.0)
    if gun.model == "beta":
        w = 1.0 - (x * x + y * y) / p["radius"] ** 2
        return np.where(w > 0, q0 * np.clip(w, 0, None) ** (p["beta"] - 1), 0.0)
    u = 1.0 - y * y / p["a"] ** 2
    w = np.where(u > 0, 1.0 - x * x / (p["b"] ** 2 * np.where(u > 0, u, 1.0)), 0.0)
    ok = (u > 0) & (w > 0)
    q = q0 * np.clip(u, 0, None) ** (p["beta1"] - 1) * np.clip(w, 0, None) ** (p["beta2"] - 1)
    return np.where(ok, q, 0.0)


def surface_rate(gun: Gun, points_tool, normals_tool) -> np.ndarray:
    """Growth rate (um/s) at surface points given in the **tool frame** ``(..., 3)`` with unit
    normals ``(..., 3)`` (towards the side the paint lands on): the projection formula of the
    module docstring, without occlusion."""
    P = np.asarray(points_tool, dtype=float)
    N = np.asarray(normals_tool, dtype=float)
    X, Y, Z = P[..., 0], P[..., 1], P[..., 2]
    d = np.linalg.norm(P, axis=-1)
    ok = Z > 0
    Zs = np.where(ok, Z, 1.0)
    ds = np.where(ok, d, 1.0)
    cos_a = -np.sum(N * P, axis=-1) / ds
    cos_g = Zs / ds
    h0 = gun.standoff
    q = plane_rate(gun, h0 * X / Zs, h0 * Y / Zs) * (h0 / ds) ** 2 * cos_a / cos_g ** 3
    return np.where(ok & (cos_a > 0), q, 0.0)


def stroke_profile(gun: Gun, y, speed: float) -> np.ndarray:
    """Film (um) across one straight stroke at ``speed`` over a plane at the reference standoff,
    perpendicular to the gun, ``y`` the distance from the stroke's line (tool y, the travel
    along tool x): ``(1/v) integral q(x, y) dx``, in closed form:

    - gaussian: ``sqrt(2 pi) sigma q0 / v exp(-y^2 / (2 sigma^2))``;
    - beta: ``q0 R / v B(1/2, beta) (1 - y^2/R^2)^(beta - 1/2)``;
    - double-beta: ``q0 b / v B(1/2, beta2) (1 - y^2/a^2)^(beta1 - 1/2)``.
    """
    from scipy.special import beta as B

    y = np.asarray(y, dtype=float)
    p, q0 = gun.params, gun.peak_rate
    if not (math.isfinite(speed) and speed > 0):
        raise ValueError(f"speed must be positive; got {speed!r}")
    if gun.model == "gaussian":
        s = p["sigma"]
        return math.sqrt(2 * math.pi) * s * q0 / speed * np.exp(-y * y / (2 * s * s))
    if gun.model == "beta":
        R = p["radius"]
        w = np.clip(1 - y * y / R ** 2, 0, None)
        return q0 * R / speed * B(0.5, p["beta"]) * w ** (p["beta"] - 0.5)
    w = np.clip(1 - y * y / p["a"] ** 2, 0, None)
    return q0 * p["b"] / speed * B(0.5, p["beta2"]) * w ** (p["beta1"] - 0.5)


# ----------------------------------------------------------------------------- calibration
@dataclass(frozen=True)
class StripeFit:
    """A fitted gun and how well it fits the stripe.

    ``gun``; ``centre`` (the stripe's centre offset found, unit); ``rms`` and ``max_abs``
    residuals (um); ``rms_relative`` (rms / the measured peak); ``n`` points.
    """

    gun: Gun
    centre: float
    rms: float
    max_abs: float
    rms_relative: float
    n: int

    def report(self) -> str:
        return (f"fit: {self.gun.describe()}\n"
                f"stripe centre at offset {self.centre:.4g} {self.gun.unit}; residual rms {self.rms:.4g} um "
                f"({100 * self.rms_relative:.3g} % of the peak), max {self.max_abs:.4g} um, {self.n} points")


def load_stripe_csv(file) -> tuple[np.ndarray, np.ndarray]:
    """``(offset, thickness_um)`` columns of a stripe CSV (header row; ``#`` comments skipped)."""
    fp = FilePath(file)
    if not fp.is_file():
        raise FileNotFoundError(f"no such stripe file: {fp}")
    rows = [line for line in fp.read_text().splitlines()
            if line.strip() and not line.lstrip().startswith("#")]
    if not rows:
        raise ValueError(f"{fp}: empty; expected a header 'offset,thickness_um' and rows of numbers")
    header = [c.strip().lower() for c in rows[0].split(",")]
    if "offset" not in header or "thickness_um" not in header:
        raise ValueError(f"{fp}: the header {rows[0]!r} must name the columns offset and thickness_um")
    io, it = header.index("offset"), header.index("thickness_um")
    data = []
    for k, line in enumerate(rows[1:], start=2):
        cells = line.split(",")
        try:
            data.append((float(cells[io]), float(cells[it])))
        except (IndexError, ValueError) as exc:
            raise ValueError(f"{fp}, row {k}: expected numbers in offset and thickness_um; "
                             f"got {line!r}") from exc
    arr = np.array(data)
    if len(arr) < 5 or not np.all(np.isfinite(arr)):
        raise ValueError(f"{fp}: need at least 5 rows of finite numbers; got {len(arr)}")
    return arr[:, 0], arr[:, 1]


def fit_stripe(offset, thickness, *, model: str, speed: float, standoff: float, unit: str = "mm",
               b: float | None = None, beta2: float | None = None, name: str = "fitted gun") -> StripeFit:
    """Fit a gun model to a stripe: the film across one straight stroke sprayed at ``speed``
    (unit/s) and ``standoff`` over a flat plate perpendicular to the gun.

    The stripe gives the stroke profile :func:`stroke_profile` ``T(y - centre)``: gaussian ->
    ``peak_rate, sigma``; beta -> ``peak_rate, radius, beta``; double-beta -> ``peak_rate, a,
    beta1`` only (the profile across the stroke depends on ``b`` and ``beta2`` through
    ``peak_rate b B(1/2, beta2)`` alone): give ``b`` and ``beta2`` (from the fan's length along
    the travel). The centre offset is fitted too. Least squares (scipy), residuals in um.
    """
    from scipy.optimize import least_squares

    y = np.asarray(offset, dtype=float)
    T = np.asarray(thickness, dtype=float)
    if y.shape != T.shape or y.ndim != 1 or len(y) < 5:
        raise ValueError("offset and thickness must be two 1-D arrays of the same length >= 5")
    if model not in MODELS:
        raise ValueError(f"model must be one of {', '.join(MODELS)}; got {model!r}")
    if model == "double-beta" and (b is None or beta2 is None):
        raise ValueError("a stripe across the stroke does not determine the fan's b and beta2 "
                         "(only peak_rate * b * B(1/2, beta2)): give b and beta2")
    peak = float(T.max())
    if not peak > 0:
        raise ValueError("the stripe has no positive thickness")
    w = T / peak
    c0 = float(np.sum(y * w) / np.sum(w))
    sd = float(math.sqrt(max(np.sum(w * (y - c0) ** 2) / np.sum(w), 1e-12)))
    half = float(np.ptp(y[T > 0.05 * peak])) / 2 if np.sum(T > 0.05 * peak) > 1 else 2 * sd

    def gun_of(x):
        if model == "gaussian":
            return Gun(model, standoff, x[1], {"sigma": x[2]}, unit, name)
        if model == "beta":
            return Gun(model, standoff, x[1], {"radius": x[2], "beta": x[3]}, unit, name)
        return Gun(model, standoff, x[1], {"a": x[2], "b": b, "beta1": x[3], "beta2": beta2}, unit, name)

    # start: the peak rate from the closed form's centre value
    if model == "gaussian":
        x0 = [c0, peak * speed / (math.sqrt(2 * math.pi) * sd), sd]
        lo, hi = [y.min(), 1e-9, 1e-9], [y.max(), np.inf, np.inf]
    else:
        from scipy.special import beta as Bf

        R0 = max(half * 1.1, 1e-6)
        x0 = [c0, peak * speed / (R0 * Bf(0.5, 2.0)) if model == "beta" else
              peak * speed / (b * Bf(0.5, beta2)), R0, 2.0]
        lo, hi = [y.min(), 1e-9, 1e-9, 1.0 + 1e-6], [y.max(), np.inf, np.inf, 50.0]

    def resid(x):
        return stroke_profile(gun_of(x), y - x[0], speed) - T

    sol = least_squares(resid, x0, bounds=(lo, hi), x_scale="jac", xtol=1e-12, ftol=1e-12, gtol=1e-12)
    r = resid(sol.x)
    return StripeFit(gun_of(sol.x), float(sol.x[0]), float(np.sqrt(np.mean(r ** 2))), float(np.abs(r).max()),
                     float(np.sqrt(np.mean(r ** 2)) / peak), len(y))
