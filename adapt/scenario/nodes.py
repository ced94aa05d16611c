"""Reading YAML nodes with positions: the machinery under the scenario reader.

:class:`NodeReader` walks the node tree PyYAML composes (never a plain
``yaml.safe_load``), so every value keeps its line and column.  It provides
the typed readers every section uses (numbers, integers, vectors, strings,
colours, booleans, number-or-range), checks keys, records the
:class:`~adapt.scenario.source.Source` of every key path it reads, and turns
every error into a :class:`~adapt.errors.ScenarioError` at the offending node.

Numbers follow YAML 1.2: ``1e-3`` and ``1.0e6`` are floats (PyYAML's YAML
1.1 would read them as strings).

Overrides (``adapt sweep --set KEY=VALUE``) replace or add nodes before
anything is read, so a bad override gets the same positioned error, located
in the override text.
"""

from __future__ import annotations

import difflib
import math
import os
import re
from pathlib import Path
from typing import Any, Callable, Sequence

import yaml

from adapt.errors import ScenarioError
from adapt.scenario.bounds import Bound, bound_of, show
from adapt.scenario.records import Range
from adapt.scenario.source import Source

__all__ = ["NodeReader", "Node", "Override", "join", "YAML12Loader", "yaml_value"]

Node = yaml.Node


#: The deepest nesting of lists and mappings a scenario, or a ``--set`` value, may have (the
#: documented keys go five deep); bounded while composing, before it could exhaust the stack.
MAX_DEPTH = 64


class NestingError(yaml.MarkedYAMLError):
    """YAML that nests deeper than :data:`MAX_DEPTH` levels, at the node that would go deeper."""


class YAML12Loader(yaml.SafeLoader):
    """PyYAML's safe loader with YAML 1.2 floats (``1e-3``, ``2E5``, ``.5e1``) and nesting
    bounded by :data:`MAX_DEPTH` (:class:`NestingError`).

    >>> try:
    ...     yaml.load("[" * 65 + "]" * 65, Loader=YAML12Loader)
    ... except NestingError as exc:
    ...     print(exc.problem, "at column", exc.problem_mark.column + 1)
    the YAML nests deeper than 64 levels of lists and mappings at column 65
    """

    _depth = 0

    def compose_node(self, parent: Node | None, index: int) -> Node | None:
        depth = self._depth
        if depth >= MAX_DEPTH:
            raise NestingError(problem=f"the YAML nests deeper than {MAX_DEPTH} levels of lists "
                               "and mappings", problem_mark=self.peek_event().start_mark)
        self._depth = depth + 1
        try:
            return super().compose_node(parent, index)  # type: ignore[no-any-return]
        finally:
            self._depth = depth


YAML12Loader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(r"^[-+]?(?:[0-9][0-9_]*(?:\.[0-9_]*)?|\.[0-9_]+)[eE][-+]?[0-9]+$"),
    list("-+0123456789."),
)


def yaml_value(text: str) -> Any:
    """A value written in YAML (``0.7``, ``[1, 2]``, ``brick``), read as a scenario's values
    are (YAML 1.2 numbers).

    Raises
    ------
    ValueError
        When ``text`` is not YAML.

    Examples
    --------
    >>> yaml_value("1e-3"), yaml_value("[1, 2]"), yaml_value("brick")
    (0.001, [1, 2], 'brick')
    """
    try:
        return yaml.load(text, Loader=YAML12Loader)
    except yaml.YAMLError as exc:
        raise ValueError(f"not a YAML value: {exc}") from None


def join(path: str, key: str | int) -> str:
    """``path.key`` (``path[i]`` for an index); the document's own path is ``""``.

    Examples
    --------
    >>> join("", "world"), join("world", "walls"), join("world.walls", 2)
    ('world', 'world.walls', 'world.walls[2]')
    """
    if isinstance(key, int):
        return f"{path}[{key}]"
    return f"{path}.{key}" if path else key


