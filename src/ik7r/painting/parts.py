"""Workpieces to paint: triangle meshes loaded with trimesh (STL, OBJ, PLY) or built in by name.

A :class:`Part` holds its vertices in the **part frame** and in the **robot's length unit**
(the file's unit is converted on loading), and ``T_base_part``, the part frame in the robot's
base frame. Two parts are built in (:data:`BUILTIN_PARTS`), generated exactly from formulas:

``"panel"``
    a flat 500 x 600 mm plate in the part's x-y plane, its painted side +z;
``"hood"``
    a doubly curved panel like a car hood: 700 mm long (x), 500 mm wide at the back tapering
    to 400 mm at the front (y), crowned (radii of curvature 1500 mm along x and 1000 mm along
    y, so 41 mm of sag at the ends and 31 mm at the sides), painted side +z.

Both are placed by default at ``(1100, 0, 0)`` mm in the base frame, axes of the base
(:data:`DEFAULT_PART_ORIGIN`), where the paper robot and the IRB 5400 paint them from above at
a 200 mm standoff in configuration 1.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path as FilePath

import numpy as np

from ..errors import PartFileError
from ..geometry.checks import check_transforms
from ..geometry.rotations import transform
from ..units import unit_scale

__all__ = ["Part", "load_part", "builtin_part", "BUILTIN_PARTS", "DEFAULT_PART_ORIGIN", "MESH_SUFFIXES"]

#: Mesh file types read by :func:`load_part`.
MESH_SUFFIXES = (".stl", ".obj", ".ply")
#: Where the built-in parts are placed by default in the base frame (mm, converted to the unit).
DEFAULT_PART_ORIGIN = (1100.0, 0.0, 0.0)


@dataclass(frozen=True, eq=False)
class Part:
    """A triangle mesh in its part frame, placed in the robot's base frame (immutable).

    Attributes
    ----------
    vertices : ndarray, shape (V, 3)
        Vertex positions in the part frame, in ``unit``.
    faces : ndarray, shape (F, 3), int
        Vertex indices of each triangle (counter-clockwise seen from the side its normal
        points to).
    T_base_part : ndarray, shape (4, 4)
        The part frame in the robot's base frame (translation in ``unit``).
    name : str
    unit : str
        Length unit of ``vertices`` (the robot's).
    file_unit : str
        The unit the part was given in (``thickness.csv`` is written in it).
    """

    vertices: np.ndarray
    faces: np.ndarray
    T_base_part: np.ndarray
    name: str = "part"
    unit: str = "mm"
    file_unit: str = "mm"

    def __post_init__(self) -> None:
        V = np.array(self.vertices, dtype=float)
        F = np.array(self.faces)
        if V.ndim != 2 or V.shape[1] != 3 or len(V) < 3:
            raise ValueError(f"{self.name}: vertices must have shape (V, 3) with V >= 3; got {V.shape}")
        if not np.all(np.isfinite(V)):
            raise ValueError(f"{self.name}: vertices must be finite; got NaN or infinity")
        if F.ndim != 2 or F.shape[1] != 3 or len(F) == 0 or F.dtype.kind not in "iu":
            raise ValueError(f"{self.name}: faces must be integers of shape (F, 3) with F >= 1; "
                             f"got shape {F.shape}, dtype {F.dtype}")
        if F.min() < 0 or F.max() >= len(V):
            raise ValueError(f"{self.name}: face indices must lie in [0, {len(V) - 1}]")
        T = check_transforms(self.T_base_part, "T_base_part")
        if T.shape != (4, 4):
            raise ValueError(f"T_base_part must have shape (4, 4); got {T.shape}")
        unit_scale(self.unit, self.file_unit)  # both known
        F = F.astype(np.int64)
        for a in (V, F, T):
            a.setflags(write=False)
        object.__setattr__(self, "vertices", V)
        object.__setattr__(self, "faces", F)
        object.__setattr__(self, "T_base_part", T)

    @property
    def triangles(self) -> np.ndarray:
        """Corner positions ``(F, 3, 3)`` (part frame)."""
        return self.vertices[self.faces]

    @property
    def face_normals(self) -> np.ndarray:
        """Unit normals ``(F, 3)`` (right-hand rule on the corner order); 0 for degenerate faces."""
        tri = self.triangles
        n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        norm = np.linalg.norm(n, axis=1, keepdims=True)
        return np.divide(n, norm, out=np.zeros_like(n), where=norm > 0)

    @property
    def face_areas(self) -> np.ndarray:
        """Triangle areas ``(F,)`` (unit squared)."""
        tri = self.triangles
        return 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)

    def vertex_areas(self, faces=None) -> np.ndarray:
        """Area per vertex ``(V,)``: a third of each adjacent face's (of ``faces``, a boolean
        mask over the faces, default all), so the areas add up to the faces' total."""
        A = self.face_areas if faces is None else np.where(faces, self.face_areas, 0.0)
        out = np.zeros(len(self.vertices))
        np.add.at(out, self.faces.reshape(-1), np.repeat(A / 3.0, 3))
        return out

    @property
    def vertex_normals(self) -> np.ndarray:
        """Area-weighted unit vertex normals ``(V, 3)``."""
        n = np.cross(self.triangles[:, 1] - self.triangles[:, 0], self.triangles[:, 2] - self.triangles[:, 0])
        out = np.zeros_like(self.vertices)
        for k in range(3):
            np.add.at(out, self.faces[:, k], n)
        return _unit_rows(out)

    @property
    def bounds(self) -> np.ndarray:
        """``[[xmin, ymin, zmin], [xmax, ymax, zmax]]`` (part frame)."""
        return np.array([self.vertices.min(axis=0), self.vertices.max(axis=0)])

    def placed(self, T_base_part) -> Part:
        """The same part at another place in the base frame."""
        return Part(self.vertices, self.faces, T_base_part, self.name, self.unit, self.file_unit)

    def to_trimesh(self):
        """A :class:`trimesh.Trimesh` of the part (part frame, ``unit``), not processed."""
        import trimesh

        return trimesh.Trimesh(self.vertices.copy(), self.faces.copy(), process=False)


