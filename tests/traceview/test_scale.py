"""``show``, ``wm`` and ``stats`` on a 100,000-decision trace: seconds, bounded memory.

Each command runs in its own process so that its peak resident memory can be
read from ``wait4``; the trace file is about 150 MB, so a reader that loaded
it whole would need well over a gigabyte.
"""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

TIME_LIMIT_S = 60.0
MEMORY_LIMIT_MB = 120.0


def measured(*argv: str) -> tuple[float, float, str]:
    """Run ``python -m adapt ARGV``; return (seconds, peak RSS in MB, stdout)."""
    start = time.perf_counter()
    root = str(Path(__file__).resolve().parents[2])
    env = {**os.environ, "PYTHONPATH": root + os.pathsep + os.environ.get("PYTHONPATH", "")}
    proc = subprocess.Popen([sys.executable, "-m", "adapt", *argv], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, env=env)
    chunks = []
    assert proc.stdout is not None
    for chunk in iter(lambda: proc.stdout.read(1 << 16), b""):
        chunks.append(chunk)
    _, status, usage = os.wait4(proc.pid, 0)
    proc.returncode = os.waitstatus_to_exitcode(status)
    elapsed = time.perf_counter() - start
    err = proc.stderr.read().decode() if proc.stderr else ""
    assert proc.returncode == 0, err
    return elapsed, usage.ru_maxrss / 1024, b"".join(chunks).decode()


@pytest.mark.parametrize("argv, expect", [
    (("stats",), "decisions: 100000"),
    # the counter skips one increment per tie: count = D - D // 50
    (("wm", "--at", "99999", "--depth", "1"), f"(S1 ^count {99999 - 99999 // 50} "),
    (("show", "--level", "4", "--decisions", "99990..99991"), "99991: O: O"),
    (("show",), "100000: ==>S: S2001 (operator tie)"),  # the 2000th tie
])
def test_big_trace_commands_stream(big_trace, argv, expect) -> None:
    elapsed, peak_mb, out = measured("trace", argv[0], str(big_trace), *argv[1:])
    print(f"\nadapt trace {' '.join(argv)}: {elapsed:.1f} s, peak RSS {peak_mb:.0f} MB")
    assert expect in out
    assert elapsed < TIME_LIMIT_S
    assert peak_mb < MEMORY_LIMIT_MB
