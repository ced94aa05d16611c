"""The fuzz workspace: one pool of inputs for the session; each fuzz module runs inside it."""

from __future__ import annotations

import os
from collections.abc import Iterator
from pathlib import Path

import pytest

from .harness import Pool


@pytest.fixture(scope="session")
def pool(tmp_path_factory: pytest.TempPathFactory) -> Pool:
    return Pool(tmp_path_factory.mktemp("fuzz"))


@pytest.fixture(scope="module", autouse=True)
def _in_workspace(pool: Pool) -> Iterator[None]:
    """Default outputs (``runs/<name>``, ``TRACE.html``) land in the workspace."""
    here = Path.cwd()
    os.chdir(pool.root)
    try:
        yield
    finally:
        os.chdir(here)
