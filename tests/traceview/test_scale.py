"""``show``, ``wm`` and ``stats`` on a 100,000-decision trace: seconds, bounded memory.

Each command runs in its own process, which reports its peak resident memory
(``VmHWM``); the trace file is about 150 MB, so a reader that loaded it whole
would need well over a gigabyte.
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


#: Runs the CLI, then reports the process's own peak RSS (VmHWM belongs to the new
#: address space, so it does not include the pytest process the child was forked from).
RUNNER = (
    "import sys\n"
    "from adapt.cli import main\n"
    "status = main(sys.argv[1:])\n"
    "sys.stdout.flush()\n"
    "hwm = [l for l in open('/proc/self/status') if l.startswith('VmHWM')][0].split()[1]\n"
    "print('VmHWM', hwm, file=sys.stderr)\n"
    "sys.exit(status)\n"
)


def measured(*argv: str) -> tuple[float, float, str]:
    """Run ``adapt ARGV`` in a fresh process; return (seconds, peak RSS in MB, stdout)."""
    root = str(Path(__file__).resolve().parents[2])
    env = {**os.environ, "PYTHONPATH": root + os.pathsep + os.environ.get("PYTHONPATH", "")}
    start = time.perf_counter()
    proc = subprocess.run([sys.executable, "-c", RUNNER, *argv], capture_output=True, env=env,
                          check=False)
    elapsed = time.perf_counter() - start
    err = proc.stderr.decode()
    assert proc.returncode == 0, err
    peak_kb = int(err.rsplit("VmHWM", 1)[1].split()[0])
    return elapsed, peak_kb / 1024, proc.stdout.decode()


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
