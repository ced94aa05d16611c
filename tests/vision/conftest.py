"""Shared fixtures of the vision tests."""

from __future__ import annotations

import numpy as np
import pytest

from adapt.vision.threads import set_threads


@pytest.fixture(autouse=True, scope="session")
def _two_threads():
    previous = set_threads(2)
    yield
    set_threads(previous)


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(12345)