class Override:
    """One ``KEY=VALUE`` override: a key path and a YAML value.

    Examples
    --------
    >>> o = Override.parse("world.objects.ball.restitution=0.7")
    >>> o.path, o.value
    ('world.objects.ball.restitution', '0.7')
    >>> Override.parse("seed")
    Traceback (most recent call last):
    ...
    adapt.errors.ScenarioError: --set:1:5: expected KEY=VALUE (for example world.objects.ball.restitution=0.7)
        seed
            ^
    """

    __slots__ = ("path", "value", "text")

    def __init__(self, path: str, value: str, text: str | None = None) -> None:
        self.path = path
        self.value = value
        self.text = text if text is not None else f"{path}={value}"

    @classmethod
    def parse(cls, text: str) -> "Override":
        """Read ``KEY=VALUE``."""
        key, eq, value = text.partition("=")
        if not eq or not key.strip():
            raise ScenarioError("expected KEY=VALUE (for example world.objects.ball.restitution=0.7)",
                                file="--set", line=1, col=len(text) + 1, source_line=text)
        return cls(key.strip(), value, text)


def _finite(value: int | float) -> bool:
    """True for an int (of any size) or a finite float."""
    return isinstance(value, int) or math.isfinite(value)


_STEP = re.compile(r"([^.\[\]]+)|\[(\d+)\]")


