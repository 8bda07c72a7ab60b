"""The kernels compiled ahead of time into an extension module, from the same source.

The entry points of a typical session (``fk``, ``ik``, ``ik_all``, their batch forms, paths and
the pose checks) are compiled once, at installation (``make`` runs ``python -m
ik7r._kernels.aot``), by numba's ``pycc`` from the very functions the JIT compiles, into
``_compiled`` (a shared library next to this file). A process that finds it calls it without
importing numba: its first answer costs loading a shared library (milliseconds) instead of
numba's start-up and cache load (about 0.5 s), and a fresh installation never compiles on
first use. Without the module (not built, no C compiler, or built from other sources) the
numba JIT compiles the kernels on first use, as before; the answers are the same bit for bit
(``tests/kernels/test_aot.py``).

The module is used only when its stamp (:func:`source_stamp`: a hash of the kernel sources, the
numpy version and the processor it was built for) matches the running code, so an edited
kernel never runs stale compiled code. ``IK7R_AOT=0`` ignores the module (the JIT compiles);
``IK7R_JIT=0`` runs the kernels as plain Python and ignores it too.

The compiled functions take exactly the argument types of :data:`SIGNATURES` (C-contiguous
float64 arrays of the given dimension, bool and int64 arrays where named): unlike a numba
dispatcher they do not check what they are given. They are reached only through
``ik7r._kernels``, from the functions of :mod:`ik7r.ik` and :class:`ik7r.robot.model.Robot`,
which validate their input and build every array they pass.
"""

from __future__ import annotations

import hashlib
import importlib
import json
import os
import platform
import sys
import time
from pathlib import Path
from typing import Any

#: The extension module's name (``ik7r._kernels._compiled``) and its stamp file.
MODULE = "_compiled"
HERE = Path(__file__).resolve().parent
STAMP_FILE = HERE / f"{MODULE}.json"

#: Each compiled entry point: (kernel module, argument types, return type). Types: ``f8`` a
#: float, ``i8`` an int, ``b1`` a bool, ``none`` no value; ``"f8[2]"`` a C-contiguous float64
#: array of 2 dimensions, ``"f8[2]r"`` one typed read-only; ``(i8, b1)`` a tuple. The compiled
#: function takes any array of that dtype and dimension, writable or not, and the kernel docstrings
#: say which it writes. An array is typed as the public API passes it: writable, except the
#: robot's parameter vector ``K`` (read-only), because numba types a read-only array apart and
#: compiles a kernel again for each mix. So the solver (``complete.solve_into``) and everything
#: below it is compiled once for every entry point that calls it (35-60 CPU s each time; the
#: build records how many, ``tests/kernels/test_aot.py`` wants one), and the kernels the build
#: leaves in numba's cache are the very ones the JIT fallback, and the tests that compare it with
#: this module, call.
SIGNATURES: dict[str, tuple[str, tuple[str, ...], Any]] = {
    "fk_batch": ("fk", ("f8[2]", "f8[1]r", "f8[3]"), "none"),
    "frames_batch": ("fk", ("f8[2]", "f8[1]r", "f8[4]"), "none"),
    "validate_pose": ("validate", ("f8[2]", "f8", "f8[2]", "f8[2]"), "i8"),
    "validate_poses": ("validate", ("f8[3]", "f8", "f8[3]", "i1[1]"), "i8"),
    "ik_all_one": ("select", ("f8[2]", "f8", "f8[1]r", "f8[2]", "f8", "f8[1]", "b1", "b1", "f8[2]",
                              "f8[2]"), ("i8", "i8")),
    "ik_one": ("select", ("f8[2]", "f8", "f8[1]r", "f8[2]", "f8", "i8", "i8", "i8", "f8[1]", "b1", "b1",
                          "f8[2]", "f8[1]"), ("i8", "b1")),
    "config_rows": ("select", ("f8[3]", "f8[1]r", "f8[2]", "f8", "i8", "i8", "i8", "f8[2]", "b1", "b1",
                               "b1[1]", "f8[2]", "b1[1]"), "none"),
    "all_rows": ("select", ("f8[3]", "f8[1]r", "f8[2]", "f8", "b1[1]", "f8[3]", "i8[1]"), "none"),
    "count_within_limits": ("select", ("f8[2]", "i8", "f8[1]r"), "i8"),
    "expand_within_limits": ("select", ("f8[2]", "i8", "f8[1]r", "f8[2]"), "i8"),
    "track_path": ("track", ("f8[3]", "f8[1]r", "f8[2]", "f8", "i8", "i8", "i8", "f8[1]", "b1", "b1", "f8",
                             "b1[1]", "f8[2]", "b1[1]", "b1[1]"), "i8"),
}

