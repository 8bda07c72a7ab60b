"""The one place that knows about numba.

The kernels are written in the subset of Python that numba compiles. When numba is not
importable they run as plain Python (slow, but the same code and the same answers).
Compiled kernels are cached on disk (``cache=True``), so the compile cost is paid once per
installation, not at import time and not per process.
"""

from __future__ import annotations

try:  # pragma: no cover - exercised implicitly
    from numba import njit as _njit

    HAVE_NUMBA = True
except ImportError:  # pragma: no cover
    HAVE_NUMBA = False
    _njit = None


def njit(func):
    """Compile ``func`` lazily with numba (cached, no fastmath), or return it unchanged."""
    if _njit is None:  # pragma: no cover
        return func
    return _njit(cache=True, nogil=True)(func)
