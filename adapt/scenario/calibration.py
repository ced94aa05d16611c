"""Camera calibration files: OpenCV's FileStorage (YAML or XML) and ROS's camera_info YAML.

``camera: {calibration: FILE}`` reads a camera's intrinsics and lens distortion
from the file a calibration tool wrote; ``camera: {distortion: [k1, k2, p1, p2,
k3]}`` gives the distortion beside the scenario's own ``fx fy cx cy``.  Either
way the scenario gets a :class:`~adapt.lens.Lens`, and the runner undistorts
every frame before perception sees it.

Formats read (keys matched without regard to case, so OpenCV's tutorial's
``Camera_Matrix`` is read too; other keys are ignored):

* **OpenCV FileStorage YAML** (``%YAML:1.0``; what ``cv::FileStorage`` and
  the calibration samples write): ``image_width``, ``image_height``,
  ``camera_matrix`` and ``distortion_coefficients`` as ``!!opencv-matrix``
  (``rows``, ``cols``, ``dt``, ``data``);
* **OpenCV FileStorage XML**: the same keys as elements of
  ``<opencv_storage>`` with ``type_id="opencv-matrix"``;
* **ROS camera_info YAML** (``camera_calibration_parsers``): the same keys
  plus ``distortion_model`` (``plumb_bob``: 5 coefficients, or
  ``rational_polynomial``: 8), and the optional ``rectification_matrix``
  (3x3) and ``projection_matrix`` (3x4), whose left 3x3 is the camera matrix
  of the rectified image.

Every error names ``file:line:col`` in the calibration file (a matrix of the
wrong shape, a missing key, an unknown distortion model), and the scenario
line that names the file.

Examples
--------
>>> import tempfile, pathlib
>>> d = pathlib.Path(tempfile.mkdtemp())
>>> _ = (d / "cam.yaml").write_text('''%YAML:1.0
... ---
... image_width: 640
... image_height: 480
... camera_matrix: !!opencv-matrix
...    rows: 3
...    cols: 3
...    dt: d
...    data: [ 500., 0., 319.5, 0., 500., 239.5, 0., 0., 1. ]
... distortion_coefficients: !!opencv-matrix
...    rows: 1
...    cols: 5
...    dt: d
...    data: [ -0.2, 0.05, 0., 0., 0. ]
... ''')
>>> lens = read_calibration(d / "cam.yaml")
>>> lens.size, lens.intrinsics, lens.distortion
((640, 480), (500.0, 500.0, 319.5, 239.5), (-0.2, 0.05, 0.0, 0.0, 0.0))
>>> _ = (d / "bad.yaml").write_text("image_width: 640\\nimage_height: 480\\n"
...     "camera_matrix: {rows: 2, cols: 3, data: [1, 0, 0, 0, 1, 0]}\\n")
>>> read_calibration(d / "bad.yaml")
Traceback (most recent call last):
...
adapt.errors.ScenarioError: .../bad.yaml:3:23: camera_matrix: expected a 3x3 matrix, got 2x3
...
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any
from xml.parsers import expat

import numpy as np
import yaml

from adapt.errors import ScenarioError
from adapt.lens import DISTORTION_LENGTHS, Lens
from adapt.scenario.bounds import bound_of
from adapt.scenario.nodes import Node, NodeReader, join

__all__ = ["read_calibration", "DISTORTION_MODELS", "MAX_CALIBRATION_BYTES"]

#: ROS distortion models read, with their number of coefficients (OpenCV's model).
DISTORTION_MODELS = {"plumb_bob": 5, "rational_polynomial": 8}
#: The largest calibration file read, bytes.
MAX_CALIBRATION_BYTES = 1024 * 1024
#: The scenario key whose bound a calibration file's image size is held to.
SCENARIO_KEY = {"image_width": "camera.width", "image_height": "camera.height"}


@dataclass(frozen=True, slots=True)
class _Value:
    """A value of the file with its position: a scalar's text, a mapping, or a list."""

    value: Any
    line: int
    col: int


