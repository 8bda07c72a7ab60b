"""The public API: every exported name resolves, nothing heavy at import, one error base."""

from __future__ import annotations

import importlib
import subprocess
import sys

import numpy as np
import pytest

import ik7r

SUBPACKAGES = ["ik7r", "ik7r.robot", "ik7r.geometry", "ik7r.ik", "ik7r._kernels", "ik7r.cli"]


@pytest.mark.parametrize("name", SUBPACKAGES)
def test_every_exported_name_resolves(name):
    module = importlib.import_module(name)
    missing = [n for n in module.__all__ if getattr(module, n, None) is None]
    assert missing == []
    assert set(module.__all__) <= set(dir(module))


def test_unknown_name_is_an_attribute_error():
    with pytest.raises(AttributeError, match="has no attribute 'nope'"):
        ik7r.robot.nope  # noqa: B018


def test_import_does_no_heavy_work():
    code = ("import sys, ik7r; r = ik7r.load_robot(); r.to_toml(); "
            "print(sorted(m for m in ('numba', 'scipy', 'matplotlib', 'ik7r.ik.solve') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_errors_share_one_base_and_stay_value_errors():
    for err in (ik7r.UnreachableError, ik7r.RobotFileError, ik7r.FamilyError):
        assert issubclass(err, ik7r.Ik7rError) and issubclass(err, ValueError)
    far = np.eye(4)
    far[0, 3] = 1e5  # far beyond the reach of the paper robot (mm)
    with pytest.raises(ik7r.Ik7rError):
        ik7r.load_robot().ik(far, 1)
