"""Parts (mesh files, units, placement, bad files) and surface rasters (standoff, orientation,
passes, overspray, spray flags, holes), and the reach of the built-in parts."""

from __future__ import annotations

import math

import numpy as np
import pytest
import trimesh

import ik7r
from ik7r.errors import PartFileError
from ik7r.painting import solve_path, workpiece_frame
from ik7r.painting.parts import BUILTIN_PARTS, Part, builtin_part, load_part
from ik7r.painting.surface import sprayed_length, surface_raster, target_faces


def _box_mesh():
    return trimesh.creation.box(extents=(0.4, 0.3, 0.02))  # metres


@pytest.mark.parametrize("suffix", [".stl", ".obj", ".ply"])
def test_load_mesh_files_in_a_unit(tmp_path, suffix):
    box = _box_mesh()
    fp = tmp_path / f"box{suffix}"
    box.export(fp)
    T = workpiece_frame((1000.0, 0.0, 100.0))
    part = load_part(fp, unit="mm", part_unit="m", T_base_part=T)
    assert part.unit == "mm" and part.file_unit == "m"
    np.testing.assert_allclose(part.bounds, [[-200, -150, -10], [200, 150, 10]], atol=1e-6)
    assert part.face_areas.sum() == pytest.approx(box.area * 1e6, rel=1e-6)  # STL is float32
    np.testing.assert_allclose(part.T_base_part, T)
    assert part.name == fp.name


@pytest.mark.parametrize("content, words", [
    (b"", "empty"),
    (b"solid nothing\nthis is not an stl at all\n", "box.stl"),
    (b"v 0 0 0\nv 1 0 0\nv 0 1 0\n", "no faces"),
    (b"v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", "not finite"),
])
def test_bad_mesh_files_raise_part_file_errors_naming_the_file(tmp_path, content, words):
    suffix = ".stl" if b"solid" in content or not content else ".obj"
    fp = tmp_path / f"box{suffix}"
    fp.write_bytes(content)
    with pytest.raises(PartFileError) as exc:
        load_part(fp)
    assert fp.name in str(exc.value) and words in str(exc.value)


def test_missing_or_unknown_part_files(tmp_path):
    with pytest.raises(FileNotFoundError, match="panel, hood"):
        load_part(tmp_path / "nothing.stl")
    fp = tmp_path / "part.step"
    fp.write_text("ISO-10303-21;")
    with pytest.raises(PartFileError, match="part.step"):
        load_part(fp)


def test_builtin_parts():
    panel = builtin_part("panel")
    np.testing.assert_allclose(panel.bounds, [[-250, -300, 0], [250, 300, 0]])
    assert panel.face_areas.sum() == pytest.approx(500 * 600)
    hood = builtin_part("hood")
    # doubly curved: sag 41 mm along x (R 1500) and 31 mm along y (R 1000) from the crown
    assert hood.vertices[:, 2].max() == pytest.approx(0.0, abs=1e-9)
    x, y, z = hood.vertices.T
    np.testing.assert_allclose(z, np.sqrt(1500 ** 2 - x ** 2) - 1500 + np.sqrt(1000 ** 2 - y ** 2) - 1000,
                               atol=1e-9)
    assert np.all(target_faces(hood))  # every face looks up at the gun
    m = builtin_part("hood", unit="m")
    np.testing.assert_allclose(m.vertices, hood.vertices / 1000)
    np.testing.assert_allclose(m.T_base_part[:3, 3], [1.1, 0, 0])
    assert set(BUILTIN_PARTS) == {"panel", "hood"}


def _seg_on(path):
    return path.spray[:-1] & path.spray[1:]


