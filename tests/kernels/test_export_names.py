"""An exported name means the same thing whatever was imported before it.

A lazily exported function that shares its name with a submodule of its package is replaced by
the module once someone imports the submodule first (``ik7r._kernels.track`` once hid the
kernel ``track``, and ``robot.ik_path`` then failed with "'module' object is not callable").
"""

from __future__ import annotations

import json
import subprocess
import sys

KINDS = r"""
import importlib, json, pkgutil, sys
import ik7r
first = sys.argv[1] == "submodules-first"
names = ["ik7r"] + sorted(i.name for i in pkgutil.walk_packages(ik7r.__path__, "ik7r.")
                          if not i.name.endswith("__main__"))
if first:
    for name in names:
        importlib.import_module(name)
kinds = {}
for name in names:
    module = sys.modules.get(name) or importlib.import_module(name)
    if hasattr(module, "__path__"):
        for export in getattr(module, "__all__", []):
            kinds[f"{name}.{export}"] = type(getattr(module, export)).__name__
print(json.dumps(kinds))
"""


def _kinds(order: str) -> dict[str, str]:
    p = subprocess.run([sys.executable, "-c", KINDS, order], capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr
    return json.loads(p.stdout.strip().splitlines()[-1])


def test_exports_do_not_depend_on_the_import_order():
    lazy, eager = _kinds("exports-first"), _kinds("submodules-first")
    assert lazy.keys() == eager.keys() and len(lazy) > 50
    changed = {k: (lazy[k], eager[k]) for k in lazy if lazy[k] != eager[k]}
    assert not changed, changed


def test_ik_path_works_after_every_kernel_module_was_imported(robot):
    import importlib
    import pkgutil

    import numpy as np

    for info in pkgutil.iter_modules(importlib.import_module("ik7r._kernels").__path__, "ik7r._kernels."):
        importlib.import_module(info.name)
    q = np.linspace(np.full(6, 0.3), np.full(6, 0.4), 5)
    res = robot.ik_path(robot.fk(q), int(robot.config_of(q[0])), seed=q[0])
    assert res.ok.all()
    assert np.abs(robot.fk(res.q)[:, :3, 3] - robot.fk(q)[:, :3, 3]).max() < 1e-9