#: Source files whose code (or constants) the compiled module holds: every kernel module (this
#: one's :data:`SIGNATURES` enter the stamp by value) and the family's joint-angle bound. The
#: JIT's cache of every kernel is stamped with a hash of the same files (:mod:`.jit`).
SOURCES = sorted([*(p.name for p in HERE.glob("*.py") if p.name not in ("__init__.py", "aot.py")),
                  "../robot/family.py", "../geometry/rotations.py", "../geometry/configs.py"])
# (family.py and the two geometry modules hold functions compiled into the kernels: the family's
# constants, the one wrap and the one indicator rule, see jit.shared)


def _cpu() -> str:
    """The processor the module is built for (it is compiled for the host's instruction set)."""
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            lines = []
            for line in f:
                if line.startswith(("model name", "flags")):
                    lines.append(line.strip())
                if len(lines) == 2:
                    break
            return "\n".join(lines)
    except OSError:
        return platform.machine() + platform.processor()


def source_stamp() -> str:
    """Hash of what the compiled module was built from: the kernel sources, the numpy version
    (its C interface), the Python version and the processor."""
    import numpy as np

    h = hashlib.sha256()
    for name in SOURCES:
        h.update(name.encode())
        h.update((HERE / name).read_bytes())
    h.update(f"{np.__version__}|{sys.version}|{_cpu()}|{sorted(SIGNATURES.items())}".encode())
    return h.hexdigest()


_LOADED: list[Any] = []


def load() -> Any:
    """The compiled module, or None: not built, built from other sources, or turned off
    (``IK7R_AOT=0``, ``IK7R_JIT=0``). Checked once per process."""
    if _LOADED:
        return _LOADED[0]
    module = None
    if os.environ.get("IK7R_AOT", "1") != "0" and os.environ.get("IK7R_JIT", "1") != "0":
        try:
            stamp = json.loads(STAMP_FILE.read_text(encoding="utf-8"))["stamp"]
        except (OSError, ValueError, KeyError, TypeError):
            stamp = None
        if stamp is not None and stamp == source_stamp():
            try:
                module = importlib.import_module(f"{__package__}.{MODULE}")
            except ImportError:  # pragma: no cover - a broken build: the JIT compiles instead
                module = None
    _LOADED.append(module)
    return module


