"""Pictures of the film: a heat map (PNG) and a self-contained 3-D view (HTML, no network).

:func:`plot_thickness` draws the painted faces seen from the gun side, coloured by thickness
with a colour bar in um (the target band marked on it). :func:`write_view_html` writes one
HTML file with a small hand-written WebGL viewer embedded (about 150 lines of JavaScript, no
library, no CDN): the part coloured by thickness, the path (red where the gun sprays, grey
where it does not) and the robot at a few postures (polylines through its frame origins);
drag to turn, wheel to zoom.
"""

from __future__ import annotations

import base64
import json
from pathlib import Path as FilePath

import numpy as np

from .surface import _axes

__all__ = ["plot_thickness", "write_view_html", "write_thickness_csv"]


def _limits(thickness, faces_mask, part):
    used = np.zeros(len(part.vertices), dtype=bool)
    used[np.unique(part.faces[faces_mask])] = True
    t = np.asarray(thickness)[used]
    lo, hi = float(t.min()), float(t.max())
    return (lo, hi if hi > lo else lo + 1.0), used


def write_thickness_csv(part, thickness, file) -> FilePath:
    """``x,y,z,thickness_um`` per vertex, in the part frame and the part's file unit."""
    from ..units import unit_scale

    fp = FilePath(file)
    s = unit_scale(part.unit, part.file_unit)
    table = np.column_stack([part.vertices * s, np.asarray(thickness, dtype=float)])
    np.savetxt(fp, table, delimiter=",", fmt="%.9g", header="x,y,z,thickness_um", comments="")
    return fp


def plot_thickness(part, thickness, out, *, faces=None, direction=(1.0, 0.0, 0.0), view=(0.0, 0.0, 1.0),
                   target: float | None = None, tolerance: float | None = None,
                   title: str | None = None) -> FilePath:
    """Heat map of the film on the ``faces`` (mask; default all), seen along ``-view`` with the
    pass ``direction`` to the right (part frame); colour bar in um."""
    from .plots import _pyplot

    plt = _pyplot()
    mask = np.ones(len(part.faces), dtype=bool) if faces is None else np.asarray(faces, dtype=bool)
    d, c, _ = _axes(direction, view)
    xy = np.column_stack([part.vertices @ d, part.vertices @ c])
    (lo, hi), _ = _limits(thickness, mask, part)
    fig, ax = plt.subplots(figsize=(8, 6.5))
    try:
        tpc = ax.tripcolor(xy[:, 0], xy[:, 1], part.faces[mask], np.asarray(thickness, dtype=float),
                           shading="gouraud", cmap="viridis", vmin=lo, vmax=hi)
        bar = fig.colorbar(tpc, ax=ax)
        bar.set_label("film thickness (um)")
        if target is not None:
            tol = 0.1 * target if tolerance is None else tolerance
            for v, ls in ((target, "-"), (target - tol, "--"), (target + tol, "--")):
                if lo <= v <= hi:
                    bar.ax.axhline(v, color="white", ls=ls, lw=1.2)
        ax.set_aspect("equal")
        u = part.unit
        ax.set_xlabel(f"along the passes ({u})")
        ax.set_ylabel(f"across the passes ({u})")
        ax.set_title(title or f"Film thickness on {part.name}")
        fig.tight_layout()
        fig.savefig(out, dpi=110)
    finally:
        plt.close(fig)
    return FilePath(out)


def _b64(a, dtype) -> str:
    return base64.b64encode(np.ascontiguousarray(a, dtype=dtype).tobytes()).decode("ascii")


def write_view_html(out, robot, part, thickness, trajectory, path, *, faces=None, postures: int = 4,
                    title: str | None = None) -> FilePath:
    """One self-contained HTML file: the part coloured by thickness (base frame), the path and
    the robot at ``postures`` instants of ``trajectory``; opens offline."""
    from matplotlib import colormaps

    mask = np.ones(len(part.faces), dtype=bool) if faces is None else np.asarray(faces, dtype=bool)
    (lo, hi), used = _limits(thickness, mask, part)
    T = part.T_base_part
    Vb = part.vertices @ T[:3, :3].T + T[:3, 3]
    Nb = part.vertex_normals @ T[:3, :3].T
    cmap = colormaps["viridis"]
    col = cmap(np.clip((np.asarray(thickness) - lo) / (hi - lo), 0, 1))[:, :3]
    col[~used] = 0.6  # faces not painted: grey
    base_inv = np.linalg.inv(robot.base)
    idx = np.unique(np.linspace(0, len(trajectory.t) - 1, max(1, postures)).round().astype(int))
    skel = np.einsum("ij,nkj->nki", base_inv[:3, :3], robot.frames(np.asarray(trajectory.q)[idx])[..., :3, 3])
    skel = skel + base_inv[:3, 3]
    P = path.positions
    on = path.spray[:-1] & path.spray[1:]
    stops = [[float(x), [int(255 * v) for v in cmap(x)[:3]]] for x in np.linspace(0, 1, 9)]
    data = {
        "pos": _b64(Vb, np.float32), "nrm": _b64(Nb, np.float32), "col": _b64(col, np.float32),
        "idx": _b64(part.faces, np.uint32), "nidx": int(part.faces.size),
        "path": _b64(np.stack([P[:-1], P[1:]], axis=1).reshape(-1, 3), np.float32),
        "on": _b64(np.repeat(on, 2), np.uint8), "npath": int(2 * len(on)),
        "robots": [s.tolist() for s in skel], "times": [float(trajectory.t[i]) for i in idx],
        "lo": lo, "hi": hi, "stops": stops, "unit": part.unit,
        "title": title or f"{part.name}: film thickness (um), path and robot {robot.name}",
    }
    from importlib import resources

    template = (resources.files("ik7r.painting") / "data" / "view.html").read_text()
    html = template.replace("/*DATA*/", json.dumps(data))
    fp = FilePath(out)
    fp.write_text(html)
    return fp
