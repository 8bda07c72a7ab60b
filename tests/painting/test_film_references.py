"""Film thickness against references: closed forms, mass balance, brute-force integration of the
projection formula, occlusion on a stepped part (issue 15, item 7)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from ik7r.painting.film import (
    film_stats,
    film_step,
    film_thickness,
    gaussian_ripple,
    poses_from_samples,
    ripple,
)
from ik7r.painting.parts import Part
from ik7r.painting.spray import Gun, load_gun, plane_rate, stroke_profile, surface_rate

DOWN = np.diag([1.0, -1.0, -1.0])  # tool x along +x, tool z pointing down -z


def grid(xs, ys, z=lambda x, y: 0.0 * x):
    """Vertices and counter-clockwise (seen from +z) triangles of a grid, vertex i * len(ys) + j."""
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    V = np.column_stack([X.ravel(), Y.ravel(), z(X, Y).ravel()])
    nu, nv = len(xs), len(ys)
    i, j = np.meshgrid(np.arange(nu - 1), np.arange(nv - 1), indexing="ij")
    a = (i * nv + j).ravel()
    F = np.concatenate([np.column_stack([a, a + nv, a + nv + 1]), np.column_stack([a, a + nv + 1, a + 1])])
    return V, F


def pose(R, p):
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = p
    return T


def strokes(gun, ys, speed, half_length, step, height=None):
    """Straight strokes along x at lateral offsets ``ys``, constant speed, gun down at height h0;
    the turn between strokes is off (a jump, unsprayed interval)."""
    h = gun.standoff if height is None else height
    n = int(math.ceil(2 * half_length / step)) + 1
    xs = np.linspace(-half_length, half_length, n)
    t, T, on, t0 = [], [], [], 0.0
    for k, y in enumerate(ys):
        tt = t0 + (xs - xs[0]) / speed
        t.append(tt)
        T += [pose(DOWN, (x, y, h)) for x in xs]
        on += [True] * (n - 1) + ([False] if k + 1 < len(ys) else [])
        t0 = tt[-1] + 1.0
    return poses_from_samples(np.concatenate(t), np.array(T), np.array(on))


@pytest.mark.parametrize("name", ["bell", "beta", "fan"])
def test_straight_strokes_on_a_flat_plate_match_the_closed_forms(name):
    gun = load_gun(name)
    h = film_step(gun)
    V, F = grid(np.linspace(-60, 60, 25), np.linspace(-200, 200, 201))
    N = np.tile([0.0, 0.0, 1.0], (len(V), 1))
    speed = 450.0
    L = 60 + gun.reach + 5 * h
    # one stroke
    T = film_thickness(V, N, F, strokes(gun, [0.0], speed, L, h), gun)
    ref = stroke_profile(gun, V[:, 1], speed)
    assert np.abs(T - ref).max() <= 0.005 * ref.max()
    # strokes 50 mm apart: the sum of the profiles
    ys = [-100.0, -50.0, 0.0, 50.0, 100.0]
    T = film_thickness(V, N, F, strokes(gun, ys, speed, L, h), gun)
    ref = sum(stroke_profile(gun, V[:, 1] - y, speed) for y in ys)
    assert np.abs(T - ref).max() <= 0.005 * ref.max()


def test_step_rule_and_ripple():
    bell = load_gun("bell")
    assert film_step(bell) == pytest.approx(15.0)  # sigma / 2 passes for a Gaussian
    # a beta pattern with a square-root edge needs a finer step than a smooth one
    assert film_step(Gun("beta", 200, 100, {"radius": 90, "beta": 1.5})) < film_step(load_gun("beta"))
    # ripple of Gaussian strokes: the first Fourier term 2 exp(-2 pi^2 sigma^2 / D^2)
    for D in (45.0, 60.0, 75.0):
        assert ripple(bell, D) == pytest.approx(gaussian_ripple(30.0, D), rel=0.02)
    assert gaussian_ripple(30.0, 60.0) == pytest.approx(0.0144, abs=5e-5)


def _ray_hits_rect(G, dirs, c, n, u, v, a, b):
    """Rays G + s dirs (s > 0) against the rectangle c + x u + y v, |x| <= a, |y| <= b."""
    den = dirs @ n
    s = ((c - G) @ n) / np.where(np.abs(den) > 1e-12, den, np.nan)
    P = G + s[:, None] * dirs
    x, y = (P - c) @ u, (P - c) @ v
    return (s > 0) & (np.abs(x) <= a) & (np.abs(y) <= b)


def test_mass_balance_on_a_tilted_plate():
    """Film volume on a plate smaller than the spray = the flux that hits it, integrated over time:
    the flux through the pixels of the reference plane whose rays meet the plate (ray casting)."""
    gun = load_gun("bell")
    a, b, tilt = 40.0, 50.0, math.radians(25)
    R = np.array([[math.cos(tilt), 0, math.sin(tilt)], [0, 1, 0], [-math.sin(tilt), 0, math.cos(tilt)]])
    V0, F = grid(np.linspace(-a, a, 81), np.linspace(-b, b, 101))
    c = np.array([0.0, 0.0, 0.0])
    V = V0 @ R.T + c
    part = Part(V, F, np.eye(4), "plate")
    N = part.vertex_normals
    # a gun moving along y above the plate, pointing down, slightly off-centre and low
    ys = np.linspace(-120, 120, 13)
    poses = poses_from_samples(ys / 300.0, np.array([pose(DOWN, (10.0, y, 180.0)) for y in ys]))
    T = film_thickness(V, N, F, poses, gun)
    volume = float(np.sum(part.vertex_areas() * T))
    # reference: per pose, the rate through the plane at h0 over the pixels whose rays hit the plate
    g = np.linspace(-gun.reach, gun.reach, 501)
    cell = (g[1] - g[0]) ** 2
    X, Y = np.meshgrid(g, g, indexing="ij")
    q = plane_rate(gun, X, Y).ravel()
    flux = []
    for Tm in poses.T_part_tool:
        dirs = np.column_stack([X.ravel(), Y.ravel(), np.full(X.size, gun.standoff)]) @ Tm[:3, :3].T
        hit = _ray_hits_rect(Tm[:3, 3], dirs, c, R[:, 2], R[:, 0], R[:, 1], a, b)
        flux.append(float(np.sum(q[hit]) * cell))
    reference = float(np.sum(poses.weights * np.array(flux)))
    assert volume == pytest.approx(reference, rel=5e-3)
    # and the stats add up
    s = film_stats(part, T)
    assert s.volume == pytest.approx(volume) and s.area == pytest.approx(4 * a * b, rel=1e-9)


def _brute_force(gun, points, normals, poses_of_t, t0, t1, n=40001):
    """Thickness at ``points`` by the trapezoidal rule over ``n`` instants (a footprint move of
    hundredths of a millimetre) of the projection formula, written out here."""
    t = np.linspace(t0, t1, n)
    T = poses_of_t(t)  # (n, 4, 4)
    out = np.zeros(len(points))
    for i, (p, nn) in enumerate(zip(points, normals)):
        rel = np.einsum("mji,mj->mi", T[:, :3, :3], p - T[:, :3, 3])  # the point in the tool frame
        nt = np.einsum("mji,j->mi", T[:, :3, :3], nn)
        d = np.linalg.norm(rel, axis=1)
        cos_g = rel[:, 2] / d
        cos_a = -np.sum(nt * rel, axis=1) / d
        ok = (rel[:, 2] > 0) & (cos_a > 0)
        Z = np.where(ok, rel[:, 2], 1.0)
        q = plane_rate(gun, gun.standoff * rel[:, 0] / Z, gun.standoff * rel[:, 1] / Z)
        rate = np.where(ok, q * (gun.standoff / d) ** 2 * cos_a / np.where(ok, cos_g, 1.0) ** 3, 0.0)
        out[i] = np.sum(0.5 * (rate[1:] + rate[:-1]) * np.diff(t))
    return out


def _poses(R_of_t, p_of_t, t):
    T = np.zeros((len(t), 4, 4))
    T[:, :3, :3] = R_of_t(t)
    T[:, :3, 3] = p_of_t(t)
    T[:, 3, 3] = 1.0
    return T


def test_tilted_gun_against_brute_force():
    gun = load_gun("fan")
    V, F = grid(np.linspace(-150, 150, 61), np.linspace(-150, 150, 61))
    N = np.tile([0.0, 0.0, 1.0], (len(V), 1))
    tilt = math.radians(30)
    # gun tilted 30 deg about its travel axis x, moving along x at 230 mm height, spinning slowly
    R_tilt = np.array([[1, 0, 0], [0, math.cos(tilt), -math.sin(tilt)], [0, math.sin(tilt), math.cos(tilt)]])

    def R_of_t(t):
        c, s = np.cos(0.3 * t), np.sin(0.3 * t)
        Rz = np.zeros((len(t), 3, 3))
        Rz[:, 0, 0], Rz[:, 0, 1], Rz[:, 1, 0], Rz[:, 1, 1], Rz[:, 2, 2] = c, -s, s, c, 1.0
        return R_tilt @ DOWN @ Rz

    def p_of_t(t):
        return np.column_stack([-300 + 400 * t, np.full(len(t), -60.0), np.full(len(t), 230.0)])

    def poses_of_t(t):
        return _poses(R_of_t, p_of_t, t)

    h = film_step(gun)
    t = np.linspace(0.0, 1.5, int(math.ceil(600 / (h / 2))) + 1)  # footprint moves < h
    poses = poses_from_samples(t, poses_of_t(t))
    T = film_thickness(V, N, F, poses, gun, occlusion=False)
    sel = np.random.default_rng(5).choice(len(V), 60, replace=False)
    sel = np.concatenate([sel, [int(np.argmax(T))]])
    ref = _brute_force(gun, V[sel], N[sel], poses_of_t, 0.0, 1.5)
    assert ref.max() > 1.0
    assert np.abs(T[sel] - ref).max() <= 0.005 * T.max()
    # occlusion on: a flat plate cannot hide itself
    np.testing.assert_allclose(film_thickness(V, N, F, poses, gun), T, rtol=0, atol=1e-12)


def test_curved_part_against_brute_force():
    gun = load_gun("bell")
    Rs = 400.0  # a spherical cap of radius 400 mm, crown at z = 0
    V, F = grid(np.linspace(-160, 160, 81), np.linspace(-160, 160, 81),
                lambda x, y: np.sqrt(Rs ** 2 - x ** 2 - y ** 2) - Rs)
    N = (V - [0, 0, -Rs]) / Rs  # exact normals

    def poses_of_t(t):  # a straight stroke at constant height, gun down
        return _poses(lambda t: np.broadcast_to(DOWN, (len(t), 3, 3)),
                      lambda t: np.column_stack([-250 + 500 * t, np.full(len(t), 20.0),
                                                 np.full(len(t), 200.0)]),
                      t)

    h = film_step(gun)
    t = np.linspace(0.0, 1.0, int(math.ceil(500 / h)) + 1)
    poses = poses_from_samples(t, poses_of_t(t))
    T = film_thickness(V, N, F, poses, gun)
    sel = np.random.default_rng(6).choice(len(V), 60, replace=False)
    ref = _brute_force(gun, V[sel], N[sel], poses_of_t, 0.0, 1.0)
    assert np.abs(T[sel] - ref).max() <= 0.005 * T.max()
    # on the crown the cap is at the reference standoff and square to the gun: the flat closed form
    crown = (np.abs(V[:, 0]) < 1e-9) & (np.abs(V[:, 1] - 20) < 2.5)
    assert T[crown] == pytest.approx(stroke_profile(gun, V[crown, 1] - 20.0, 500.0), rel=0.005)


def _stepped_part(H=100.0, cell=4.0):
    """Lower floor z = 0 for x in [-200, 0], wall x = 0 up to z = H (facing -x), upper floor z = H
    for x in [0, 200]; y in [-100, 100]."""
    ys = np.arange(-100, 100 + cell / 2, cell)
    Vl, Fl = grid(np.arange(-200, 0 + cell / 2, cell), ys)
    Vu, Fu = grid(np.arange(0, 200 + cell / 2, cell), ys, lambda x, y: 0 * x + H)
    # wall: grid in (z, y) mapped to x = 0; orientation so that the normal is -x
    Vw, Fw = grid(np.arange(0, H + cell / 2, cell), ys)
    Vw = np.column_stack([np.zeros(len(Vw)), Vw[:, 1], Vw[:, 0]])
    V = np.concatenate([Vl, Vu, Vw])
    F = np.concatenate([Fl, Fu + len(Vl), Fw + len(Vl) + len(Vu)])
    return Part(V, F, np.eye(4), "step")


def test_occlusion_on_a_stepped_part():
    gun = load_gun("bell")
    H = 100.0
    part = _stepped_part(H)
    V, N = part.vertices, part.vertex_normals
    lower = (V[:, 2] == 0) & (V[:, 0] < -1e-9)
    assert np.all(N[lower] @ [0, 0, 1] > 0.999)
    wall = V[:, 0] == 0
    G = np.array([30.0, 0.0, H + gun.standoff])  # above the upper floor, 30 mm from the edge
    poses = poses_from_samples([0.0, 1.0], np.array([pose(DOWN, G)] * 2))  # 1 s static
    T = film_thickness(V, N, part.faces, poses, gun)
    T_free = film_thickness(V, N, part.faces, poses, gun, occlusion=False)
    # reference without occlusion: the projection formula point by point
    ref = surface_rate(gun, (V - G) @ DOWN, N @ DOWN)
    np.testing.assert_allclose(T_free, ref, rtol=1e-9, atol=1e-12)
    # a point of the lower floor is hidden when its ray to the tip crosses the wall below its top
    s0 = G[0] / (G[0] - V[:, 0])
    z_cross = G[2] * (1 - s0)
    margin = 3.0  # mm at the wall: a few pixels of the depth buffer
    hidden = lower & (z_cross < H - margin) & (ref > 0)
    seen = lower & (z_cross > H + margin) & (ref > 0)
    assert hidden.sum() > 50 and seen.sum() > 50
    assert np.all(T[hidden] == 0.0)
    np.testing.assert_allclose(T[seen], ref[seen], rtol=1e-12)
    assert np.all(T_free[hidden] > 0)  # (the occlusion is what removed it)
    # the upper floor sees the gun everywhere; the wall faces away from it
    upper = V[:, 2] == H
    np.testing.assert_allclose(T[upper & ~wall], ref[upper & ~wall], rtol=1e-12)
    inner_wall = wall & (V[:, 2] > 1e-9) & (V[:, 2] < H - 1e-9)
    assert np.all(T[inner_wall] == 0)