class NodeReader:
    """Typed access to YAML nodes with positioned errors (see the module docstring)."""

    def __init__(self, text: str, file: str, base: Path) -> None:
        self.text = text
        self.lines = text.splitlines()
        self.file = file
        self.base = base
        self.loader = YAML12Loader(text)
        self.sources: dict[str, Source] = {}
        self._override_text: dict[int, tuple[Node, str]] = {}  # the node is kept so its id stays unique

    # -- composing ---------------------------------------------------------------

    def compose(self) -> Node | None:
        """The document's root node, or None for an empty document."""
        try:
            return self.loader.get_single_node()
        except yaml.MarkedYAMLError as exc:
            mark = exc.problem_mark or exc.context_mark
            line, col = (mark.line + 1, mark.column + 1) if mark else (1, 1)
            what = (f"{exc.problem}; a scenario needs far fewer" if isinstance(exc, NestingError)
                    else f"not valid YAML: {exc.problem or exc}")
            raise ScenarioError(what, file=self.file, line=line, col=col,
                                source_line=self.line_text(line)) from None
        except yaml.YAMLError as exc:
            raise ScenarioError(f"not valid YAML: {exc}", file=self.file) from None

    def line_text(self, line: int) -> str | None:
        """The text of a 1-based line of the file, or None."""
        return self.lines[line - 1] if 0 < line <= len(self.lines) else None

    # -- positions and errors --------------------------------------------------------

    def source(self, node: Node | None, path: str) -> Source:
        """The :class:`Source` of ``node`` (recorded under ``path``)."""
        if node is not None and id(node) in self._override_text:
            text = self._override_text[id(node)][1]
            col = text.find("=") + 2 if "=" in text else 1
            src = Source("--set", 1, col, path, text)
        elif node is not None:
            line, col = node.start_mark.line + 1, node.start_mark.column + 1
            src = Source(self.file, line, col, path, self.line_text(line))
        else:
            src = Source(self.file, 1, 1, path, self.line_text(1))
        self.sources.setdefault(path, src)
        return src

    def error(self, node: Node | None, path: str, message: str) -> ScenarioError:
        """A positioned error at ``node``."""
        return self.source(node, path).error(message)

    def scalar(self, node: Node, path: str = "") -> Any:
        """The Python value of a scalar node."""
        try:
            return self.loader.construct_object(node, deep=True)
        except yaml.YAMLError as exc:
            raise self.error(node, path, f"cannot read this value: {exc}") from None

    def describe(self, node: Node) -> str:
        """``a mapping``, ``a list`` or the value's repr, for messages."""
        if isinstance(node, yaml.MappingNode):
            return "a mapping"
        if isinstance(node, yaml.SequenceNode):
            return "a list"
        return repr(self.scalar(node))

    def is_null(self, node: Node) -> bool:
        """True for an empty value (``~``, ``null`` or nothing)."""
        return isinstance(node, yaml.ScalarNode) and node.tag == "tag:yaml.org,2002:null"

    # -- mappings and keys ---------------------------------------------------------

    def mapping(self, node: Node, path: str) -> dict[str, tuple[Node, Node]]:
        """Keys of a mapping node -> (key node, value node); rejects duplicates."""
        if not isinstance(node, yaml.MappingNode):
            raise self.error(node, path, f"expected a mapping, got {self.describe(node)}")
        out: dict[str, tuple[Node, Node]] = {}
        for k, v in node.value:
            key = self.scalar(k, path) if isinstance(k, yaml.ScalarNode) else None
            if not isinstance(key, str):
                raise self.error(k, path, "expected a string key")
            if key in out:
                raise self.error(k, join(path, key), "duplicate key")
            out[key] = (k, v)
            self.source(v, join(path, key))
        return out

    def check_keys(self, items: dict[str, tuple[Node, Node]], allowed: Sequence[str],
                   path: str) -> None:
        """Refuse a key that is not in ``allowed`` (suggesting a close one)."""
        for key, (knode, _) in items.items():
            if key not in allowed:
                close = difflib.get_close_matches(key, allowed, n=1, cutoff=0.6)
                hint = f" (did you mean {close[0]!r}?)" if close else ""
                raise self.error(knode, join(path, key),
                                 f"unknown key{hint}; expected one of " + ", ".join(allowed))

    def fields(self, node: Node, path: str, spec: dict[str, Callable[[Node, str], Any]],
               required: tuple[str, ...] = ()) -> dict[str, Any]:
        """Read a mapping whose keys are those of ``spec``; each value through its reader."""
        items = self.mapping(node, path)
        self.check_keys(items, tuple(spec), path)
        for key in required:
            if key not in items:
                raise self.error(node, path, f"missing key {key!r}")
        return {key: spec[key](v, join(path, key)) for key, (_, v) in items.items()}

    def listed(self, node: Node, path: str, read: Callable[[Node, str, int], Any]) -> list[Any]:
        """Read a list (``null`` is an empty list), each item with ``read(node, path, index)``."""
        if self.is_null(node):
            return []
        if not isinstance(node, yaml.SequenceNode):
            raise self.error(node, path, f"expected a list, got {self.describe(node)}")
        return [read(v, join(path, i), i) for i, v in enumerate(node.value)]

    # -- typed values ----------------------------------------------------------------

    def number(self, node: Node, path: str, bound: Bound | None = None) -> float:
        """A finite number within ``bound`` (by default the bound :data:`~adapt.scenario.bounds.BOUNDS`
        declares for ``path``)."""
        self.source(node, path)
        value = self.scalar(node, path) if isinstance(node, yaml.ScalarNode) else None
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not _finite(value):
            raise self.error(node, path, f"expected a number, got {self.describe(node)}")
        self._bounded(node, path, value, bound)
        try:
            return float(value)
        except OverflowError:  # an integer of hundreds of digits, where no upper bound applies
            raise self.error(node, path, f"expected a number, got {show(value)}") from None

    def integer(self, node: Node, path: str, bound: Bound | None = None) -> int:
        """An integer within ``bound`` (by default the one declared for ``path``)."""
        self.source(node, path)
        value = self.scalar(node, path) if isinstance(node, yaml.ScalarNode) else None
        if isinstance(value, bool) or not isinstance(value, int):
            raise self.error(node, path, f"expected an integer, got {self.describe(node)}")
        self._bounded(node, path, value, bound)
        return value

    def _bounded(self, node: Node, path: str, value: float, bound: Bound | None) -> None:
        problem = (bound_of(path) if bound is None else bound).problem(value)
        if problem is not None:
            raise self.error(node, path, problem)

    def boolean(self, node: Node, path: str) -> bool:
        """``true`` or ``false``."""
        self.source(node, path)
        value = self.scalar(node, path) if isinstance(node, yaml.ScalarNode) else None
        if not isinstance(value, bool):
            raise self.error(node, path, f"expected true or false, got {self.describe(node)}")
        return value

    def vector(self, node: Node, path: str, n: int, bound: Bound | None = None) -> tuple[float, ...]:
        """A list of ``n`` numbers, each within ``bound`` (by default the one declared for
        ``path``)."""
        self.source(node, path)
        names = "[x, y]" if n == 2 else "[x, y, z]" if n == 3 else f"{n} numbers"
        if not isinstance(node, yaml.SequenceNode) or len(node.value) != n:
            raise self.error(node, path, f"expected {names}, got {self.describe(node)}")
        each = bound_of(path) if bound is None else bound
        return tuple(self.number(v, join(path, i), each) for i, v in enumerate(node.value))

    def string(self, node: Node, path: str) -> str:
        """A non-empty string."""
        self.source(node, path)
        value = self.scalar(node, path) if isinstance(node, yaml.ScalarNode) else None
        if not isinstance(value, str) or not value:
            raise self.error(node, path, f"expected a string, got {self.describe(node)}")
        return value

    def choice(self, node: Node, path: str, choices: Sequence[str]) -> str:
        """One of ``choices``."""
        value = self.string(node, path)
        if value not in choices:
            raise self.error(node, path, "expected one of " + ", ".join(repr(c) for c in choices)
                             + f", got {value!r}")
        return value

    def range(self, node: Node, path: str, bound: Bound | None = None) -> Range:
        """A number, or ``[low, high]`` with ``low <= high`` (drawn per run), within ``bound``
        (by default the bound declared for ``path``)."""
        self.source(node, path)
        each = bound_of(path) if bound is None else bound
        if isinstance(node, yaml.SequenceNode):
            if len(node.value) != 2:
                raise self.error(node, path, f"expected a number or [low, high], got {self.describe(node)}")
            low = self.number(node.value[0], join(path, 0), each)
            high = self.number(node.value[1], join(path, 1), each)
            if low > high:
                raise self.error(node, path, f"expected [low, high] with low <= high, got [{low:g}, {high:g}]")
            return Range(low, high)
        return Range.fixed(self.number(node, path, each))

    def path_value(self, node: Node, path: str) -> Path:
        """A file path, relative to the scenario file (not checked for existence)."""
        value = self.string(node, path)
        p = Path(value).expanduser()
        return Path(os.path.normpath(p if p.is_absolute() else self.base / p))

    def existing_file(self, node: Node, path: str, what: str) -> Path:
        """A path (relative to the scenario) that must name an existing file."""
        p = self.path_value(node, path)
        if not p.is_file():
            raise self.error(node, path, f"{what} {str(p)!r} not found; expected a file "
                             "(relative to the scenario)")
        return p

    # -- overrides --------------------------------------------------------------------

    def apply_overrides(self, root: Node, overrides: Sequence[Override]) -> Node:
        """Replace (or add) the nodes the overrides name; returns the new root.

        A list of named items (``world.objects``) may be addressed by name
        (``world.objects.ball.restitution``) as well as by index
        (``world.objects[0].restitution``).  Missing mappings on the way are
        created, so an override may set a key the file does not have.
        """
        for ov in overrides:
            value = self._override_node(ov)
            root = self._replace(root, self._steps(ov), value, ov)
        return root

    def _steps(self, ov: Override) -> list[str | int]:
        steps: list[str | int] = []
        pos = 0
        text = ov.path
        lead = len(ov.text) - len(ov.text.lstrip())  # the key's column in the --set text
        while pos < len(text):
            if text[pos] == ".":
                if pos == 0 or pos + 1 == len(text) or text[pos + 1] == ".":
                    at = pos + 1 if pos and pos + 1 < len(text) else pos
                    raise ScenarioError(
                        "an empty key between dots; expected a key path like run.fps or "
                        "world.objects.ball.mass", file="--set", line=1, col=lead + at + 1,
                        source_line=ov.text)
                pos += 1
                continue
            m = _STEP.match(text, pos)
            if m is None:
                raise ScenarioError(f"cannot read the key path {text!r}", file="--set", line=1,
                                    col=pos + 1, source_line=ov.text)
            steps.append(int(m.group(2)) if m.group(2) is not None else m.group(1))
            pos = m.end()
        if not steps:
            raise ScenarioError("expected a key path before '='", file="--set", line=1, col=1,
                                source_line=ov.text)
        return steps

    def _override_node(self, ov: Override) -> Node:
        loader = YAML12Loader(ov.value if ov.value.strip() else "~")
        try:
            node = loader.get_single_node()
        except NestingError as exc:
            mark = exc.problem_mark
            col = len(ov.text) - len(ov.value) + 1 + (mark.column if mark and not mark.line else 0)
            raise ScenarioError(f"{ov.path}: {exc.problem}", file="--set", line=1, col=col,
                                source_line=ov.text) from None
        except yaml.YAMLError as exc:
            raise ScenarioError(f"{ov.path}: the value is not valid YAML: {exc}", file="--set",
                                line=1, col=len(ov.path) + 2, source_line=ov.text) from None
        finally:
            loader.dispose()
        if node is None:
            node = yaml.ScalarNode("tag:yaml.org,2002:null", "")
        self._mark(node, ov.text)
        return node

    def _mark(self, node: Node, text: str) -> None:
        self._override_text[id(node)] = (node, text)
        if isinstance(node, yaml.SequenceNode):
            for v in node.value:
                self._mark(v, text)
        elif isinstance(node, yaml.MappingNode):
            for k, v in node.value:
                self._mark(k, text)
                self._mark(v, text)

    def _replace(self, node: Node, steps: list[str | int], value: Node, ov: Override) -> Node:
        if not steps:
            return value
        step, rest = steps[0], steps[1:]
        where = ov.path

        def fail(message: str) -> ScenarioError:
            return ScenarioError(f"{where}: {message}", file="--set", line=1, col=1,
                                 source_line=ov.text)

        if isinstance(node, yaml.SequenceNode):
            index: int | None = None
            if isinstance(step, int):
                if step >= len(node.value):
                    raise fail(f"index {step} is past the end of a list of {len(node.value)}")
                index = step
            else:
                for i, item in enumerate(node.value):
                    if isinstance(item, yaml.MappingNode) and any(
                        isinstance(k, yaml.ScalarNode) and k.value == "name"
                        and isinstance(v, yaml.ScalarNode) and v.value == step
                        for k, v in item.value
                    ):
                        index = i
                        break
                if index is None:
                    raise fail(f"no item named {step!r} in that list")
            items = list(node.value)
            items[index] = self._replace(items[index], rest, value, ov)
            return yaml.SequenceNode(node.tag, items, node.start_mark, node.end_mark,
                                     flow_style=node.flow_style)
        if isinstance(node, yaml.MappingNode) or self.is_null(node):
            if isinstance(step, int):
                raise fail(f"[{step}] indexes a list, but this is a mapping")
            pairs = list(node.value) if isinstance(node, yaml.MappingNode) else []
            for i, (k, v) in enumerate(pairs):
                if isinstance(k, yaml.ScalarNode) and k.value == step:
                    pairs[i] = (k, self._replace(v, rest, value, ov))
                    break
            else:
                if rest and isinstance(rest[0], int):
                    present = [str(k.value) for k, _ in pairs if isinstance(k, yaml.ScalarNode)]
                    close = difflib.get_close_matches(step, present, n=1, cutoff=0.6)
                    hint = f" (did you mean {close[0]!r}?)" if close else ""
                    raise fail(f"no list called {step!r} to index{hint}")
                key = yaml.ScalarNode("tag:yaml.org,2002:str", step)
                self._mark(key, ov.text)
                empty = yaml.MappingNode("tag:yaml.org,2002:map", [])
                self._mark(empty, ov.text)
                pairs.append((key, self._replace(empty, rest, value, ov) if rest else value))
            new = yaml.MappingNode("tag:yaml.org,2002:map", pairs, node.start_mark,
                                   node.end_mark, flow_style=getattr(node, "flow_style", None))
            if id(node) in self._override_text:
                self._override_text[id(new)] = (new, self._override_text[id(node)][1])
            return new
        raise fail(f"cannot go into {self.describe(node)} with {step!r}")
