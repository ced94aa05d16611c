"""What native libraries print, kept under adapt's own messages.

libpng, libjpeg, FFmpeg and OpenCV write their complaints straight to the
standard-error file descriptor (``libpng error: IDAT: invalid distance too
far back``), before and apart from adapt's own message about the same file.
:func:`native_messages` catches them while an image or a video is decoded:
the caller folds them into its error (:meth:`NativeMessages.detail`) or drops
them when the file was read after all (a warning about a colour profile).
Lines that do not look like a native library's (a Python thread printing at
that moment) are written back to standard error.

This module imports only the standard library.

Examples
--------
>>> import os
>>> with native_messages() as caught:
...     _ = os.write(2, b"libpng error: IHDR: CRC error\\n")
>>> caught.lines, caught.detail()
(['libpng error: IHDR: CRC error'], ' (libpng error: IHDR: CRC error)')
"""

from __future__ import annotations

import os
import re
import sys
import tempfile
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field

__all__ = ["native_messages", "NativeMessages"]

#: Lines native image and video libraries print.
_NATIVE = re.compile(r"^(libpng (error|warning)|\[ *(WARN|ERROR|INFO)[:\]]|Corrupt JPEG|"
                     r"Premature end of JPEG|Invalid SOS|Bogus|\[[a-z0-9_]+ @ 0x[0-9a-f]+\]|"
                     r"JPEG|libjpeg|TIFF|OpenCV)")

#: OpenCV's log lines: ``[ WARN:0@0.108] global grfmt_png.cpp:793 readFromStreamOrBuffer TEXT``.
_OPENCV = re.compile(r"^\[ *(?:WARN|ERROR|INFO):[^\]]*\] *(?:global +)?\S+:\d+ +\S+ +(.*)$")

#: At most this much of what they print is kept.
_KEEP = 4096

_LOCK = threading.Lock()


@dataclass
class NativeMessages:
    """The lines caught (filled when the block ends)."""

    lines: list[str] = field(default_factory=list)

    def detail(self) -> str:
        """`` (first line; second line)`` to end an error message with, or ``""``."""
        if not self.lines:
            return ""
        text = "; ".join(_OPENCV.sub(r"OpenCV: \1", line) for line in self.lines[:2])
        return f" ({text[:200]})"


@contextmanager
def native_messages() -> Iterator[NativeMessages]:
    """Catch what is written to file descriptor 2 while the block runs (see the module
    docstring).  One block at a time in a process (a lock); without a file descriptor 2 it
    catches nothing."""
    caught = NativeMessages()
    with _LOCK:
        try:
            sys.stderr.flush()
            saved = os.dup(2)
        except (OSError, ValueError, AttributeError):
            yield caught
            return
        try:
            with tempfile.TemporaryFile() as sink:
                os.dup2(sink.fileno(), 2)
                try:
                    yield caught
                finally:
                    os.dup2(saved, 2)
                    sink.seek(0)
                    _sort(sink.read(_KEEP).decode("utf-8", "replace"), caught)
        finally:
            os.close(saved)


def _sort(text: str, caught: NativeMessages) -> None:
    """Keep the native libraries' lines; write the others back to standard error."""
    other: list[str] = []
    for line in text.splitlines():
        if line.strip():
            (caught.lines if _NATIVE.match(line.strip()) else other).append(line.strip())
    if other:
        try:
            sys.stderr.write("\n".join(other) + "\n")
        except (OSError, ValueError):
            pass
