"""The one place that knows about numba.

The kernels are written in the subset of Python that numba compiles. When numba is not
importable they run as plain Python (slow, but the same code and the same answers).
Compiled kernels are cached on disk (``cache=True``), so the compile cost is paid once per
installation, not at import time and not per process. The entry points of a typical session
are also compiled at installation into an extension module (:mod:`.aot`), which then answers
without numba; this JIT is its fallback and compiles everything else.

Two things happen here beside compiling:

- **A notice before a compile.** An entry point called from Python whose numba cache index
  does not exist yet (a fresh installation, or an edited kernel file) is about to compile:
  one line on stderr says what, roughly how long it takes and that it happens once
  (``IK7R_QUIET=1`` silences it). Detecting this costs a look at the entry point's cache
  index (exists, and written for this source) on the first call of each entry point of a
  process (when numba looks for a compiled version), nothing afterwards.
- **One stamp for all the kernel sources.** numba's cache of a kernel is keyed by the source
  file that defines it, while the code it holds includes every kernel it calls, from other
  files: an edit to ``complete.py`` left the cached ``select.ik_all_one`` running the old solver,
  silently. The kernels are cached with one stamp, a hash of every kernel source
  (:data:`ik7r._kernels.aot.SOURCES`, the files the compiled module's stamp covers too), so an
  edit to any of them recompiles every kernel on its next use (:func:`sources_stamp`).
- **One specialisation per kernel.** numba compiles a kernel called from another kernel once
  per distinct argument *type*, and a constant argument (``polish(q, T, K, 30)``, a count
  that starts at ``0``, ``True``) has its own literal type: the same kernel was compiled
  three or four times, each time with everything it calls. Calls from kernels are typed
  with the literal types widened (``int64``, ``bool``), except for the parameters in
  :data:`LITERAL_PARAMETERS`, which select a variant at compile time on purpose.
"""

from __future__ import annotations

import functools
import hashlib
import os
import sys
from typing import Any

#: ``IK7R_JIT=0`` runs the kernels as plain Python without importing numba: the command line
#: sets it for one-shot commands (``ik7r fk``, ``ik7r ik``), where numba's start-up (about 0.5 s)
#: costs more than solving one pose in Python.
JIT_ENABLED = os.environ.get("IK7R_JIT", "1") != "0"

#: Parameters whose constant value picks a variant of the kernel at compile time (numba prunes
#: the branches of the other): ``kind``, the residual of :mod:`ik7r._kernels.poly` (0 general, 1 with
#: theta1 fixed). Every other constant argument is widened to its plain type.
LITERAL_PARAMETERS = frozenset({"kind"})

#: Rough first-compile times (s, 2 cores) of the entry points a first call compiles, with
#: everything they call: what the notice says.
COMPILE_SECONDS = {"fk_batch": 5, "fk_user": 5, "ik_all_one": 60, "ik_one": 60, "all_rows": 60,
                   "config_rows": 60, "track_path": 60}  # measured 44-55 CPU s for ik_all_one

_njit: Any = None
if JIT_ENABLED:
    try:  # pragma: no cover - exercised implicitly
        from numba import njit as _njit
    except ImportError:  # pragma: no cover
        _njit = None


def sources_stamp(paths) -> bytes:
    """A hash of the contents of the files ``paths`` (in the order given), remembered while
    each file's modification time and size stay the same: the one source stamp of every
    cached kernel defined in one of them."""
    key = []
    for path in paths:
        st = os.stat(path)
        key.append((str(path), st.st_mtime_ns, st.st_size))
    key_t = tuple(key)
    if key_t not in _stamps:
        h = hashlib.sha256()
        for path, _, _ in key_t:
            h.update(path.encode())
            with open(path, "rb") as f:
                h.update(f.read())
        _stamps[key_t] = h.digest()
    return _stamps[key_t]


_stamps: dict[tuple, bytes] = {}


@functools.lru_cache(maxsize=1)
def _kernel_sources() -> tuple[str, ...]:
    from . import aot  # (its SOURCES: the kernel modules and the files compiled into them)

    return tuple(os.path.realpath(aot.HERE / name) for name in aot.SOURCES)


