"""The Soar kernel's process, seen from adapt: start it, talk to it, notice its death.

The kernel runs in a child process (:mod:`adapt.soar.worker`) so that a
crash inside the native kernel ends the run with a clear error, while the
report and the trace of what ran -- kept in this process -- stay complete
and valid.  :class:`KernelProcess` starts ``python -m adapt.soar.worker``
with two pipes, in its own session (a Ctrl-C at the terminal reaches only
adapt, which asks the kernel to stop), and with its standard output and
error in a temporary file whose end is quoted when it dies.

:func:`require_soar` is the check made before anything starts: without
``soar-sml`` installed it says which extra to install.
"""

from __future__ import annotations

import importlib.util
import os
import signal
import subprocess
import sys
import tempfile
import weakref
from multiprocessing.connection import Connection
from pathlib import Path
from typing import Any, BinaryIO

from adapt.errors import AdaptError, EngineError

__all__ = ["KernelProcess", "KernelCrash", "require_soar", "INSTALL_HINT", "WORKER"]

#: The worker script (:mod:`adapt.soar.worker`), run as ``python -I WORKER FD_IN FD_OUT``.
WORKER = Path(__file__).resolve().with_name("worker.py")

#: What to install for ``--engine soar``.
INSTALL_HINT = "pip install 'adapt[soar]' (soar-sml, Soar 9.6)"


class KernelCrash(EngineError):
    """The Soar kernel's process died (a crash in the kernel, or it was killed)."""


def require_soar() -> None:
    """Raise :class:`adapt.errors.AdaptError` unless ``soar_sml`` can be imported.

    The module is looked for, not imported: this process never loads the kernel.
    """
    try:
        found = importlib.util.find_spec("soar_sml") is not None
    except (ImportError, ValueError):  # a broken install, or hidden by sys.modules
        found = False
    if not found:
        raise AdaptError("the Soar engine needs the Soar kernel, which is not installed: "
                         f"{INSTALL_HINT}")


def _describe(code: int | None) -> str:
    if code is None:
        return "stopped answering"
    if code < 0:
        try:
            name = signal.Signals(-code).name
        except ValueError:
            name = f"signal {-code}"
        return f"was killed by {name}"
    return f"exited with status {code}"


def _shutdown(proc: subprocess.Popen[bytes], tx: Connection, log: BinaryIO) -> None:
    try:
        tx.send(("quit",))
    except OSError:
        pass
    try:
        proc.wait(timeout=5)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()
    tx.close()
    log.close()


class KernelProcess:
    """One worker process with one kernel and one agent.

    Raises
    ------
    AdaptError
        When soar-sml is not installed, or the kernel cannot start.
    """

    def __init__(self) -> None:
        require_soar()
        r_child, w_parent = os.pipe()
        r_parent, w_child = os.pipe()
        self.log: BinaryIO = tempfile.TemporaryFile()  # noqa: SIM115 (closed by close())
        try:  # the worker is a script of the standard library and soar_sml: run it by its path
            self.proc = subprocess.Popen(
                [sys.executable, "-I", str(WORKER), str(r_child), str(w_child)],
                pass_fds=(r_child, w_child), stdin=subprocess.DEVNULL, stdout=self.log,
                stderr=self.log, start_new_session=True)
        finally:
            os.close(r_child)
            os.close(w_child)
        self.tx = Connection(w_parent, readable=False)
        self.rx = Connection(r_parent, writable=False)
        self.pid = self.proc.pid
        self.dead: str | None = None
        self._finalizer = weakref.finalize(self, _shutdown, self.proc, self.tx, self.log)

    def send(self, message: tuple[Any, ...]) -> None:
        """Send a request (raises :class:`KernelCrash` if the process is gone)."""
        if self.dead is not None:
            raise KernelCrash(self.dead)
        try:
            self.tx.send(message)
        except OSError:
            raise self._died() from None

    def recv(self) -> tuple[Any, ...]:
        """The next message (raises :class:`KernelCrash` if the process died)."""
        if self.dead is not None:
            raise KernelCrash(self.dead)
        try:
            message: tuple[Any, ...] = self.rx.recv()
        except (EOFError, OSError):
            raise self._died() from None
        if message[0] == "failed":
            self.dead = f"the Soar kernel could not start: {message[1]}"
            raise AdaptError(self.dead)
        return message

    def request(self, message: tuple[Any, ...]) -> tuple[Any, ...]:
        """Send a request and return its reply."""
        self.send(message)
        return self.recv()

    def stop(self) -> None:
        """Ask a running agent to stop (after its current phase)."""
        if self.dead is None and self.proc.poll() is None:
            os.kill(self.pid, signal.SIGUSR1)

    def kill(self) -> None:
        """End the process at once (a second Ctrl-C)."""
        if self.proc.poll() is None:
            self.proc.kill()

    def _died(self) -> KernelCrash:
        try:
            code = self.proc.wait(timeout=5)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            code = self.proc.wait()
        tail = ""
        try:
            self.log.seek(0)
            lines = [line for line in self.log.read().decode("utf-8", "replace").splitlines()
                     if line.strip()]
            if lines:
                tail = f"; its last words: {' | '.join(lines[-3:])[:300]}"
        except OSError:
            pass
        self.dead = f"the Soar kernel's process {_describe(code)}{tail}"
        return KernelCrash(self.dead)

    def close(self) -> None:
        """End the process (asks it to quit, kills it after 5 s)."""
        self._finalizer()
        self.rx.close()
