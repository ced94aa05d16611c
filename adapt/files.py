"""Output files: checked before any work, written atomically, one command per folder.

Every command that writes follows the same steps.

1. **Check** (:func:`check_outputs`), before any work and before anything is
   written: no output may be one of the command's :class:`Inputs` (everything
   it reads: a scenario lists its own with ``Scenario.inputs()``), nor another
   of its own outputs (the same file once resolved: symlinks and hard links
   count); a folder output (``figures/``) may hold no input, whatever the
   names of the files it will write; each file must have an extension that
   fits what is written, must not be a folder or a special file, and its
   folder must be writable (or creatable: missing folders are made when the
   file is written).  A failure raises :class:`adapt.errors.OutputError`
   naming the option and the path.
2. **Lock** (:func:`lock_folder`): a command that fills a folder (``adapt
   run``, ``adapt sweep``) holds ``.adapt.lock`` in it while it runs, so two
   of them never write into one folder at once; holding it, the command
   removes the temporary files a killed command left there.
3. **Write** (:func:`write_output`, or :func:`atomic_path` for writers that
   need a file name, such as a video encoder): to a temporary file beside the
   target, renamed over it only when complete, so an error or an interrupt
   never leaves a half-written file and never destroys the previous one.
   Every temporary file's name starts with :data:`TEMP_PREFIX`.  Missing
   folders are created first.  Errors name the output, never the temporary
   file.

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
>>> check_outputs([Output("the figures", d, folder=True)], Inputs([("the texture", d / "a.txt")]))
Traceback (most recent call last):
...
adapt.errors.OutputError: the figures '...' would hold the texture ('...a.txt'); an output never replaces an input: choose another file name
>>> write_output(Output("--out", d / "new" / "b.txt"), b"x").read_bytes()
b'x'
"""

from __future__ import annotations

import os
import stat
import tempfile
from collections.abc import Iterable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import IO, Union

from adapt.errors import OutputError

__all__ = ["Output", "Input", "Inputs", "atomic_path", "write_atomic", "same_file",
           "check_outputs", "make_folder", "write_output", "temporary_file", "lock_folder",
           "FolderLock", "remove_stale", "is_special", "TEMP_PREFIX", "LOCK_NAME"]

#: The start of the name of every temporary file adapt writes (``.adapt-tmp-report.json.x1y2.tmp``):
#: a command that holds a folder's lock removes the ones a killed command left there.
TEMP_PREFIX = ".adapt-tmp-"

#: The lock file of a folder a command fills (:func:`lock_folder`).
LOCK_NAME = ".adapt.lock"


@dataclass(frozen=True, slots=True)
class Output:
    """One file -- or one folder of files -- a command writes.

    Attributes
    ----------
    option : str
        How the user named it, for messages: ``"--out"``, ``"--trace"``,
        ``"the figures output"``.
    path : Path
        The file (or folder).
    suffixes : tuple of str
        The extensions that fit what is written, lower case with the dot
        (``(".html", ".htm")``); empty for any.
    folder : bool
        A folder the command fills with files (``figures/``): it may hold no
        input, whatever the names of the files it will write.
    remedy : str
        What to do instead, ending the messages that refuse it.
    """

    option: str
    path: Path
    suffixes: tuple[str, ...] = ()
    folder: bool = False
    remedy: str = "choose another file name"

    def __post_init__(self) -> None:
        object.__setattr__(self, "path", Path(self.path))


@dataclass(frozen=True, slots=True)
class Input:
    """One thing a command reads.

    Attributes
    ----------
    what : str
        How to name it in a message: ``"the scenario"``, ``"the scenario's
        world.floor.texture"``.
    path : Path
    folder : bool
        A folder read whole (a learned appearance): no output may be written
        inside it.
    """

    what: str
    path: Path
    folder: bool = False

    def __post_init__(self) -> None:
        object.__setattr__(self, "path", Path(self.path))


#: An input as a record or as ``(what, path)``.
InputLike = Union[Input, "tuple[str, str | os.PathLike[str]]"]


def _identity(path: Path) -> tuple[str, tuple[int, int] | None]:
    """The resolved path and, for an existing file, its (device, inode): what makes two
    names one file."""
    try:
        resolved = str(path.resolve())
    except (OSError, RuntimeError, ValueError):  # a symlink loop, an embedded NUL
        return os.path.abspath(path), None
    try:
        st = os.stat(path)
    except (OSError, ValueError):
        return resolved, None
    return resolved, (st.st_dev, st.st_ino)