def _unit_rows(v: np.ndarray) -> np.ndarray:
    n = np.linalg.norm(v, axis=-1, keepdims=True)
    return np.divide(v, n, out=np.zeros_like(v), where=n > 0)


# ----------------------------------------------------------------------------- loading
def load_part(source, *, unit: str = "mm", part_unit: str | None = None, T_base_part=None) -> Part:
    """A part from a built-in name or a mesh file (STL, OBJ, PLY), in ``unit``.

    Parameters
    ----------
    source : str or Path
        A name of :data:`BUILTIN_PARTS` or a mesh file.
    unit : str
        Length unit of the result (the robot's): ``m``, ``cm``, ``mm`` or ``in``.
    part_unit : str, optional
        Length unit of the file's coordinates (default ``unit``; the built-in parts are in mm).
    T_base_part : array_like, shape (4, 4), optional
        Part frame in the base frame (translation in ``unit``). Default: the built-in part's
        placement (:data:`DEFAULT_PART_ORIGIN`), or the base frame itself for a file.

    Raises
    ------
    FileNotFoundError
        No such file (and not a built-in name).
    PartFileError
        The file is not a triangle mesh, is empty, has no faces or non-finite vertices; the
        message names the file.
    """
    if isinstance(source, str) and source in BUILTIN_PARTS:
        if part_unit not in (None, "mm"):
            raise ValueError(f"the built-in part {source!r} is defined in mm; a part unit "
                             f"({part_unit!r}) applies to mesh files")
        return builtin_part(source, unit=unit, T_base_part=T_base_part)
    fp = FilePath(source)
    if not fp.is_file():
        raise FileNotFoundError(f"no such part file: {fp} (built-in parts: {', '.join(BUILTIN_PARTS)})")
    if fp.suffix.lower() not in MESH_SUFFIXES:
        raise PartFileError(f"{fp}: unknown mesh type {fp.suffix!r}; expected {', '.join(MESH_SUFFIXES)}")
    file_unit = unit if part_unit is None else part_unit
    scale = unit_scale(file_unit, unit)
    V, F = _read_mesh(fp)
    T = np.eye(4) if T_base_part is None else T_base_part
    return Part(V * scale, F, T, fp.name, unit, file_unit)