def read_calibration(path: str | Path, *, file: str | None = None) -> Lens:
    """The :class:`~adapt.lens.Lens` a calibration file describes (see the module docstring).

    Raises
    ------
    ScenarioError
        At the position of what is wrong in the file.
    """
    p = Path(path)
    name = file or str(p)
    try:
        data = p.read_bytes()[: MAX_CALIBRATION_BYTES + 1]
    except OSError as exc:
        raise ScenarioError(f"cannot read the calibration file: {exc}", file=name) from None
    if len(data) > MAX_CALIBRATION_BYTES:
        raise ScenarioError("larger than 1 MiB; expected a camera calibration file", file=name)
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError:
        raise ScenarioError("not a text file; expected a camera calibration file (OpenCV "
                            "YAML or XML, or ROS camera_info YAML)", file=name) from None
    lines = text.splitlines()
    if text.lstrip().startswith("<"):
        top = _XmlReader(name, lines).read(data)
    else:
        top = _YamlReader(text, name).read()
    return replace(_Calibration(name, lines, top).lens(), file=str(p))


# -- the two syntaxes, to one tree of positioned values -----------------------------------------

class _YamlReader(NodeReader):
    def __init__(self, text: str, file: str) -> None:
        # OpenCV writes "%YAML:1.0", which is not a YAML directive: blank it, keeping lines
        text = re.sub(r"\A%YAML:[0-9.]+", lambda m: " " * len(m.group(0)), text)
        super().__init__(text, file, Path.cwd())

    def read(self) -> _Value:
        root = self.compose()
        if root is None:
            raise ScenarioError("the calibration file is empty", file=self.file)
        return self.tree(root, "")

    def tree(self, node: Node, path: str) -> _Value:
        line, col = node.start_mark.line + 1, node.start_mark.column + 1
        if isinstance(node, yaml.MappingNode):
            items = self.mapping(node, path)
            return _Value({k: self.tree(v, join(path, k)) for k, (_, v) in items.items()}, line, col)
        if isinstance(node, yaml.SequenceNode):
            return _Value([self.tree(v, join(path, i)) for i, v in enumerate(node.value)], line, col)
        return _Value(str(node.value), line, col)


class _XmlReader:
    """OpenCV's FileStorage XML: elements to mappings, text to scalars, positions kept."""

    def __init__(self, file: str, lines: list[str]) -> None:
        self.file = file
        self.lines = lines

    def read(self, data: bytes) -> _Value:
        parser = expat.ParserCreate()
        stack: list[tuple[str, dict[str, _Value], list[str], int, int]] = []
        root: list[_Value] = []

        def start(tag: str, attrs: dict[str, str]) -> None:
            stack.append((tag, {}, [], parser.CurrentLineNumber, parser.CurrentColumnNumber + 1))

        def end(tag: str) -> None:
            name, children, text, line, col = stack.pop()
            value = _Value(children if children else " ".join(text).strip(), line, col)
            if stack:
                stack[-1][1].setdefault(name.lower(), value)
            else:
                root.append(value)

        def chars(text: str) -> None:
            if stack:
                stack[-1][2].append(text)

        parser.StartElementHandler = start
        parser.EndElementHandler = end
        parser.CharacterDataHandler = chars
        try:
            parser.Parse(data, True)
        except expat.ExpatError as exc:
            line = exc.lineno
            raise ScenarioError(f"not valid XML: {expat.ErrorString(exc.code)}", file=self.file,
                                line=line, col=exc.offset + 1,
                                source_line=self.lines[line - 1] if 0 < line <= len(self.lines)
                                else None) from None
        return root[0]


# -- what the keys mean --------------------------------------------------------------------------