class Inputs:
    """Everything a command reads: an ordered set of :class:`Input`, open to additions
    (a scenario's own files, the files its rules ``source``, and whatever a later part
    of adapt reads).

    Looking a path up is a dictionary access, so a video of ten thousand frames
    costs no more to guard than one file.

    Examples
    --------
    >>> ins = Inputs([("the scenario", "s.yaml")])
    >>> ins.add("the rule file", "rules/../r.soar")
    >>> [i.what for i in ins], ins.find("r.soar").what, ins.find("x.png")
    (['the scenario', 'the rule file'], 'the rule file', None)
    """

    def __init__(self, items: Iterable[InputLike] = ()) -> None:
        self._items: list[Input] = []
        self._given: set[str] = set()  # paths as given: a path added again is not resolved again
        self._by_name: dict[str, Input] = {}
        self._by_id: dict[tuple[int, int], Input] = {}
        self._folders: list[tuple[str, Input]] = []
        self.extend(items)

    def add(self, what: str, path: str | os.PathLike[str], *, folder: bool = False) -> None:
        """Add one input (a path already listed keeps its first name)."""
        item = Input(what, Path(path), folder)
        if str(item.path) in self._given:
            return
        self._given.add(str(item.path))
        name, ident = _identity(item.path)
        if name in self._by_name or (ident is not None and ident in self._by_id):
            return
        self._items.append(item)
        self._by_name[name] = item
        if ident is not None:
            self._by_id[ident] = item
        if folder:
            self._folders.append((name, item))

    def extend(self, items: Iterable[InputLike]) -> None:
        """Add every input of ``items`` (records, or ``(what, path)`` pairs)."""
        for item in items:
            if isinstance(item, Input):
                self.add(item.what, item.path, folder=item.folder)
            else:
                self.add(item[0], item[1])

    def __iter__(self) -> Iterator[Input]:
        return iter(self._items)

    def __len__(self) -> int:
        return len(self._items)

    def find(self, path: str | os.PathLike[str]) -> Input | None:
        """The input that writing ``path`` would replace: the same file (by name once
        resolved, or by hard link), or a file inside an input folder."""
        name, ident = _identity(Path(path))
        hit = self._by_name.get(name) or (self._by_id.get(ident) if ident is not None else None)
        if hit is not None:
            return hit
        for folder, item in self._folders:
            if _inside(name, folder):
                return item
        return None

    def within(self, folder: str | os.PathLike[str]) -> Input | None:
        """An input inside ``folder`` (or the folder itself), or None."""
        top, _ = _identity(Path(folder))
        for name, item in self._by_name.items():
            if _inside(name, top) or (item.folder and _inside(top, name)):
                return item
        return None


def _inside(name: str, folder: str) -> bool:
    """Whether the resolved path ``name`` is ``folder`` or inside it."""
    return name == folder or name.startswith(folder.rstrip(os.sep) + os.sep)


def same_file(a: str | os.PathLike[str], b: str | os.PathLike[str]) -> bool:
    """Whether two paths name one file (after resolving ``..`` and symlinks, or by hard link).

    >>> same_file("a/../b.txt", "b.txt")
    True
    """
    name_a, id_a = _identity(Path(a))
    name_b, id_b = _identity(Path(b))
    return name_a == name_b or (id_a is not None and id_a == id_b)


def _quoted(path: Path) -> str:
    return repr(str(path))


