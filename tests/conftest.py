"""Fixtures shared by every test folder (helpers live in :mod:`helpers`, imported by name)."""

from __future__ import annotations

import os

import numpy as np
import pytest

# The notice before a numba compile (ik7r._kernels.jit) goes to stderr; tests that check a
# command's stderr line by line must not depend on whether an earlier test filled the cache.
# tests/kernels/test_compile_notice.py tests the notice itself, in processes of its own.
os.environ.setdefault("IK7R_QUIET", "1")


@pytest.fixture(scope="session")
def robot():
    import ik7r

    return ik7r.load_robot()


@pytest.fixture
def rng():
    return np.random.default_rng(20261126)
