"""A one-line progress display on a terminal, rewritten in place (``adapt run``, ``adapt sweep``)."""

from __future__ import annotations

from typing import TextIO

__all__ = ["ProgressLine"]


class ProgressLine:
    """Shows a line of text on ``stream``, each new one over the last; :meth:`clear` wipes it."""

    def __init__(self, stream: TextIO) -> None:
        self.stream = stream
        self.width = 0

    def show(self, text: str) -> None:
        self.stream.write("\r" + text.ljust(self.width))
        self.width = len(text)
        self.stream.flush()

    def clear(self) -> None:
        if self.width:
            self.stream.write("\r" + " " * self.width + "\r")
            self.stream.flush()
            self.width = 0
