"""The one exception hierarchy of adapt.

Every error a user can cause (a malformed rule file, scenario YAML, image, video
or trace) is an :class:`AdaptError`.  The command line prints ``str(error)`` and
exits with status 1; it never shows a Python traceback for bad input.

Errors that point into a text file (rules, YAML) are :class:`LocatedError`\\ s:
their message starts with ``file:line:col:`` and, when the source line is known,
shows it with a caret under the column.

This module imports only the standard library, so every layer (including the
numpy-free engine) may use it.

Examples
--------
>>> err = RuleSyntaxError("expected '-->'", file="a.soar", line=3, col=5,
...                       source_line="sp {x (state <s>) (write hi)}")
>>> print(err)
a.soar:3:5: expected '-->'
    sp {x (state <s>) (write hi)}
        ^
"""

from __future__ import annotations

__all__ = [
    "AdaptError",
    "LocatedError",
    "RuleError",
    "RuleSyntaxError",
    "RuleSemanticError",
    "EngineError",
    "ScenarioError",
    "ImaginationError",
    "VisionError",
    "ImageError",
    "TraceError",
    "SchemaError",
    "RealityError",
    "GroundTruthError",
    "RunError",
    "OutputError",
    "AppearanceError",
    "SweepError",
    "SweepSpecError",
    "PluginError",
]


class AdaptError(Exception):
    """Base class of every error adapt raises on purpose."""


class LocatedError(AdaptError):
    """An error at a position in a text file.

    Parameters
    ----------
    message : str
        What was wrong and what was expected.
    file : str
        The file's path as the user gave it (``"<string>"`` for text not read
        from a file).
    line, col : int
        1-based line and column.
    source_line : str, optional
        The text of the offending line, shown with a caret under ``col``.
    """

    def __init__(
        self,
        message: str,
        *,
        file: str = "<string>",
        line: int = 1,
        col: int = 1,
        source_line: str | None = None,
    ) -> None:
        self.message = message
        self.file = file
        self.line = line
        self.col = col
        self.source_line = source_line
        super().__init__(self.__str__())

    @property
    def location(self) -> str:
        """``file:line:col``."""
        return f"{self.file}:{self.line}:{self.col}"

    def __str__(self) -> str:
        text = f"{self.location}: {self.message}"
        if self.source_line is not None:
            line = self.source_line.rstrip("\n").expandtabs(1)
            text += f"\n    {line}\n    {' ' * max(self.col - 1, 0)}^"
        return text


class RuleError(LocatedError):
    """A rule file could not be loaded; nothing from that file was loaded."""


class RuleSyntaxError(RuleError):
    """Rule text that does not follow the grammar of Soar's ``sp`` productions."""


class RuleSemanticError(RuleError):
    """Well-formed rule text that cannot mean anything (an unbound RHS variable,
    a condition not linked to a state, two equality tests in one ``{}``, an
    unknown RHS function, an unsupported Soar construct)."""


class EngineError(AdaptError):
    """The rule engine was used wrongly at run time (for example, writing to the
    input-link outside the input phase)."""


class ScenarioError(LocatedError):
    """A scenario YAML file is malformed; the message names the key path
    (``world.walls[2].height``) and what was expected."""


class ImaginationError(AdaptError):
    """The imagination (physics world, camera, renderer) was given an impossible
    scene or camera."""


class VisionError(AdaptError):
    """Images could not be compared (sizes, dtypes or channels that do not fit)."""


class ImageError(VisionError):
    """An image or video file is missing, unreadable, or not an image."""


class TraceError(AdaptError):
    """A trace file is not a trace, or of another format version."""


class SchemaError(AdaptError):
    """A schema type, parameter or command is wrong (an unknown type, a value
    out of range, a command for a schema that does not exist)."""


class RealityError(AdaptError):
    """A frame source cannot deliver frames (a video that cannot be opened,
    frames of the wrong size, a ground-truth file with bad rows)."""


class GroundTruthError(RealityError, LocatedError):
    """A ground-truth file (``t,object,x,y[,vx,vy]``) has a bad header or row;
    the message names ``file:line:col`` and what was expected."""


class RunError(AdaptError):
    """The scenario runner cannot start or go on (an output folder that cannot
    be written, a reality whose frames do not fit the camera)."""


class OutputError(AdaptError):
    """An output path cannot be used: it is one of the command's inputs or
    another of its outputs, has an extension that does not fit what is written,
    is a folder or a special file, or cannot be written (``adapt/files.py``).
    Nothing has been written when it is raised before the work."""


class AppearanceError(AdaptError):
    """A learned-appearance folder cannot be read or written (a missing or
    malformed ``index.json``, an image or mask that does not fit its entry, a
    surface the scene does not have)."""


class SweepError(AdaptError):
    """A sweep cannot start or go on (no Dask installed, a scheduler that cannot be
    reached, workers that cannot see the scenario, an output folder that holds runs
    of another version of the scenario)."""


class SweepSpecError(SweepError, LocatedError):
    """A ``--seeds`` or ``--set`` argument of a sweep that cannot be read; the
    message points at the column of the argument (``--set:1:31:``)."""


class PluginError(AdaptError):
    """A plugin cannot be loaded: its module is missing, it raised on import, or it
    registered a name that is taken or a malformed type (:mod:`adapt.plugins`)."""