def test_panel_raster_geometry():
    part = builtin_part("panel", T_base_part=np.eye(4))
    spacing, standoff, over, approach = 60.0, 200.0, 50.0, 120.0
    path = surface_raster(part, spacing=spacing, standoff=standoff, overspray=over, approach=approach)
    P, R, on = path.positions, path.rotations, path.spray
    # sprayed samples: at the standoff above the plate, gun axis (tool z) pointing down at it
    assert np.all(np.abs(P[on, 2] - standoff) < 1e-9)
    np.testing.assert_allclose(R[on][:, :, 2], np.tile([0, 0, -1.0], (on.sum(), 1)), atol=1e-12)
    # passes: ceil(600 / 60) = 10 planes 60 mm apart centred on the panel, boustrophedon
    ys = np.unique(np.round(P[on, 1], 6))
    np.testing.assert_allclose(ys, -270 + 60 * np.arange(10), atol=1e-9)
    for k, y in enumerate(ys):
        sel = on & (np.abs(P[:, 1] - y) < 1e-6)
        # each pass runs from overspray before the edge to overspray after it, spray on
        assert P[sel, 0].min() == pytest.approx(-250 - over) and P[sel, 0].max() == pytest.approx(250 + over)
        # tool x along the travel: +x on even passes, -x on odd ones
        x_travel = [1.0 if k % 2 == 0 else -1.0, 0, 0]
        np.testing.assert_allclose(R[sel][:, :, 0], np.tile(x_travel, (sel.sum(), 1)), atol=1e-12)
    # the sprayed length is the passes' and nothing else; turns and approach are off
    assert sprayed_length(path) == pytest.approx(10 * (500 + 2 * over), rel=1e-9)
    seg = _seg_on(path)
    mid = 0.5 * (P[1:] + P[:-1])
    assert np.all(np.abs(mid[~seg, 0]) > 250 + over - 1e-9)  # every spray-off stretch is off the part
    assert not on[0] and not on[-1]  # approach and retract off
    assert P[0, 0] == pytest.approx(-250 - over - approach)
    # the path parameter: samples 5 mm apart at most along the passes
    assert np.diff(path.u)[seg].max() <= 5.0 + 1e-9


def test_spin_turns_tool_x_about_the_gun_axis():
    part = builtin_part("panel", T_base_part=np.eye(4))
    a = surface_raster(part, spacing=100, standoff=200, overspray=50, approach=100)
    b = surface_raster(part, spacing=100, standoff=200, overspray=50, approach=100, spin=math.radians(30))
    np.testing.assert_allclose(a.positions, b.positions, atol=1e-9)
    on = a.spray
    ang = np.arctan2(np.einsum("ni,ni->n", np.cross(a.rotations[on][:, :, 0], b.rotations[on][:, :, 0]),
                               a.rotations[on][:, :, 2]),
                     np.einsum("ni,ni->n", a.rotations[on][:, :, 0], b.rotations[on][:, :, 0]))
    np.testing.assert_allclose(ang, math.radians(30), atol=1e-9)


def test_hood_raster_keeps_the_standoff_along_the_normal():
    part = builtin_part("hood", cell=25.0, T_base_part=np.eye(4))  # coarse mesh
    standoff = 200.0
    path = surface_raster(part, spacing=60, standoff=standoff, overspray=40, approach=100)
    on = path.spray
    P, z = path.positions[on], path.rotations[on][:, :, 2]
    # foot of the gun axis on the exact surface: within 1.5 mm of the standoff, axis within 1.5 deg
    # of the exact normal (x^2 terms: z = sqrt(Rx^2 - x^2) - Rx + sqrt(Ry^2 - y^2) - Ry)
    foot = P + standoff * z
    inside = (np.abs(foot[:, 0]) < 340) & (np.abs(foot[:, 1]) < 190)
    x, y = foot[inside, 0], foot[inside, 1]
    zs = np.sqrt(1500 ** 2 - x ** 2) - 1500 + np.sqrt(1000 ** 2 - y ** 2) - 1000
    assert np.abs(foot[inside, 2] - zs).max() < 1.5
    n = np.column_stack([x / np.sqrt(1500 ** 2 - x ** 2), y / np.sqrt(1000 ** 2 - y ** 2), np.ones(len(x))])
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    cosang = np.einsum("ni,ni->n", -z[inside], n)
    assert np.degrees(np.arccos(np.clip(cosang, -1, 1))).max() < 1.5
    # and the orientation changes smoothly from sample to sample along the passes
    seg = _seg_on(path)
    dz = np.linalg.norm(np.diff(path.rotations[:, :, 2], axis=0), axis=1)[seg]
    assert dz.max() < math.radians(1.0)


