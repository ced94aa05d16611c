"""Reading the runner's sections: ``goals``, ``rules``, ``schemas``, ``run``,
``predict`` and ``outputs`` (see ``docs/scenario.md``).

Schema types and their parameters are not known here (the schema layer sits
above the scenario reader): ``schemas`` is read as plain parameters with
their positions, and the schema network checks them against the registry,
reporting any problem at the recorded position.
"""

from __future__ import annotations

from types import MappingProxyType
from typing import Any, Callable

import yaml

from adapt.scenario.bounds import BOUNDS, bound_of
from adapt.scenario.nodes import Node, join
from adapt.scenario.reality import RealityReader
from adapt.scenario.records import (
    Goal,
    ObjectModel,
    OutputSettings,
    PredictSettings,
    RuleFile,
    RunSettings,
    SchemaSettings,
    VideoCodec,
)

__all__ = ["RunReader", "RUN_KEYS", "PREDICT_KEYS", "OUTPUT_KEYS", "MAX_FRAMES", "MAX_FPS"]

RUN_KEYS = ("fps", "duration", "max_frames", "seed", "decisions_per_frame")
PREDICT_KEYS = ("horizons", "every", "ensemble", "evidence")
OUTPUT_KEYS = ("report", "trace", "video", "figures", "trace_level", "video_codec")

#: Most frames a scenario may ask for (about 9 hours at 30 frames/s).
MAX_FRAMES = int(BOUNDS["run.max_frames"].high or 0)
#: Highest frame rate accepted.
MAX_FPS = float(BOUNDS["run.fps"].high or 0)


class RunReader(RealityReader):
    """The runner's sections."""

    def goals(self, node: Node, path: str, models: tuple[ObjectModel, ...]) -> tuple[Goal, ...]:
        """``goals``: a list of mappings, each with a ``name``."""
        names = {m.name for m in models}

        def goal(n: Node, p: str, i: int) -> Goal:
            items = self.mapping(n, p)
            if "name" not in items:
                raise self.error(n, p, "missing key 'name' (what the goal is, for example intercept)")
            name = self.string(items["name"][1], join(p, "name"))
            attrs: list[tuple[str, str | int | float]] = []
            sources = {}
            for key, (knode, vnode) in items.items():
                if key == "name":
                    continue
                kp = join(p, key)
                if not _is_attribute(key):
                    raise self.error(knode, kp, "expected an attribute name of letters, digits and "
                                     "'-' or '_', starting with a letter")
                value = self.scalar(vnode, kp) if isinstance(vnode, yaml.ScalarNode) else None
                if isinstance(value, bool) or not isinstance(value, (str, int, float)) or value == "":
                    raise self.error(vnode, kp, "expected a string or a number (goal attributes "
                                     f"become WMEs), got {self.describe(vnode)}")
                if isinstance(value, float) and value != value:
                    raise self.error(vnode, kp, "expected a number, got nan")
                if key == "object" and value not in names:
                    raise self.error(vnode, kp, f"no object called {value!r} in world.objects"
                                     + (f"; expected one of {', '.join(sorted(names))}" if names else ""))
                attrs.append((key, value))
                sources[key] = self.source(vnode, kp)
            return Goal(name, tuple(attrs), self.source(n, p), MappingProxyType(sources))

        return tuple(self.listed(node, path, goal))

    def rules(self, node: Node, path: str) -> tuple[RuleFile, ...]:
        """``rules``: rule files relative to the scenario (one file may be given as a string)."""
        if isinstance(node, yaml.ScalarNode) and not self.is_null(node):
            return (RuleFile(self.existing_file(node, path, "rule file"), self.source(node, path)),)
        return tuple(self.listed(
            node, path,
            lambda n, p, i: RuleFile(self.existing_file(n, p, "rule file"), self.source(n, p))))

    def schemas(self, node: Node, path: str) -> tuple[SchemaSettings, ...]:
        """``schemas``: ``type: {parameter: value, ...}`` for each schema type."""
        if self.is_null(node):
            return ()
        out = []
        for key, (knode, vnode) in self.mapping(node, path).items():
            kp = join(path, key)
            params: dict[str, Any] = {}
            sources = {}
            if not self.is_null(vnode):
                for pkey, (_pk, pv) in self.mapping(vnode, kp).items():
                    pp = join(kp, pkey)
                    params[pkey] = self.plain(pv, pp)
                    sources[pkey] = self.source(pv, pp)
            out.append(SchemaSettings(key, MappingProxyType(params), self.source(knode, kp),
                                      MappingProxyType(sources)))
        return tuple(out)

    def plain(self, node: Node, path: str) -> Any:
        """A scalar or a list of scalars, as plain Python data."""
        if isinstance(node, yaml.ScalarNode):
            return self.scalar(node, path)
        if isinstance(node, yaml.SequenceNode):
            return [self.plain(v, join(path, i)) for i, v in enumerate(node.value)]
        raise self.error(node, path, f"expected a value or a list of values, got {self.describe(node)}")

    def run_settings(self, node: Node, path: str) -> tuple[RunSettings, int | None]:
        """``run``; also returns ``run.seed`` (None when absent)."""
        spec: dict[str, Callable[[Node, str], Any]] = {
            "fps": self.number,
            "duration": self.number,
            "max_frames": self.integer,
            "seed": self.integer,
            "decisions_per_frame": self.integer,
        }
        kw = self.fields(node, path, spec)
        items = self.mapping(node, path)
        if "duration" in kw and "max_frames" in kw:
            # a --set of one replaces the file's other: how long to run is one setting
            given = [k for k in ("duration", "max_frames") if id(items[k][1]) in self._override_text]
            if len(given) == 1:
                del kw["max_frames" if given[0] == "duration" else "duration"]
        if "duration" in kw and "max_frames" in kw:
            raise self.error(items["max_frames"][0], join(path, "max_frames"),
                             "give either duration or max_frames, not both")
        seed = kw.pop("seed", None)
        settings = RunSettings(**kw, source=self.source(node, path))
        if settings.frames > MAX_FRAMES:
            raise self.error(items["duration"][1], join(path, "duration"),
                             f"{settings.frames} frames at {settings.fps:g} frames/s; expected at "
                             f"most {MAX_FRAMES}")
        return settings, seed

    def predict_settings(self, node: Node, path: str) -> PredictSettings:
        def horizons(n: Node, p: str) -> tuple[float, ...]:
            each = bound_of(p)
            values = self.listed(n, p, lambda v, q, i: self.number(v, q, each))
            if not values:
                raise self.error(n, p, "expected at least one horizon (seconds ahead)")
            return tuple(sorted(set(values)))

        spec: dict[str, Callable[[Node, str], Any]] = {
            "horizons": horizons,
            "every": self.integer,
            "ensemble": self.integer,
            "evidence": self.integer,
        }
        kw = self.fields(node, path, spec)
        return PredictSettings(**kw, source=self.source(node, path))

    def output_settings(self, node: Node, path: str) -> OutputSettings:
        spec: dict[str, Callable[[Node, str], Any]] = {
            "report": self.boolean,
            "trace": self.boolean,
            "video": self.boolean,
            "figures": self.boolean,
            "trace_level": self.integer,
            "video_codec": lambda n, p: VideoCodec(self.choice(n, p, [c.value
                                                                      for c in VideoCodec])),
        }
        return OutputSettings(**self.fields(node, path, spec), source=self.source(node, path))


def _is_attribute(key: str) -> bool:
    return bool(key) and key[0].isalpha() and all(c.isalnum() or c in "-_" for c in key)