class _AllKernelSources:
    """Mixed into each of numba's source-file cache locators: for a function defined in a
    kernel source, the cache's source stamp is :func:`sources_stamp` of all of them (numba's
    own is its file's alone); other functions are left to numba's locators."""

    @classmethod
    def from_function(cls, py_func, py_file):
        if os.path.realpath(py_file) not in _kernel_sources():
            return None
        return super().from_function(py_func, py_file)

    def get_source_stamp(self):
        return sources_stamp(_kernel_sources())


def _install_locators() -> None:
    """Put a locator with :class:`_AllKernelSources` before each of numba's source-file
    locators (the same cache folders, one stamp). A numba without that layout keeps its own
    (per-file stamps)."""
    try:
        from numba.core import caching

        # (named _CacheImpl before numba 0.61)
        impl: Any = getattr(caching, "CacheImpl", None) or getattr(caching, "_CacheImpl", None)
        locators = impl._locator_classes
        bases = [c for c in locators if issubclass(c, caching._SourceFileBackedLocatorMixin)]
    except (ImportError, AttributeError):  # pragma: no cover - another numba
        return
    locators[0:0] = [type(f"Kernels{c.__name__}", (_AllKernelSources, c), {"__module__": __name__})
                       for c in bases]


if _njit is not None:
    _install_locators()

_announced: set[str] = set()


def _cache_is_cold(dispatcher) -> bool:
    """Whether ``dispatcher``'s first call compiles: no numba cache index on disk, or one
    written for another version of its source file (numba then recompiles)."""
    cache = getattr(dispatcher, "_cache", None)
    index: Any = getattr(cache, "_cache_file", None)
    try:
        if not os.path.exists(index._index_path):
            return True
        return not index._load_index()  # empty when the source stamp or numba's version differ
    except Exception:  # pragma: no cover - another numba cache layout: say nothing
        return False


def compile_notice(name: str) -> str:
    """The line printed before entry point ``name`` compiles."""
    seconds = COMPILE_SECONDS.get(name, 10)
    return (f"ik7r: compiling the numba kernels of {name} (about {seconds} s on 2 cores); this happens "
            "once per installation, later runs load them from the cache")


def _with_notice(dispatcher):
    """Print :func:`compile_notice` on stderr before ``dispatcher``'s first compile from Python."""
    compile_for_args = dispatcher._compile_for_args
    name = dispatcher.py_func.__name__

    def _compile_for_args(*args, **kws):
        if (name not in _announced and _cache_is_cold(dispatcher)
                and os.environ.get("IK7R_QUIET", "") in ("", "0")):
            _announced.add(name)
            print(compile_notice(name), file=sys.stderr, flush=True)
        return compile_for_args(*args, **kws)

    dispatcher._compile_for_args = _compile_for_args  # the call path of a missing overload
    return dispatcher


def _widened(dispatcher):
    """Type calls from other kernels with their literal argument types widened (except the
    :data:`LITERAL_PARAMETERS`), so each kernel is compiled once for its plain types."""
    from numba.core import types

    get_call_template = dispatcher.get_call_template
    code = dispatcher.py_func.__code__
    names = code.co_varnames[:code.co_argcount]
    keep = [n in LITERAL_PARAMETERS for n in names]

    def widened_call_template(args, kws):
        args = tuple(a if (i < len(keep) and keep[i]) else types.unliteral(a) for i, a in enumerate(args))
        kws = {k: (v if k in LITERAL_PARAMETERS else types.unliteral(v)) for k, v in kws.items()}
        return get_call_template(args, kws)

    dispatcher.get_call_template = widened_call_template
    return dispatcher


_shared: set = set()


def shared(func):
    """Let the kernels call ``func``, a plain function over numpy operations written outside the
    kernels for numpy arrays (the one wrap, the one indicator rule of :mod:`ik7r.geometry`), and
    return it unchanged: with numba it is registered (``numba.extending.register_jitable``) and
    compiled into every kernel that calls it, on scalars; without numba the kernels call it as it
    is. One source, so numpy code and the kernels give the same bits. It must compile as numba
    code for scalars (no allocation) and stay numba-free itself, so that the modules that define
    it import without numba."""
    if _njit is not None and func not in _shared:
        from numba.extending import register_jitable

        register_jitable(func)
        _shared.add(func)
    return func


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
    return _with_notice(_widened(_njit(**options)(func)))
