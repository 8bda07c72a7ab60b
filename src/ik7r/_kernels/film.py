"""The compiled film-thickness kernel (numba through :func:`ik7r._jit.njit`).

One loop over the gun poses; per pose, the vertices in the tool frame, an optional depth
buffer of the part seen from the gun tip, and the growth rate of every vertex in the spray
cone times the pose's time weight. Everything it writes is given by the caller.
"""

from __future__ import annotations

import math

from .jit import njit

#: Points closer to the tool's x-y plane than this (length unit) are ignored (behind the tip).
Z_MIN = 1e-9


@njit
def _plane_rate(gun, x, y):
    """The plane model q(x, y) (um/s): gun = [model, h0, peak, p1, p2, p3, p4]."""
    model = int(gun[0])
    peak = gun[2]
    if model == 0:  # gaussian, cut at 5 sigma
        s = gun[3]
        r2 = x * x + y * y
        if r2 > 25.0 * s * s:
            return 0.0
        return peak * math.exp(-r2 / (2.0 * s * s))
    if model == 1:  # beta
        w = 1.0 - (x * x + y * y) / (gun[3] * gun[3])
        if w <= 0.0:
            return 0.0
        return peak * w ** (gun[4] - 1.0)
    u = 1.0 - y * y / (gun[3] * gun[3])  # double-beta: a along y, b along x
    if u <= 0.0:
        return 0.0
    w = 1.0 - x * x / (gun[4] * gun[4] * u)
    if w <= 0.0:
        return 0.0
    return peak * u ** (gun[5] - 1.0) * w ** (gun[6] - 1.0)


@njit
def _raster(zbuf, res, cone, x0, y0, z0, x1, y1, z1, x2, y2, z2):
    """Draw one triangle (screen coordinates X/Z, Y/Z and depths Z) into the depth buffer
    (nearest Z kept; 1/Z interpolated linearly in screen space: exact for a plane)."""
    area = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0)
    if abs(area) < 1e-300:
        return
    pix = 2.0 * cone / res
    lo_x = min(x0, min(x1, x2))
    hi_x = max(x0, max(x1, x2))
    lo_y = min(y0, min(y1, y2))
    hi_y = max(y0, max(y1, y2))
    i0 = max(0, int(math.ceil((lo_x + cone) / pix - 0.5)))
    i1 = min(res - 1, int(math.floor((hi_x + cone) / pix - 0.5)))
    j0 = max(0, int(math.ceil((lo_y + cone) / pix - 0.5)))
    j1 = min(res - 1, int(math.floor((hi_y + cone) / pix - 0.5)))
    w0, w1, w2 = 1.0 / z0, 1.0 / z1, 1.0 / z2
    inv = 1.0 / area
    for j in range(j0, j1 + 1):
        cy = -cone + (j + 0.5) * pix
        for i in range(i0, i1 + 1):
            cx = -cone + (i + 0.5) * pix
            l1 = ((cx - x0) * (y2 - y0) - (x2 - x0) * (cy - y0)) * inv
            l2 = ((x1 - x0) * (cy - y0) - (cx - x0) * (y1 - y0)) * inv
            l0 = 1.0 - l1 - l2
            if l0 < -1e-12 or l1 < -1e-12 or l2 < -1e-12:
                continue
            z = 1.0 / (l0 * w0 + l1 * w1 + l2 * w2)
            k = j * res + i
            if z < zbuf[k]:
                zbuf[k] = z