class _Calibration:
    def __init__(self, file: str, lines: list[str], top: _Value) -> None:
        self.file = file
        self.lines = lines
        self.top = top
        if not isinstance(top.value, dict):
            raise self.error(top, "", "expected a mapping of keys (image_width, camera_matrix, "
                             "...)")
        self.items = {k.lower(): v for k, v in top.value.items()}

    def error(self, at: _Value, path: str, message: str) -> ScenarioError:
        text = self.lines[at.line - 1] if 0 < at.line <= len(self.lines) else None
        return ScenarioError((f"{path}: " if path else "") + message, file=self.file,
                             line=at.line, col=at.col, source_line=text)

    def key(self, name: str) -> _Value:
        if name not in self.items:
            raise self.error(self.top, "", f"missing key {name!r}; expected an OpenCV or ROS "
                             "camera calibration (image_width, image_height, camera_matrix, "
                             "distortion_coefficients)")
        return self.items[name]

    def number(self, v: _Value, path: str) -> float:
        try:
            x = float(v.value) if isinstance(v.value, str) else math.nan
        except ValueError:
            x = math.nan
        if not math.isfinite(x):
            raise self.error(v, path, f"expected a number, got {v.value!r}")
        return x

    def integer(self, name: str) -> int:
        v = self.key(name)
        x = self.number(v, name)
        if x != int(x) or x <= 0:
            raise self.error(v, name, f"expected a positive whole number, got {v.value!r}")
        self.within(v, name, x, SCENARIO_KEY[name])
        return int(x)

    def within(self, at: _Value, path: str, x: float, key: str) -> None:
        """``x`` within the bound the scenario's own ``key`` has (a calibration file is no
        scenario, but its numbers become the same camera's)."""
        problem = bound_of(key).problem(x)
        if problem is not None:
            raise self.error(at, path, f"{problem} (as for {key})")

    def matrix(self, name: str, shapes: tuple[tuple[int, int], ...]) -> np.ndarray:
        """A ``rows cols data`` matrix of one of ``shapes`` (``(0, n)``: any vector of n)."""
        v = self.key(name)
        if not isinstance(v.value, dict):
            raise self.error(v, name, "expected a matrix (rows, cols, data)")
        m = {k.lower(): x for k, x in v.value.items()}
        for k in ("rows", "cols", "data"):
            if k not in m:
                raise self.error(v, name, f"missing key {k!r} of the matrix")
        rows = self.number(m["rows"], f"{name}.rows")
        cols = self.number(m["cols"], f"{name}.cols")
        data = m["data"]
        if isinstance(data.value, list):
            values = [self.number(x, f"{name}.data[{i}]") for i, x in enumerate(data.value)]
        elif isinstance(data.value, str):  # XML: numbers separated by spaces
            values = [self.number(_Value(t, data.line, data.col), f"{name}.data")
                      for t in data.value.split()]
        else:
            raise self.error(data, f"{name}.data", "expected a list of numbers")
        r, c = int(rows), int(cols)
        if not any((r, c) == s or (s[0] == 0 and min(r, c) == 1 and max(r, c) == s[1])
                   for s in shapes):
            want = " or ".join(f"{a}x{b}" if a else f"1x{b}" for a, b in shapes)
            raise self.error(m["rows"], name, f"expected a {want} matrix, got {r}x{c}")
        if len(values) != r * c:
            raise self.error(data, f"{name}.data", f"expected {r * c} numbers ({r}x{c}), got "
                             f"{len(values)}")
        return np.array(values, np.float64).reshape(r, c)

    def lens(self) -> Lens:
        width, height = self.integer("image_width"), self.integer("image_height")
        k = self.matrix("camera_matrix", ((3, 3),))
        kv = self.items["camera_matrix"]
        if not (k[0, 0] > 0 and k[1, 1] > 0 and k[2, 2] == 1 and k[1, 0] == k[2, 0] == k[2, 1] == 0):
            raise self.error(kv, "camera_matrix", "expected [fx 0 cx; 0 fy cy; 0 0 1] with "
                             "positive fx and fy")
        for (i, j), key in (((0, 0), "camera.fx"), ((1, 1), "camera.fy"), ((0, 2), "camera.cx"),
                            ((1, 2), "camera.cy")):
            self.within(kv, "camera_matrix", float(k[i, j]), key)
        lengths: tuple[int, ...] = DISTORTION_LENGTHS
        if "distortion_model" in self.items:
            mv = self.items["distortion_model"]
            model = str(mv.value) if isinstance(mv.value, str) else ""
            if model not in DISTORTION_MODELS:
                raise self.error(mv, "distortion_model", "unknown distortion model "
                                 f"{mv.value!r}; expected " + " or ".join(DISTORTION_MODELS))
            lengths = (DISTORTION_MODELS[model],)
        d = self.matrix("distortion_coefficients", tuple((0, n) for n in lengths)).ravel()
        for x in d:
            self.within(self.items["distortion_coefficients"], "distortion_coefficients",
                        float(x), "camera.distortion")
        r = (self.matrix("rectification_matrix", ((3, 3),)) if "rectification_matrix" in self.items
             else np.eye(3))
        p = k
        if "projection_matrix" in self.items:
            p = self.matrix("projection_matrix", ((3, 4),))[:, :3]
            if not (p[0, 0] > 0 and p[1, 1] > 0):
                raise self.error(self.items["projection_matrix"], "projection_matrix",
                                 "expected positive focal lengths in the projection matrix")
            for (i, j), key in (((0, 0), "camera.fx"), ((1, 1), "camera.fy"),
                                ((0, 2), "camera.cx"), ((1, 2), "camera.cy")):
                self.within(self.items["projection_matrix"], "projection_matrix", float(p[i, j]),
                            key)
        return Lens(k, tuple(float(x) for x in d), (width, height), r, p)