def _check_one(out: Output) -> None:
    path = out.path
    name = f"{out.option} {_quoted(path)}"
    if "\x00" in str(path):
        raise OutputError(f"{out.option}: the path holds a NUL character; expected a "
                          f"{'folder' if out.folder else 'file'} name")
    if out.suffixes and path.suffix.lower() not in out.suffixes:
        wanted = " or ".join(out.suffixes)
        raise OutputError(f"{name}: expected a {wanted} file name")
    try:
        if out.folder:
            if path.exists() and not path.is_dir():
                raise OutputError(f"{name} is a file; expected a folder")
        elif path.exists() and not path.is_file():
            kind = "a directory" if path.is_dir() else "not a regular file"
            raise OutputError(f"{name} is {kind}; expected a file name")
        folder = Path(os.path.abspath(path)) if out.folder else Path(os.path.abspath(path)).parent
        while not folder.exists() and folder != folder.parent:
            folder = folder.parent
        if not folder.is_dir():
            raise OutputError(f"{name}: {_quoted(folder)} is not a folder")
    except OSError as exc:  # a name too long, a loop of symlinks
        raise OutputError(f"{name}: {exc.strerror or exc}") from None
    try:  # a real probe: os.access says yes to root even on read-only file systems
        fd, probe = tempfile.mkstemp(dir=folder, prefix=f"{TEMP_PREFIX}probe.")
        os.close(fd)
        os.unlink(probe)
    except OSError as exc:
        raise OutputError(f"{name}: cannot write in the folder {_quoted(folder)} "
                          f"({exc.strerror or exc})") from None


