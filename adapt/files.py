"""Output files: checked before any work, then written atomically.

Every command that writes follows the same two steps.

1. **Check** (:func:`check_outputs`), before any work and before anything is
   written: no output may be one of the command's inputs, nor another of its
   own outputs (the same file once resolved: symlinks and hard links count);
   each must have an extension that fits what is written, must not be a
   folder or a special file, and its folder must be writable (or creatable:
   missing folders are made when the file is written).  A failure raises
   :class:`adapt.errors.OutputError` naming the option and the path.
2. **Write** (:func:`write_output`, or :func:`atomic_path` for writers that
   need a file name, such as a video encoder): to a temporary file beside the
   target, renamed over it only when complete, so an error or an interrupt
   never leaves a half-written file and never destroys the previous one.
   Missing folders are created first.  Errors name the output, never the
   temporary file.

This module imports only the standard library and :mod:`adapt.errors`.

Examples
--------
>>> import tempfile, pathlib
>>> d = pathlib.Path(tempfile.mkdtemp())
>>> write_atomic(d / "a.txt", b"hello").read_bytes()
b'hello'
>>> sorted(p.name for p in d.iterdir())
['a.txt']
>>> check_outputs([Output("--out", d / "a.txt", (".html",))], [])
Traceback (most recent call last):
...
adapt.errors.OutputError: --out '...a.txt': expected a .html file name
>>> check_outputs([Output("--trace", d / "a.txt")], [("the rule file", d / "a.txt")])
Traceback (most recent call last):
...
adapt.errors.OutputError: --trace '...a.txt' is the rule file; an output never replaces an input: choose another file name
>>> write_output(Output("--out", d / "new" / "b.txt"), b"x").read_bytes()
b'x'
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Iterable, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Iterator

from adapt.errors import OutputError

__all__ = ["Output", "atomic_path", "write_atomic", "same_file", "check_outputs",
           "make_folder", "write_output"]

#: An input of a command: how to name it in a message ("the rule file") and its path.
Input = tuple[str, "str | os.PathLike[str]"]


@dataclass(frozen=True, slots=True)
class Output:
    """One file a command writes.

    Attributes
    ----------
    option : str
        How the user named it, for messages: ``"--out"``, ``"--trace"``.
    path : Path
        The file.
    suffixes : tuple of str
        The extensions that fit what is written, lower case with the dot
        (``(".html", ".htm")``); empty for any.
    """

    option: str
    path: Path
    suffixes: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        object.__setattr__(self, "path", Path(self.path))


def same_file(a: str | os.PathLike[str], b: str | os.PathLike[str]) -> bool:
    """Whether two paths name one file (after resolving ``..`` and symlinks, or by hard link).

    >>> same_file("a/../b.txt", "b.txt")
    True
    """
    pa, pb = Path(a), Path(b)
    try:
        if pa.resolve() == pb.resolve():
            return True
        return pa.exists() and pb.exists() and os.path.samefile(pa, pb)
    except (OSError, RuntimeError, ValueError):  # a symlink loop, an embedded NUL
        return os.path.abspath(pa) == os.path.abspath(pb)


def _quoted(path: Path) -> str:
    return repr(str(path))


def _check_one(out: Output) -> None:
    path = out.path
    name = f"{out.option} {_quoted(path)}"
    if "\x00" in str(path):
        raise OutputError(f"{out.option}: the path holds a NUL character; expected a file name")
    if out.suffixes and path.suffix.lower() not in out.suffixes:
        wanted = " or ".join(out.suffixes)
        raise OutputError(f"{name}: expected a {wanted} file name")
    try:
        if path.exists() and not path.is_file():
            kind = "a directory" if path.is_dir() else "not a regular file"
            raise OutputError(f"{name} is {kind}; expected a file name")
        folder = Path(os.path.abspath(path)).parent
        while not folder.exists() and folder != folder.parent:
            folder = folder.parent
        if not folder.is_dir():
            raise OutputError(f"{name}: {_quoted(folder)} is not a folder")
    except OSError as exc:  # a name too long, a loop of symlinks
        raise OutputError(f"{name}: {exc.strerror or exc}") from None
    try:  # a real probe: os.access says yes to root even on read-only file systems
        fd, probe = tempfile.mkstemp(dir=folder, prefix=".adapt-probe-")
        os.close(fd)
        os.unlink(probe)
    except OSError as exc:
        raise OutputError(f"{name}: cannot write in the folder {_quoted(folder)} "
                          f"({exc.strerror or exc})") from None


def check_outputs(outputs: Iterable[Output], inputs: Iterable[Input] = ()) -> None:
    """Refuse, before any work, outputs that cannot be written or would destroy something.

    Parameters
    ----------
    outputs : iterable of Output
        Every file the command will write.
    inputs : iterable of (str, path)
        Every file the command reads, with how to name it ("the rule file").

    Raises
    ------
    adapt.errors.OutputError
        If an output is an input or another output, has an extension that
        does not fit, is a folder or a special file, or its folder cannot be
        written.  Nothing has been written then.
    """
    sources = [(what, Path(p)) for what, p in inputs]
    seen: list[Output] = []
    for out in outputs:
        for earlier in seen:
            if same_file(out.path, earlier.path):
                raise OutputError(f"{out.option} {_quoted(out.path)} is the same file as "
                                  f"{earlier.option} {_quoted(earlier.path)}; expected a "
                                  "different file for each output")
        for what, source in sources:
            if same_file(out.path, source):
                raise OutputError(f"{out.option} {_quoted(out.path)} is {what}; an output never "
                                  "replaces an input: choose another file name")
        _check_one(out)
        seen.append(out)


def make_folder(out: Output) -> None:
    """Create the output's missing folders.

    Raises
    ------
    adapt.errors.OutputError
        If they cannot be created.
    """
    try:
        out.path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OutputError(f"{out.option} {_quoted(out.path)}: cannot create its folder "
                          f"({exc.strerror or exc})") from None


def write_output(out: Output, data: bytes) -> Path:
    """Write ``data`` to a checked output: its folders created, the file written atomically.

    Raises
    ------
    adapt.errors.OutputError
        If it cannot be written; the message names the output, not a temporary file.
    """
    make_folder(out)
    try:
        return write_atomic(out.path, data)
    except OSError as exc:
        raise OutputError(f"{out.option} {_quoted(out.path)}: cannot write it "
                          f"({exc.strerror or exc})") from None


def _permit(path: str) -> None:
    """Give a temporary file the permissions a plain ``open`` would have."""
    mask = os.umask(0)
    os.umask(mask)
    os.chmod(path, 0o666 & ~mask)


def _about(exc: OSError, tmp: str | None, target: Path) -> OSError:
    """``exc`` told about ``target`` instead of the temporary file ``tmp``."""
    names: Sequence[object] = (exc.filename, exc.filename2)
    if tmp is None or tmp in names or exc.filename is None:
        return OSError(exc.errno, exc.strerror or str(exc), str(target))
    return exc


@contextmanager
def atomic_path(path: str | os.PathLike[str], suffix: str = ".tmp") -> Iterator[str]:
    """A temporary path beside ``path`` to write to; renamed over ``path`` when
    the block ends normally, removed when it raises.

    ``suffix`` keeps the extension a writer may need (``.mp4`` for a video).
    An :class:`OSError` about the temporary file is raised as one about
    ``path``, so messages never show the temporary name.
    """
    target = Path(path)
    try:
        fd, tmp = tempfile.mkstemp(dir=target.parent, prefix=f".{target.name}.", suffix=suffix)
    except OSError as exc:
        raise _about(exc, None, target) from None
    os.close(fd)
    try:
        yield tmp
        _permit(tmp)
        os.replace(tmp, target)
    except BaseException as exc:
        if os.path.exists(tmp):
            os.unlink(tmp)
        if isinstance(exc, OSError):
            raise _about(exc, tmp, target) from None
        raise


def write_atomic(path: str | os.PathLike[str], data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically; return the path."""
    with atomic_path(path) as tmp:
        with open(tmp, "wb") as f:
            f.write(data)
    return Path(path)
