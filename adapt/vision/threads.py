"""OpenCV's thread count, set deliberately.

OpenCV parallelises warps, blurs and LK pyramids over a thread pool whose
default size is the number of cores.  On the 2-core machines adapt targets,
2 threads measured 15-21 ms per MMD frame against 22-29 ms with 1 thread
(``docs/mmd.md``).  Importing :mod:`adapt.vision` does not touch the pool; the
command line and the benchmark call :func:`set_threads`.

Examples
--------
>>> previous = set_threads(1)
>>> set_threads(previous)
1
"""

from __future__ import annotations

import cv2

__all__ = ["set_threads", "DEFAULT_THREADS"]

#: Threads the command line and the benchmark use.
DEFAULT_THREADS = 2


def set_threads(n: int) -> int:
    """Set OpenCV's thread count to ``n`` (``0`` = sequential) and return the
    previous count."""
    if n < 0:
        raise ValueError(f"thread count must be 0 or more, got {n}")
    previous = int(cv2.getNumThreads())
    cv2.setNumThreads(int(n))
    return previous