@njit
def film_kernel(vertices, normals, faces, T_tool_part, weights, gun, cone, occlude, res,
                zbuf, screen, code, thickness):
    """Add the film of every pose to ``thickness``.

    Parameters
    ----------
    vertices, normals : (V, 3) float
        Points and unit normals (part frame).
    faces : (F, 3) int64
        Triangles (occluders).
    T_tool_part : (M, 4, 4) float
        Tool <- part per pose.
    weights : (M,) float
        Time weight of each pose (s; 0 where the spray is off).
    gun : (7,) float
        ``[model, h0, peak, p1, p2, p3, p4]`` (model 0 gaussian, 1 beta, 2 double-beta).
    cone : float
        Half-width of the screen window (tan of the spray's half angle, ``reach / h0``).
    occlude : bool
        Hide points behind the part (depth buffer of ``res`` x ``res`` pixels).
    zbuf : (res * res,) float, work
    screen : (V, 3) float, work: X/Z, Y/Z, Z per vertex
    code : (V,) int8, work: outcode per vertex (0 inside the window)
    thickness : (V,) float, output (um), added to
    """
    nv = vertices.shape[0]
    nf = faces.shape[0]
    h0 = gun[1]
    pix = 2.0 * cone / res
    for m in range(T_tool_part.shape[0]):
        wt = weights[m]
        if wt <= 0.0:
            continue
        A = T_tool_part[m]
        for i in range(nv):
            x = vertices[i, 0]
            y = vertices[i, 1]
            z = vertices[i, 2]
            Z = A[2, 0] * x + A[2, 1] * y + A[2, 2] * z + A[2, 3]
            c = 0
            sx = 0.0
            sy = 0.0
            if Z > Z_MIN:
                sx = (A[0, 0] * x + A[0, 1] * y + A[0, 2] * z + A[0, 3]) / Z
                sy = (A[1, 0] * x + A[1, 1] * y + A[1, 2] * z + A[1, 3]) / Z
                if sx < -cone:
                    c |= 1
                elif sx > cone:
                    c |= 2
                if sy < -cone:
                    c |= 4
                elif sy > cone:
                    c |= 8
            else:
                c = 16
            screen[i, 0] = sx
            screen[i, 1] = sy
            screen[i, 2] = Z
            code[i] = c
        if occlude:
            for k in range(res * res):
                zbuf[k] = math.inf
            for f in range(nf):
                a = faces[f, 0]
                b = faces[f, 1]
                e = faces[f, 2]
                if (code[a] & code[b] & code[e]) != 0 or ((code[a] | code[b] | code[e]) & 16) != 0:
                    continue
                _raster(zbuf, res, cone, screen[a, 0], screen[a, 1], screen[a, 2],
                        screen[b, 0], screen[b, 1], screen[b, 2], screen[e, 0], screen[e, 1], screen[e, 2])
        for i in range(nv):
            if code[i] != 0:
                continue
            sx = screen[i, 0]
            sy = screen[i, 1]
            Z = screen[i, 2]
            X = sx * Z
            Y = sy * Z
            d = math.sqrt(X * X + Y * Y + Z * Z)
            nx = A[0, 0] * normals[i, 0] + A[0, 1] * normals[i, 1] + A[0, 2] * normals[i, 2]
            ny = A[1, 0] * normals[i, 0] + A[1, 1] * normals[i, 1] + A[1, 2] * normals[i, 2]
            nz = A[2, 0] * normals[i, 0] + A[2, 1] * normals[i, 1] + A[2, 2] * normals[i, 2]
            cos_a = -(nx * X + ny * Y + nz * Z) / d
            if cos_a <= 0.0:
                continue
            q = _plane_rate(gun, h0 * sx, h0 * sy)
            if q <= 0.0:
                continue
            cos_g = Z / d
            if occlude:
                px = min(res - 1, max(0, int((sx + cone) / pix)))
                py = min(res - 1, max(0, int((sy + cone) / pix)))
                zb = zbuf[py * res + px]
                # slope-scaled bias: the point's own surface changes depth across ~1.5 pixels
                slope = math.sqrt(nx * nx + ny * ny) * cos_g / max(cos_a, 0.02)
                if Z > zb * (1.0 + 1e-4 + 1.5 * pix * slope):
                    continue
            thickness[i] += wt * q * (h0 / d) ** 2 * cos_a / (cos_g * cos_g * cos_g)
