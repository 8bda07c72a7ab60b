"""Fixtures shared by every test folder (helpers live in :mod:`helpers`, imported by name)."""

from __future__ import annotations

import numpy as np
import pytest


@pytest.fixture(scope="session")
def robot():
    import ik7r

    return ik7r.load_robot()


@pytest.fixture
def rng():
    return np.random.default_rng(20261126)
