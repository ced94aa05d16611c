"""Where a value came from: the position of a key or value in a scenario file.

Every record the reader builds for the runner's sections keeps the
:class:`Source` of its YAML node, and the loaded scenario keeps one for every
key path it read (:meth:`adapt.scenario.Scenario.where`).  So an error found
long after reading -- an unknown schema type, a goal naming an unknown
object, a rule file with an error -- still points at ``file:line:col`` with
the key path, exactly like an error the reader finds itself.

Examples
--------
>>> src = Source("s.yaml", 4, 9, "schemas.sceen-background", "  sceen-background: {}")
>>> print(src.error("unknown schema type; expected one of scene-background"))
s.yaml:4:9: schemas.sceen-background: unknown schema type; expected one of scene-background
      sceen-background: {}
            ^
"""

from __future__ import annotations

from dataclasses import dataclass

from adapt.errors import ScenarioError

__all__ = ["Source", "UNKNOWN"]


@dataclass(frozen=True, slots=True)
class Source:
    """A position in a scenario file (or in a ``--set`` override).

    Attributes
    ----------
    file : str
        The file as the user named it (``"--set"`` for an override given on
        the command line).
    line, col : int
        1-based.
    path : str
        The key path (``world.walls[2].height``); ``""`` for the document.
    text : str or None
        The source line, shown with a caret.
    """

    file: str
    line: int
    col: int
    path: str
    text: str | None = None

    def error(self, message: str, *, path: str | None = None) -> ScenarioError:
        """A :class:`~adapt.errors.ScenarioError` at this position:
        ``file:line:col: key.path: message``."""
        where = self.path if path is None else path
        prefix = f"{where}: " if where else ""
        return ScenarioError(prefix + message, file=self.file, line=self.line, col=self.col,
                             source_line=self.text)

    @property
    def location(self) -> str:
        """``file:line:col``."""
        return f"{self.file}:{self.line}:{self.col}"


#: The source of values that did not come from a file (defaults, records built in code).
UNKNOWN = Source("<default>", 1, 1, "")