def check_outputs(outputs: Iterable[Output], inputs: Iterable[InputLike] | Inputs = ()) -> None:
    """Refuse, before any work, outputs that cannot be written or would destroy something.

    Parameters
    ----------
    outputs : iterable of Output
        Every file and folder the command will write.
    inputs : Inputs, or iterable of Input or (str, path)
        Everything the command reads, with how to name it ("the rule file").

    Raises
    ------
    adapt.errors.OutputError
        If an output is an input or another output, a folder output holds an
        input, an output lies inside an input folder, an extension does not
        fit, a file output is a folder or a special file, or its folder cannot
        be written.  Nothing has been written then.
    """
    sources = inputs if isinstance(inputs, Inputs) else Inputs(inputs)
    seen: list[Output] = []
    for out in outputs:
        for earlier in seen:
            if same_file(out.path, earlier.path):
                raise OutputError(f"{out.option} {_quoted(out.path)} is the same file as "
                                  f"{earlier.option} {_quoted(earlier.path)}; expected a "
                                  "different file for each output")
        hit = sources.within(out.path) if out.folder else sources.find(out.path)
        if hit is not None:
            mine, theirs = _identity(out.path)[0], _identity(hit.path)[0]
            if same_file(hit.path, out.path):
                relation = f"is {hit.what}"
            elif out.folder and _inside(theirs, mine):
                relation = f"would hold {hit.what} ({_quoted(hit.path)})"
            else:
                relation = f"is inside {hit.what} ({_quoted(hit.path)})"
            raise OutputError(f"{out.option} {_quoted(out.path)} {relation}; an output never "
                              f"replaces an input: {out.remedy}")
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
        (out.path if out.folder else out.path.parent).mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OutputError(f"{out.option} {_quoted(out.path)}: cannot create "
                          f"{'it' if out.folder else 'its folder'} "
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


def _permit(path: str | os.PathLike[str]) -> None:
    """Give a temporary file the permissions a plain ``open`` would have."""
    mask = os.umask(0)
    os.umask(mask)
    os.chmod(path, 0o666 & ~mask)


def temporary_file(path: str | os.PathLike[str], suffix: str = ".tmp") -> Path:
    """Create an empty temporary file beside ``path``, named ``.adapt-tmp-NAME.XXXX{suffix}``
    (:data:`TEMP_PREFIX`), with the permissions a plain ``open`` would give it; return it.

    ``suffix`` keeps the extension a writer may need (``.mp4`` for a video).
    An :class:`OSError` names ``path``, never the temporary file.

    >>> import tempfile, pathlib
    >>> tmp = temporary_file(pathlib.Path(tempfile.mkdtemp()) / "report.json")
    >>> tmp.name.startswith(".adapt-tmp-report.json."), tmp.suffix, tmp.stat().st_size
    (True, '.tmp', 0)
    """
    target = Path(path)
    try:
        fd, tmp = tempfile.mkstemp(dir=target.parent, prefix=f"{TEMP_PREFIX}{target.name}.",
                                   suffix=suffix)
    except OSError as exc:
        raise _about(exc, None, target) from None
    os.close(fd)
    _permit(tmp)
    return Path(tmp)


def _about(exc: OSError, tmp: str | None, target: Path) -> OSError:
    """``exc`` told about ``target`` instead of the temporary file ``tmp``."""
    names: Sequence[object] = (exc.filename, exc.filename2)
    if tmp is None or tmp in names or exc.filename is None:
        return OSError(exc.errno, exc.strerror or str(exc), str(target))
    return exc


@contextmanager
def atomic_path(path: str | os.PathLike[str], suffix: str = ".tmp") -> Iterator[str]:
    """A temporary path beside ``path`` to write to (:func:`temporary_file`); renamed over
    ``path`` when the block ends normally, removed when it raises.

    ``suffix`` keeps the extension a writer may need (``.mp4`` for a video).
    An :class:`OSError` about the temporary file is raised as one about
    ``path``, so messages never show the temporary name.
    """
    target = Path(path)
    tmp = str(temporary_file(target, suffix))
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


def remove_stale(folder: str | os.PathLike[str]) -> list[Path]:
    """Remove the temporary files (:data:`TEMP_PREFIX`) directly in ``folder``; return them.

    Only for a folder whose lock this process holds (:func:`lock_folder`): then no
    other command is writing there, and every temporary file is one a killed command
    left.  Subfolders are not searched.
    """
    removed: list[Path] = []
    try:
        entries = list(os.scandir(folder))
    except OSError:
        return removed
    for entry in entries:
        if entry.name.startswith(TEMP_PREFIX) and entry.is_file(follow_symlinks=False):
            try:
                os.unlink(entry.path)
                removed.append(Path(entry.path))
            except OSError:
                pass
    return removed


class FolderLock:
    """An exclusive lock on an output folder (see :func:`lock_folder`); a context manager.

    Attributes
    ----------
    folder : Path
    removed : list of Path
        Temporary files a killed command had left, removed on locking.
    """

    def __init__(self, folder: Path, handle: IO[str] | None, removed: list[Path]) -> None:
        self.folder = folder
        self.removed = removed
        self._handle = handle

    @property
    def held(self) -> bool:
        """Whether the lock is still held."""
        return self._handle is not None

    def release(self) -> None:
        """Release the lock (the lock file stays, empty)."""
        if self._handle is not None:
            self._handle.close()
            self._handle = None

    def __enter__(self) -> "FolderLock":
        return self

    def __exit__(self, *exc: object) -> None:
        self.release()


def lock_folder(folder: str | os.PathLike[str], option: str = "--out",
                subfolders: Iterable[str] = ()) -> FolderLock:
    """Make ``folder`` (and its missing parents), lock it for this command alone, and remove
    the temporary files a killed command left in it and in its ``subfolders``.

    The lock is ``folder/.adapt.lock``, held with ``flock`` for as long as the
    command runs (the operating system releases it when the process ends, even
    when it is killed).  ``adapt run`` and ``adapt sweep`` take it, so two of
    them never write into one folder at once.

    Raises
    ------
    adapt.errors.OutputError
        If another command holds the lock, or the folder cannot be made.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> with lock_folder(d / "run"):
    ...     lock_folder(d / "run")
    Traceback (most recent call last):
    ...
    adapt.errors.OutputError: another adapt command (a run or a sweep) is writing into '...run' (it holds .adapt.lock); wait for it to end, or choose another --out folder
    """
    top = Path(folder)
    try:
        top.mkdir(parents=True, exist_ok=True)
        handle = open(top / LOCK_NAME, "a", encoding="utf-8")  # noqa: SIM115 (closed by release)
    except OSError as exc:
        raise OutputError(f"{option} {_quoted(top)}: cannot create or lock it "
                          f"({exc.strerror or exc})") from None
    try:
        import fcntl
    except ImportError:  # pragma: no cover - not POSIX: no lock
        fcntl = None  # type: ignore[assignment]
    if fcntl is not None:
        try:
            fcntl.flock(handle.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            handle.close()
            raise OutputError(f"another adapt command (a run or a sweep) is writing into "
                              f"{_quoted(top)} (it holds {LOCK_NAME}); wait for it to end, or "
                              f"choose another {option} folder") from None
    removed = remove_stale(top)
    for name in subfolders:
        removed += remove_stale(top / name)
    return FolderLock(top, handle, removed)


def is_special(path: str | os.PathLike[str]) -> bool:
    """Whether ``path`` exists and is neither a regular file nor a folder (a device, a pipe,
    a socket): reading it may never end.

    >>> is_special("/dev/zero"), is_special(__file__)
    (True, False)
    """
    try:
        mode = os.stat(path).st_mode
    except (OSError, ValueError):
        return False
    return not (stat.S_ISREG(mode) or stat.S_ISDIR(mode))
