"""Suite-wide pytest hooks."""

from __future__ import annotations


def pytest_report_header() -> str:
    """Say which engine the run tests: the mypyc-compiled modules or the source."""
    from adapt.engine import engine_build

    return f"adapt engine: {engine_build()}"
