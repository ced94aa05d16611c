"""The warning a reality source gives when it delivers less than it was asked for."""

from __future__ import annotations

__all__ = ["RealityWarning"]


class RealityWarning(UserWarning):
    """A reality source delivered less than it promised: a truncated video, or
    an appearance setting it cannot apply yet."""