def info() -> dict[str, Any]:
    """What the stamp file says of the build (``{}`` when there is none)."""
    try:
        return json.loads(STAMP_FILE.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {}


# ---------------------------------------------------------------------------- the build


def _numba_type(spec):
    from numba import types

    if isinstance(spec, tuple):
        return types.Tuple(tuple(_numba_type(s) for s in spec))
    scalars = {"f8": types.float64, "i8": types.int64, "i1": types.int8, "b1": types.boolean,
               "none": types.none}
    if "[" not in spec:
        return scalars[spec]
    dtype, rest = spec.split("[")
    ndim = int(rest[0])
    return types.Array(scalars[dtype], ndim, "C", readonly=rest.endswith("r"))


def build(output_dir: Path = HERE, names: list[str] | None = None) -> dict[str, Any]:
    """Compile the entry points (all of :data:`SIGNATURES`, or ``names``) into the extension
    module in ``output_dir`` and write its stamp; returns the stamp's record.

    Each entry point is compiled with the options its ``@njit`` gives the JIT (no reference
    counting unless it allocates, the numpy error model of vector loops) and releases the GIL
    as the JIT's ``nogil`` does (the batch functions run it in threads); the kernels it calls
    are compiled as the JIT compiles them, for the host processor. Every kernel is compiled
    afresh (one loaded from numba's cache has no code to link into the module) and saved to
    numba's cache as the JIT would save it, so the build leaves the JIT's cache warm too: the
    fallback and the kernels the module calls from the JIT's side (none at run time) start
    compiled. Run it in a process of its own (see :func:`main`).
    """
    import numba.pycc.compiler as pycc_compiler
    from numba.pycc import CC

    t0, c0 = time.perf_counter(), time.process_time()
    names = list(SIGNATURES) if names is None else names
    # numba's cache is keyed by each kernel's own source file, not by the files of the kernels it
    # calls: a cached select.all_rows would keep an edited complete.solve_into compiled into it.
    # Every kernel is compiled afresh here, so the stale entries go first (the JIT's other
    # signatures are compiled again on first use, from the current sources)
    for stale in [*HERE.glob("__pycache__/*.nbi"), *HERE.glob("__pycache__/*.nbc")]:
        stale.unlink(missing_ok=True)
    stamp_path = Path(output_dir) / STAMP_FILE.name
    stamp_path.unlink(missing_ok=True)  # no stale stamp beside a half-built module
    dispatchers = {}
    cc = CC(MODULE, source_module="ik7r._kernels.aot")
    cc.output_dir = str(output_dir)
    cc.target_cpu = "host"  # what the JIT compiles for
    for name in names:
        module, args, ret = SIGNATURES[name]
        dispatcher = getattr(importlib.import_module(f"{__package__}.{module}"), name)
        dispatchers[dispatcher.py_func] = dispatcher
        sig = _numba_type(ret)(*(_numba_type(a) for a in args))
        cc.export(name, sig)(dispatcher.py_func)

    from numba.core.registry import CPUDispatcher

    for mod in [m for n, m in sys.modules.items() if n.startswith(f"{__package__}.")]:
        for value in vars(mod).values():
            cache = getattr(value, "_cache", None) if isinstance(value, CPUDispatcher) else None
            if cache is not None:
                cache.load_overload = lambda sig, target_context: None  # compile, then save as usual

    compile_extra = pycc_compiler.compile_extra

    def compile_as_jit(typingctx, targetctx, func, args, return_type, flags, locals, **kws):
        options = dispatchers[func].targetoptions
        flags = flags.copy()
        flags.release_gil = True
        flags.nrt = bool(options.get("_nrt", True))
        if "error_model" in options:
            flags.error_model = options["error_model"]
        return compile_extra(typingctx, targetctx, func, args, return_type, flags, locals, **kws)

    pycc_compiler.compile_extra = compile_as_jit
    try:
        cc.compile()
    finally:
        pycc_compiler.compile_extra = compile_extra
    import numba

    from .complete import solve_into

    record = {"stamp": source_stamp(), "entry_points": names, "numba": numba.__version__,
              # the solver's typings compiled (one when its callers pass it the same types)
              "solver_compiles": len(solve_into.overloads),
              "seconds": round(time.perf_counter() - t0, 1),
              "cpu_seconds": round(time.process_time() - c0, 1),
              "built": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())}
    tmp = stamp_path.with_suffix(".tmp")
    tmp.write_text(json.dumps(record, indent=1) + "\n", encoding="utf-8")
    os.replace(tmp, stamp_path)
    return record


def main(argv: list[str] | None = None) -> int:
    """``python -m ik7r._kernels.aot [--if-stale]``: build the compiled module (in a process
    of its own). With ``--if-stale``, only when its stamp does not
    match the sources. Exit status 0, or 1 when the build failed (the JIT then compiles on
    first use)."""
    import subprocess

    argv = sys.argv[1:] if argv is None else argv
    built = any(HERE.glob(f"{MODULE}.*.so")) or any(HERE.glob(f"{MODULE}.*.pyd"))
    if "--if-stale" in argv and built and info().get("stamp") == source_stamp():
        print("ik7r: the compiled kernels are up to date", file=sys.stderr)
        return 0
    if "--child" not in argv:
        print("ik7r: compiling the kernels into an extension module (once per installation, "
              "about 1-2 minutes)", file=sys.stderr, flush=True)
        env = {**os.environ, "IK7R_QUIET": "1", "IK7R_AOT": "0"}
        p = subprocess.run([sys.executable, "-m", "ik7r._kernels.aot", "--child"], env=env)
        if p.returncode != 0:
            print("ik7r: building the compiled kernels failed; the numba JIT compiles them on first "
                  "use instead", file=sys.stderr)
            return 1
        record = info()
        print(f"ik7r: compiled {len(record.get('entry_points', []))} entry points in "
              f"{record.get('seconds')} s", file=sys.stderr)
        return 0
    importlib.import_module("ik7r._kernels.aot").build()  # (this file runs as __main__)
    return 0


if __name__ == "__main__":
    sys.exit(main())
