"""The static type check of the public API really checks: a wrong use of the API is an error.

``make test`` runs mypy over the package's public modules and ``tests/typing/public_api.py``
(configured in pyproject.toml); here mypy checks two small programs against the annotations.
"""

from __future__ import annotations

from pathlib import Path

import pytest

api = pytest.importorskip("mypy.api")

ROOT = Path(__file__).resolve().parents[2]

GOOD = """
import numpy as np
import ik7r
robot: ik7r.Robot = ik7r.load_robot("irb5400")
q: np.ndarray = robot.ik(robot.fk(np.zeros(6)), config=(1, 0, 1))
"""

BAD = """
import numpy as np
import ik7r
robot = ik7r.load_robot()
q: np.ndarray = robot.ik(robot.fk(np.zeros(6)), config="one")   # a configuration is not a str
name: int = robot.ik_all_batch(np.zeros((2, 4, 4)))            # it returns a tuple
"""


def _mypy(code: str, tmp_path: Path) -> tuple[str, int]:
    program = tmp_path / "program.py"
    program.write_text(code)
    out, err, status = api.run(["--config-file", str(ROOT / "pyproject.toml"),
                                "--cache-dir", str(ROOT / ".mypy_cache"), str(program)])
    return out + err, status


def test_correct_use_passes(tmp_path):
    out, status = _mypy(GOOD, tmp_path)
    assert status == 0, out


def test_wrong_use_fails_with_the_errors(tmp_path):
    out, status = _mypy(BAD, tmp_path)
    assert status == 1, out
    assert '"config"' in out and '"ik"' in out
    assert "tuple[" in out and out.count("error:") == 2
