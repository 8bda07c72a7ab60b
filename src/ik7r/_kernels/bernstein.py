"""The Bernstein tables of the residual's certified root isolation (:mod:`.poly`), in plain
numpy: computed once per degree in exact rational arithmetic. Apart from the kernels so that
a call into the compiled module (:mod:`.aot`) needs no numba."""

from __future__ import annotations

import math
from fractions import Fraction
from functools import cache

import numpy as np

from . import params as L


@cache
def bernstein_matrices(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Matrices mapping values at the Chebyshev-Lobatto points ``x_j = cos(pi j / n)`` to
    (Chebyshev coefficients, Bernstein coefficients on [-1, 1]) of the interpolant of
    degree n. Computed once in exact rational arithmetic (the Bernstein part)."""
    j = np.arange(n + 1)
    C = np.cos(np.pi * np.outer(j, j) / n) * (2.0 / n)
    C[:, 0] *= 0.5
    C[:, n] *= 0.5
    C[0, :] *= 0.5
    C[n, :] *= 0.5
    # Bernstein coefficients (on t in [0, 1], x = 2 t - 1) of each Chebyshev polynomial T_k
    TB = np.zeros((n + 1, n + 1))
    prev = [Fraction(1)]  # T_0 in powers of t
    cur = [Fraction(-1), Fraction(2)]  # T_1 = 2 t - 1
    polys = [prev, cur]
    for _ in range(2, n + 1):
        nxt = [Fraction(0)] * (len(cur) + 1)
        for i, c in enumerate(cur):  # 2 x T_k with x = 2 t - 1
            nxt[i] += -2 * c
            nxt[i + 1] += 4 * c
        for i, c in enumerate(prev):
            nxt[i] -= c
        prev, cur = cur, nxt
        polys.append(cur)
    binom = [math.comb(n, i) for i in range(n + 1)]
    for k in range(n + 1):
        m = polys[k] + [Fraction(0)] * (n + 1 - len(polys[k]))
        for i in range(n + 1):
            s = Fraction(0)
            for jj in range(i + 1):
                s += Fraction(math.comb(i, jj), binom[jj]) * m[jj]
            TB[i, k] = float(s)
    return np.ascontiguousarray(C), np.ascontiguousarray(TB @ C)


@cache
def _bernstein_tables(n: int) -> tuple[np.ndarray, float]:
    _, Bm = bernstein_matrices(n)
    return Bm, float(np.abs(Bm).sum(axis=1).max())


def bernstein_tables(K: np.ndarray) -> tuple[np.ndarray, float]:
    """``(Bm, bnorm)`` for the residual degree of ``K``: the matrix from values at the
    Chebyshev-Lobatto points to Bernstein coefficients, and its infinity norm."""
    return _bernstein_tables(int(K[L.NCHEB]))
