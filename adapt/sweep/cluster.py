"""Where a sweep's runs go: an embedded Dask cluster, or a scheduler somewhere else.

Dask (``dask[distributed]``) is an optional dependency (``pip install
'adapt[sweep]'``); this module imports it only inside its functions, and
:func:`require_dask` says how to install it when it is missing.

* With neither ``workers`` nor ``scheduler``, :func:`connect` starts an
  embedded ``distributed.LocalCluster`` sized to the machine: one worker
  **process** per available core, one thread each (a run is Python and
  OpenCV; threads would share one interpreter).  It lives as long as the
  sweep; its workers are this process's children and are restarted by their
  nannies if they die.
  More workers than cores are refused (:func:`check_workers`): a run uses a
  core, so they would only wait for one and hold memory.
* ``scheduler`` is the address of a running scheduler (``tcp://host:8786``)
  or the path of its scheduler file (``--scheduler-file`` of ``dask
  scheduler``, as dask-jobqueue and ``dask-mpi`` write it).  Before Dask's
  client is let near a ``tcp://`` address, :func:`check_scheduler` makes sure
  a Dask scheduler answers there: one greets a new connection at once with a
  small handshake frame.  A service that says something else (an SSH banner,
  which Dask would take for the length of a frame of exabytes) or nothing
  within :data:`GREETING_S` seconds (an HTTP server, waiting for a request)
  is refused as "not a Dask scheduler".

The embedded cluster starts its workers without Dask's default
``MALLOC_TRIM_THRESHOLD_`` (see :data:`NO_TRIM`).  Every worker gets a small setup (a worker plugin, so restarted and
late-joining workers get it too): OpenCV uses one thread per task, so N
single-threaded workers use N cores and no more; and the workers of an
embedded cluster ignore Ctrl-C, which is the client's to handle (it cancels
the runs and shuts the cluster down).
"""

from __future__ import annotations

import json
import logging
import os
import socket
import struct
import time
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Iterator

from adapt.errors import SweepError

__all__ = ["require_dask", "connect", "Connection", "default_workers", "check_workers",
           "check_scheduler", "INSTALL", "NO_TRIM", "GREETING_S"]

#: Seconds a scheduler has to accept a connection, and again to greet it (a Dask scheduler
#: sends its handshake the moment it accepts).
GREETING_S = 5.0

#: The largest handshake frame taken for one (Dask's is about a hundred bytes).
_MAX_GREETING = 1 << 16

#: Dask's setting that starts workers with ``MALLOC_TRIM_THRESHOLD_=65536``.  Any explicit trim
#: threshold turns glibc's dynamic mmap threshold off, so every image buffer of a run (a 640x480
#: frame is 0.9 MB) is mapped and faulted in afresh: runs took 1.6-2.1x as long
#: (docs/performance.md, "Sweeps").
#: The embedded cluster leaves it unset; docs/sweeps.md says how to do so on a cluster.
NO_TRIM = "distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_"

#: Dask settings of the embedded cluster: no trim threshold (above); no statistical profiler
#: sampling the running task's stack every 10 ms; memory checked every second rather than ten
#: times a second (a run holds a few hundred MB at most); event-loop health checks every 500 ms
#: rather than 20 ms and system samples every 2 s (they feed warnings and a dashboard the sweep
#: does not serve).  Idle, the cluster's processes then use about 7 ms of CPU a second instead of
#: 40 (docs/performance.md, "Sweeps").
EMBEDDED = {NO_TRIM: None, "distributed.worker.profile.enabled": False,
            "distributed.worker.memory.monitor-interval": "1s",
            "distributed.admin.tick.interval": "500ms",
            "distributed.admin.system-monitor.interval": "2s"}

#: How to install the optional dependency.
INSTALL = "pip install 'adapt[sweep]'  (or: pip install 'dask[distributed]')"


def require_dask() -> None:
    """Raise a :class:`SweepError` saying how to install Dask when it is missing."""
    try:
        import distributed  # noqa: F401
    except ModuleNotFoundError as exc:
        raise SweepError(f"adapt sweep runs on Dask, which is not installed ({exc.msg}); "
                         f"install it with: {INSTALL}") from None


