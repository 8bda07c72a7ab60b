"""The one place that knows about numba.

The kernels are written in the subset of Python that numba compiles. When numba is not
importable they run as plain Python (slow, but the same code and the same answers).
Compiled kernels are cached on disk (``cache=True``), so the compile cost is paid once per
installation, not at import time and not per process.
"""

from __future__ import annotations

import os

#: ``IK7R_JIT=0`` runs the kernels as plain Python without importing numba: the command line
#: sets it for one-shot commands (``ik7r fk``, ``ik7r ik``), where numba's start-up (about 0.5 s)
#: costs more than solving one pose in Python.
JIT_ENABLED = os.environ.get("IK7R_JIT", "1") != "0"

_njit = None
if JIT_ENABLED:
    try:  # pragma: no cover - exercised implicitly
        from numba import njit as _njit

    except ImportError:  # pragma: no cover
        _njit = None


def njit(func=None, *, vector=False, allocates=False):
    """Compile ``func`` lazily with numba (cached, no fastmath), or return it unchanged.

    Kernels work on arrays their caller owns (and views of them), so they are compiled
    without numba's reference counting (its ``_nrt`` target option), whose atomic increments
    and decrements on every view and call otherwise cost about a quarter of the solver's time.
    A kernel that creates an array (``np.empty``...) or copies one by slice assignment says
    ``@njit(allocates=True)``; numba refuses to compile one that does so without it, or that
    returns an array it was not given.

    ``@njit(vector=True)``: a loop over independent samples that the compiler should turn into
    SIMD code. Float division by zero then gives inf or nan (numpy's rule) instead of raising,
    as the check would keep the loop scalar; such a function must not divide by zero.
    """
    if func is None:
        return lambda f: njit(f, vector=vector, allocates=allocates)
    if _njit is None:  # pragma: no cover
        return func
    # (_nrt is explicit either way: a callee would inherit its caller's otherwise)
    options = {"cache": True, "nogil": True, "_nrt": bool(allocates)}
    if vector:
        options["error_model"] = "numpy"
    return _njit(**options)(func)