def test_holes_are_crossed_with_the_spray_off():
    # a 500 x 300 mm plate with a 200 x 100 mm hole in the middle
    xs, ys = np.arange(-250, 251, 10.0), np.arange(-150, 151, 10.0)
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    V = np.column_stack([X.ravel(), Y.ravel(), np.zeros(X.size)])
    nv = len(ys)
    faces = []
    for i in range(len(xs) - 1):
        for j in range(nv - 1):
            cx, cy = xs[i] + 5, ys[j] + 5
            if abs(cx) < 100 and abs(cy) < 50:
                continue
            a = i * nv + j
            faces += [(a, a + nv, a + nv + 1), (a, a + nv + 1, a + 1)]
    part = Part(V, np.array(faces), np.eye(4), "holed")
    over = 30.0
    path = surface_raster(part, spacing=40, standoff=200, overspray=over, approach=100)
    P, seg = path.positions, _seg_on(path)
    mid = 0.5 * (P[1:] + P[:-1])
    through = np.abs(mid[:, 1]) < 45  # passes crossing the hole
    assert np.any(through & ~seg & (np.abs(mid[:, 0]) < 50))  # off in the middle of the hole
    # on over the solid part and within the overspray of the hole's edges, off beyond it
    assert np.all(seg[through & (np.abs(mid[:, 0]) > 100 - 1e-9) & (np.abs(mid[:, 0]) < 250)])
    assert np.all(~seg[through & (np.abs(mid[:, 0]) < 100 - over - 1e-6)])


@pytest.mark.parametrize("robot_name, origin",
                         [("paper", (1100.0, 0.0, 0.0)), ("irb5400", (1600.0, 0.0, 500.0))])
@pytest.mark.parametrize("part_name", ["panel", "hood"])
def test_builtin_parts_are_reached(robot_name, origin, part_name):
    robot = ik7r.load_robot(robot_name)
    part = builtin_part(part_name, T_base_part=workpiece_frame(origin))
    path = surface_raster(part, spacing=55, standoff=200, overspray=60, approach=150)
    sol = solve_path(robot, path, 1)
    assert sol.feasible, sol.report()
    # every sample solved exactly: FK gives the path pose
    T = robot.fk(sol.q)
    np.testing.assert_allclose(T[:, :3, 3], path.positions, atol=1e-6)


def test_pass_direction_in_the_part_frame():
    part = builtin_part("panel", T_base_part=np.eye(4))
    path = surface_raster(part, spacing=100, standoff=200, overspray=50, approach=100, direction=(0, 1, 0))
    on = path.spray
    xs = np.unique(np.round(path.positions[on, 0], 6))
    np.testing.assert_allclose(xs, -200 + 100 * np.arange(5), atol=1e-9)  # ceil(500 / 100) passes across x
    assert path.positions[on, 1].min() == pytest.approx(-350)
    assert path.positions[on, 1].max() == pytest.approx(350)
    with pytest.raises(ValueError, match="parallel"):
        surface_raster(part, spacing=100, standoff=200, overspray=50, approach=100, direction=(0, 0, 1))


def test_surface_path_is_smooth_between_samples():
    """The path between samples is a spline through them (no corner at each sample of a turn)."""
    path = surface_raster(builtin_part("hood", T_base_part=np.eye(4)), spacing=60, standoff=200,
                          overspray=40, approach=100)
    P, R = path.at(path.u)
    np.testing.assert_allclose(P, path.positions, atol=1e-9)
    np.testing.assert_allclose(R, path.rotations, atol=1e-9)
    # velocity just before and just after every interior sample: the same (C1), in a turn as well
    eps = 1e-4
    u = path.u[1:-1]
    before = (path.at(u)[0] - path.at(u - eps)[0]) / eps
    after = (path.at(u + eps)[0] - path.at(u)[0]) / eps
    assert np.abs(after - before).max() < 1e-2
    # whereas the polyline through the samples turns by a finite angle at the samples of a turn
    d = np.diff(path.positions, axis=0)
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    assert np.degrees(np.arccos(np.clip(np.sum(d[1:] * d[:-1], axis=1), -1, 1))).max() > 5