def default_workers() -> int:
    """The cores this process may run on (the embedded cluster's size)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


def check_workers(workers: int) -> None:
    """Refuse a number of embedded workers below 1 or above the cores this process may use.

    >>> check_workers(0)
    Traceback (most recent call last):
    ...
    adapt.errors.SweepError: --workers must be at least 1, got 0
    """
    if workers < 1:
        raise SweepError(f"--workers must be at least 1, got {workers}")
    cores = default_workers()
    if workers > cores:
        raise SweepError(f"--workers {workers}: this machine gives adapt {cores} core"
                         f"{'s' * (cores != 1)}, and a run keeps one busy, so more workers would "
                         f"only wait for a core and hold memory: use --workers 1..{cores}, or "
                         "--scheduler for a cluster (docs/sweeps.md)")


def _tcp_address(scheduler: str) -> tuple[str, int] | None:
    """``(host, port)`` of a ``tcp://host:port`` (or ``host:port``) address; None for another
    kind of address (``tls://``, ``inproc://``), which is left to Dask."""
    text = scheduler.strip()
    if "://" in text:
        scheme, _, text = text.partition("://")
        if scheme != "tcp":
            return None
    host, sep, port = text.rpartition(":")
    if not sep or not port.isdigit() or not host:
        return None
    return host.strip("[]"), int(port)


def _receive(sock: socket.socket, n: int, deadline: float) -> bytes:
    """Up to ``n`` bytes, as many as come before ``deadline`` or the end of the stream."""
    data = b""
    while len(data) < n:
        left = deadline - time.monotonic()
        if left <= 0:
            break
        sock.settimeout(left)
        try:
            chunk = sock.recv(min(n - len(data), 65536))
        except OSError:  # a timeout, a reset
            break
        if not chunk:
            break
        data += chunk
    return data


def check_scheduler(scheduler: str, timeout: float = GREETING_S) -> None:
    """Refuse, within about ``2 * timeout`` seconds, a ``tcp://`` address where no Dask
    scheduler answers (see the module docstring); other kinds of address pass.

    Raises
    ------
    SweepError
        Nothing accepts connections there, or what does is not a Dask scheduler.
    """
    where = _tcp_address(scheduler)
    if where is None:
        return
    try:
        sock = socket.create_connection(where, timeout=timeout)
    except OSError as exc:
        raise SweepError(f"cannot reach the Dask scheduler {scheduler!r}: "
                         f"{exc.strerror or exc}; start one with `dask scheduler` (see "
                         "docs/sweeps.md)") from None
    with sock:
        deadline = time.monotonic() + timeout
        head = _receive(sock, 8, deadline)
        size = struct.unpack("Q", head)[0] if len(head) == 8 else None
        if size is not None and 0 < size <= _MAX_GREETING:
            body = _receive(sock, size, deadline)
        else:  # a little more of what it said, to show it
            body = _receive(sock, 56, min(deadline, time.monotonic() + 0.2)) if head else b""
    if size is not None and len(body) == size and b"pickle-protocol" in body:
        return
    if not head:
        said = f"it said nothing within {timeout:g} s of connecting"
    else:
        said = f"it began with {(head + body)[:64]!r}"
    raise SweepError(f"{scheduler!r} is not a Dask scheduler: {said}, where a Dask scheduler "
                     "greets at once with its handshake; check the address and the port "
                     "(`dask scheduler` prints them; docs/sweeps.md)")


@dataclass
class Connection:
    """A connected client and what it is connected to."""

    client: Any
    description: str
    embedded: bool

    def workers(self) -> set[str]:
        """The addresses of the workers the scheduler knows now."""
        info = self.client.scheduler_info()
        return set(info.get("workers", {}))


def _setup_plugin(ignore_sigint: bool) -> Any:
    from distributed.diagnostics.plugin import WorkerPlugin

    class AdaptWorkerSetup(WorkerPlugin):  # pickled by value (cloudpickle)
        name = "adapt-sweep-setup"

        def __init__(self, ignore: bool) -> None:
            self.ignore = ignore

        def setup(self, worker: Any) -> None:
            try:
                import cv2

                cv2.setNumThreads(1)
            except ImportError:  # pragma: no cover - adapt needs OpenCV
                pass
            if self.ignore:
                import signal
                import threading

                if threading.current_thread() is threading.main_thread():
                    signal.signal(signal.SIGINT, signal.SIG_IGN)

    return AdaptWorkerSetup(ignore_sigint)


@contextmanager
def connect(workers: int | None = None, scheduler: str | None = None,
            quiet: bool = True) -> Iterator[Connection]:
    """A connected :class:`Connection` (see the module docstring); closed on leaving.

    Parameters
    ----------
    workers : int, optional
        Worker processes of an embedded cluster (default: :func:`default_workers`).
    scheduler : str, optional
        A scheduler's address or scheduler file; excludes ``workers``.
    quiet : bool
        Keep Dask's own log messages below errors off standard error.
    """
    require_dask()
    from distributed import Client, LocalCluster

    if workers is not None and scheduler is not None:
        raise SweepError("give either a number of workers or a scheduler, not both")
    if workers is not None:
        check_workers(workers)
    level = logging.ERROR if quiet else logging.WARNING
    saved = {name: logging.getLogger(name).level for name in ("distributed", "tornado")}
    for name in saved:
        logging.getLogger(name).setLevel(level)
    cluster = None
    try:
        if scheduler is None:
            import dask

            n = workers or default_workers()
            with dask.config.set(EMBEDDED):  # the nannies and workers read it once, at start
                cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                                       dashboard_address="127.0.0.1:0", silence_logs=level)
            client = Client(cluster)
            description = f"an embedded local cluster of {n} worker process{'es' * (n != 1)}"
        else:
            client = _remote(scheduler)
            description = f"the scheduler at {client.scheduler.address}"
        try:
            client.register_plugin(_setup_plugin(ignore_sigint=cluster is not None))
            yield Connection(client, description, cluster is not None)
        finally:
            try:
                client.close(timeout=10)
            except Exception:  # a dead scheduler: nothing more to close
                pass
    finally:
        if cluster is not None:
            try:
                cluster.close(timeout=10)
            except Exception:  # pragma: no cover - shutting down anyway
                pass
        for name, lvl in saved.items():
            logging.getLogger(name).setLevel(lvl)


def _remote(scheduler: str) -> Any:
    from distributed import Client

    path = Path(scheduler).expanduser()
    try:
        if path.suffix == ".json" or path.is_file():
            if not path.is_file():
                raise SweepError(f"no scheduler file {str(path)!r}")
            check_scheduler(_file_address(path))
            return Client(scheduler_file=str(path), timeout="20s")
        check_scheduler(scheduler)
        return Client(scheduler, timeout="20s")
    except SweepError:
        raise
    except (OSError, TimeoutError, ValueError) as exc:
        raise SweepError(f"cannot reach the Dask scheduler {scheduler!r}: {exc}; start one "
                         "with `dask scheduler` (see docs/sweeps.md)") from None


def _file_address(path: Path) -> str:
    """The ``address`` a scheduler file gives (``""`` when it gives none: Dask says why)."""
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return ""
    address = data.get("address") if isinstance(data, dict) else None
    return address if isinstance(address, str) else ""
