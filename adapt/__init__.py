"""adapt: the ADAPT architecture's mirror system.

A production-rule engine in the spirit of Soar (``adapt.engine``), match-mediated
difference image comparison (``adapt.vision``), a pymunk imagination with a
rasterized renderer (``adapt.imagination``), RS schema networks (``adapt.schemas``),
the runner (``adapt.runner``) and the tools to inspect traces (``adapt.traceview``).

The public API is what :data:`__all__` lists (``docs/api.md``): :func:`run`,
:func:`load_scenario` and :func:`start` (:mod:`adapt.api`), and the names a plugin
registers with (``docs/extending.md``).  Everything else is private by convention.
Importing ``adapt`` imports nothing heavy: the names below are imported when first used.

Examples
--------
>>> import adapt
>>> adapt.run(adapt.EXAMPLE, max_frames=2).summary["frames"]
2
>>> sorted(set(adapt.__all__) - set(dir(adapt)))
[]
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

__version__ = "0.1.0"

#: Public name -> the module that defines it.
_WHERE = {
    "run": "adapt.api",
    "load_scenario": "adapt.api",
    "start": "adapt.api",
    "load_plugins": "adapt.api",
    "Run": "adapt.api",
    "EXAMPLE": "adapt.api",
    "Scenario": "adapt.scenario",
    "Runner": "adapt.runner",
    "RunResult": "adapt.runner",
    "FrameRecord": "adapt.runner.record",
    "FrameListener": "adapt.runner.record",
    "BaselineSetup": "adapt.runner.baseline",
    "BaselinePrediction": "adapt.runner.baseline",
    "Frame": "adapt.frames",
    "FrameSource": "adapt.frames",
    "Actuator": "adapt.frames",
    "Schema": "adapt.schemas",
    "SchemaSpec": "adapt.schemas",
    "SchemaKind": "adapt.schemas",
    "Status": "adapt.schemas",
    "Port": "adapt.schemas",
    "Parameter": "adapt.parameters",
    "REQUIRED": "adapt.parameters",
    "REGISTRY": "adapt.schemas",
    "RealityType": "adapt.scenario",
    "REALITIES": "adapt.scenario",
    "PluginReality": "adapt.scenario",
    "ObjectPercept": "adapt.schemas.percepts",
    "BackgroundPercept": "adapt.schemas.percepts",
    "Structure": "adapt.schemas.links",
    "ConstantVelocityKF": "adapt.kalman",
    "AdaptError": "adapt.errors",
}

__all__ = [
    "__version__",
    "run",
    "load_scenario",
    "start",
    "load_plugins",
    "Run",
    "EXAMPLE",
    "Scenario",
    "Runner",
    "RunResult",
    "FrameRecord",
    "FrameListener",
    "BaselineSetup",
    "BaselinePrediction",
    "Frame",
    "FrameSource",
    "Actuator",
    "Schema",
    "SchemaSpec",
    "SchemaKind",
    "Status",
    "Port",
    "Parameter",
    "REQUIRED",
    "REGISTRY",
    "RealityType",
    "REALITIES",
    "PluginReality",
    "ObjectPercept",
    "BackgroundPercept",
    "Structure",
    "ConstantVelocityKF",
    "AdaptError",
]

if TYPE_CHECKING:  # pragma: no cover
    from adapt.api import EXAMPLE, Run, load_plugins, load_scenario, run, start
    from adapt.errors import AdaptError
    from adapt.frames import Actuator, Frame, FrameSource
    from adapt.kalman import ConstantVelocityKF
    from adapt.parameters import REQUIRED, Parameter
    from adapt.runner import Runner, RunResult
    from adapt.runner.baseline import BaselinePrediction, BaselineSetup
    from adapt.runner.record import FrameListener, FrameRecord
    from adapt.scenario import REALITIES, PluginReality, RealityType, Scenario
    from adapt.schemas import REGISTRY, Port, Schema, SchemaKind, SchemaSpec, Status
    from adapt.schemas.links import Structure
    from adapt.schemas.percepts import BackgroundPercept, ObjectPercept


def __getattr__(name: str) -> Any:
    module = _WHERE.get(name)
    if module is None:
        raise AttributeError(f"module 'adapt' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
