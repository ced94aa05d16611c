"""One PyBullet physics client, and the only place that imports PyBullet.

PyBullet is an optional extra (``pip install 'adapt[bullet]'``): adapt imports
and runs without it, and a scenario that asks for a ``bullet`` reality gets a
:class:`~adapt.errors.RealityError` naming the package to install when the
reality is opened (:func:`load_pybullet`).

A :class:`Client` is a headless (``DIRECT``) PyBullet server of its own.  Every
call goes through it: ``client.stepSimulation()`` is
``pybullet.stepSimulation(physicsClientId=client.id)``, and an error PyBullet
raises becomes a :class:`~adapt.errors.RealityError` that says which call
failed, so PyBullet's own errors never reach the user as tracebacks::

    with Client("scene.yaml:12:3") as c:
        body = c.createMultiBody(baseMass=0)
        c.getNumBodies()     # 1
"""

from __future__ import annotations

import contextlib
import ctypes
import importlib
import os
import sys
from types import ModuleType, TracebackType
from typing import Any, Callable, Iterator

from adapt.errors import RealityError

__all__ = ["Client", "load_pybullet", "INSTALL"]

#: What to run to get PyBullet.
INSTALL = "pip install 'adapt[bullet]'"


def load_pybullet(where: str = "") -> ModuleType:
    """The ``pybullet`` module.

    Raises
    ------
    RealityError
        When PyBullet is not installed; the message starts with ``where`` (the
        scenario's position of the reality) and names the command to install it.
    """
    try:
        loaded = sys.modules.get("pybullet")
        if loaded is not None:
            return loaded
        with _quiet():  # PyBullet prints its build time when imported
            return importlib.import_module("pybullet")
    except ImportError:
        prefix = f"{where}: " if where else ""
        raise RealityError(f"{prefix}a 'bullet' reality needs PyBullet, which is not installed; "
                           f"install it with: {INSTALL}") from None


@contextlib.contextmanager
def _quiet() -> Iterator[None]:
    """File descriptors 1 and 2 go to the null device meanwhile (C's buffers flushed
    before they come back), so what a C extension prints at import (PyBullet: its build
    time, on stderr) never reaches the user's terminal or output."""
    try:
        sys.stdout.flush()
        sys.stderr.flush()
        saved = [os.dup(1), os.dup(2)]
    except (OSError, ValueError):
        yield
        return
    null = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(null, 1)
        os.dup2(null, 2)
        yield
    finally:
        with contextlib.suppress(OSError, AttributeError):
            ctypes.CDLL(None).fflush(None)
        os.dup2(saved[0], 1)
        os.dup2(saved[1], 2)
        for fd in (*saved, null):
            os.close(fd)


class Client:
    """A headless PyBullet physics server (see the module docstring).

    Parameters
    ----------
    where : str
        The scenario position named in errors (PyBullet missing, a failed call).
    """

    def __init__(self, where: str = "") -> None:
        self.pb = load_pybullet(where)
        self.where = where
        self.id: int = -1
        try:
            self.id = int(self.pb.connect(self.pb.DIRECT))
        except self.pb.error as exc:
            raise RealityError(self._message("connect", exc)) from None
        if self.id < 0:
            raise RealityError(self._message("connect", "no physics server"))

    def _message(self, name: str, exc: object) -> str:
        prefix = f"{self.where}: " if self.where else ""
        return f"{prefix}PyBullet failed in {name}: {exc}"

    def __getattr__(self, name: str) -> Callable[..., Any]:
        if name.startswith("_") or name in ("pb", "id", "where"):
            raise AttributeError(name)
        function = getattr(self.pb, name)
        if not callable(function):
            return function  # type: ignore[no-any-return]  # a constant such as GEOM_BOX

        def call(*args: Any, **kwargs: Any) -> Any:
            if self.id < 0:
                raise RealityError(self._message(name, "the physics client is closed"))
            try:
                return function(*args, physicsClientId=self.id, **kwargs)
            except self.pb.error as exc:
                raise RealityError(self._message(name, exc)) from None

        return call

    def close(self) -> None:
        """Disconnect (once)."""
        if self.id >= 0:
            try:
                self.pb.disconnect(physicsClientId=self.id)
            except self.pb.error:
                pass
            self.id = -1

    def __enter__(self) -> "Client":
        return self

    def __exit__(self, kind: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        self.close()

    def __del__(self) -> None:
        try:
            self.close()
        except Exception:  # interpreter shutdown: the module may be gone
            pass
