"""RS schema networks: perceptual and motor schemas, the one place where symbols meet arrays.

* :mod:`~adapt.schemas.spec` - what a schema type declares (kind, ports, parameters);
* :mod:`~adapt.schemas.registry` - types by name (:data:`REGISTRY`);
* :mod:`~adapt.schemas.base` - the :class:`Schema` base class: the frame loop's calls, and
  what a schema tells the network (boxes, claims, monitored objects);
* :mod:`~adapt.schemas.percepts` - what schemas publish on their ports, the only way they
  meet (:class:`~adapt.schemas.percepts.BackgroundPercept`,
  :class:`~adapt.schemas.percepts.ObjectPercept`);
* :mod:`~adapt.schemas.network` - :class:`SchemaNetwork`, the minimal subscene (a networkx
  DiGraph whose edges carry the percepts); :mod:`~adapt.schemas.events` - what happens to it;
* :mod:`~adapt.schemas.links` - the input-link and output-link layout (``docs/schemas.md``);
* :mod:`~adapt.schemas.tracks` - difference regions followed over frames;
* the object schema's parts: :mod:`~adapt.schemas.silhouette` (a ball's floor position from
  its outline), :mod:`~adapt.schemas.estimator` (its parameters from bounces and rolling),
  :mod:`~adapt.schemas.predictor` (predictions with a confidence);
* the types: :mod:`~adapt.schemas.background` (``scene-background``),
  :mod:`~adapt.schemas.foreground` (``foreground-object``), :mod:`~adapt.schemas.drive`
  (``drive``), :mod:`~adapt.schemas.intercept` (``intercept``), :mod:`~adapt.schemas.search`
  (``search``).

This package imports the engine (its I/O links), vision, the imagination (through
:mod:`adapt.mirror`) and networkx; it never imports the reality or ground truth.
"""

from __future__ import annotations

from adapt.schemas.base import Origin, Schema, Status
from adapt.schemas.events import EventKind, SchemaEvent
from adapt.schemas.network import SchemaNetwork, check_settings
from adapt.schemas.registry import REGISTRY, Registry
from adapt.schemas.spec import Parameter, Port, SchemaKind, SchemaSpec

__all__ = [
    "Schema",
    "Status",
    "Origin",
    "SchemaNetwork",
    "SchemaEvent",
    "EventKind",
    "check_settings",
    "Registry",
    "REGISTRY",
    "SchemaSpec",
    "SchemaKind",
    "Port",
    "Parameter",
]