def _read_mesh(fp: FilePath) -> tuple[np.ndarray, np.ndarray]:
    import trimesh

    if fp.stat().st_size == 0:
        raise PartFileError(f"{fp}: empty file; expected a triangle mesh (STL, OBJ or PLY)")
    try:
        loaded = trimesh.load(str(fp), file_type=fp.suffix.lower()[1:], force="mesh", process=False)
    except Exception as exc:  # trimesh raises many kinds on garbage: all mean "not a mesh"
        raise PartFileError(f"{fp}: not a readable {fp.suffix[1:].upper()} mesh ({exc})") from exc
    V = np.asarray(getattr(loaded, "vertices", np.empty((0, 3))), dtype=float)
    F = np.asarray(getattr(loaded, "faces", np.empty((0, 3))))
    if F.ndim != 2 or len(F) == 0 or len(V) == 0:
        raise PartFileError(f"{fp}: no faces ({len(V)} vertices kept); a part must be a triangle mesh "
                            f"(STL, OBJ or PLY)")
    if not np.all(np.isfinite(V)):
        bad = int(np.flatnonzero(~np.all(np.isfinite(V), axis=1))[0])
        raise PartFileError(f"{fp}: vertex {bad} is not finite ({V[bad].tolist()})")
    F = F.astype(np.int64)
    if F.min() < 0 or F.max() >= len(V):
        raise PartFileError(f"{fp}: face indices outside [0, {len(V) - 1}]")
    return V, F


# ----------------------------------------------------------------------------- built-in parts
def _grid_faces(nu: int, nv: int) -> np.ndarray:
    """Two counter-clockwise triangles per cell of an ``nu x nv`` vertex grid (index i*nv + j)."""
    i, j = np.meshgrid(np.arange(nu - 1), np.arange(nv - 1), indexing="ij")
    a = (i * nv + j).reshape(-1)
    b, c, d = a + nv, a + nv + 1, a + 1
    return np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])


def _panel(cell: float) -> tuple[np.ndarray, np.ndarray]:
    L, W = 500.0, 600.0
    nu, nv = int(math.ceil(L / cell)) + 1, int(math.ceil(W / cell)) + 1
    x, y = np.meshgrid(np.linspace(-L / 2, L / 2, nu), np.linspace(-W / 2, W / 2, nv), indexing="ij")
    return np.column_stack([x.ravel(), y.ravel(), np.zeros(x.size)]), _grid_faces(nu, nv)


def _hood(cell: float) -> tuple[np.ndarray, np.ndarray]:
    L, W_back, W_front, Rx, Ry = 700.0, 500.0, 400.0, 1500.0, 1000.0
    nu, nv = int(math.ceil(L / cell)) + 1, int(math.ceil(W_back / cell)) + 1
    s, t = np.meshgrid(np.linspace(-0.5, 0.5, nu), np.linspace(-0.5, 0.5, nv), indexing="ij")
    x = s * L
    y = t * (W_back + (W_front - W_back) * (s + 0.5))  # back (x = -L/2) wide, front narrow
    z = (np.sqrt(Rx ** 2 - x ** 2) - Rx) + (np.sqrt(Ry ** 2 - y ** 2) - Ry)
    return np.column_stack([x.ravel(), y.ravel(), z.ravel()]), _grid_faces(nu, nv)


#: Built-in parts: name -> (generator of (vertices mm, faces) from a cell size, description).
BUILTIN_PARTS = {
    "panel": (_panel, "flat panel 500 x 600 mm, painted side +z"),
    "hood": (_hood, "doubly curved hood 700 x 500..400 mm, crown radii 1500 and 1000 mm, painted side +z"),
}


def builtin_part(name: str, *, unit: str = "mm", T_base_part=None, cell: float = 10.0) -> Part:
    """A built-in part (see the module docstring) with mesh cells of about ``cell`` mm."""
    if name not in BUILTIN_PARTS:
        raise ValueError(f"unknown built-in part {name!r}; expected one of {', '.join(BUILTIN_PARTS)}")
    if not (math.isfinite(cell) and cell > 0):
        raise ValueError(f"cell must be a positive length in mm; got {cell!r}")
    V, F = BUILTIN_PARTS[name][0](float(cell))
    s = unit_scale("mm", unit)
    T = transform(np.eye(3), np.asarray(DEFAULT_PART_ORIGIN) * s) if T_base_part is None else T_base_part
    return Part(V * s, F, T, name, unit, unit)
